// The same controller step with the friction cones imposed (solve_constrained, warm-started
// from the previous period's multipliers) instead of monitored. Built by
// cmake/check_embedded.sh like grasp_step.cpp.
#include "grasp_io.hpp"

#include <grip/solve/solve_constrained.hpp>

using EmbeddedGrasp = grip::Grasp<kGripFingers, grip::HardFinger, float>;

// The solver's settings, constant (in flash, not on the stack): the defaults, whose bounds
// (ConstrainedSettings::max_iterations, newton_passes) bound every solve, a slipping grasp's
// too; bench/m4_cycles.py estimates the cycles per pass and per iteration. Warm-started from
// the previous period's multipliers, a grasp that holds usually takes a few Newton passes.
constexpr grip::ConstrainedSettings<float> kSettings{};

extern "C" int grip_constrained_step(const GripContactIn* contacts, const float* w_ext, float* multipliers,
                                     GripStepOut* out) {
  EmbeddedGrasp grasp;
  if (load_grasp(grasp, contacts) != grip::Status::Ok) return static_cast<int>(grip::Status::InvalidInput);
  const grip::Wrench<float> w = load_wrench(w_ext);
  const grip::Wrench<float> warm = load_wrench(multipliers);
  const grip::ConstrainedSolution<EmbeddedGrasp> sol = grip::solve_constrained(grasp, w, kSettings, warm);
  monitor_and_store(grasp, sol.forces, sol.residual, out);
  for (int k = 0; k < 6; ++k) multipliers[k] = sol.multipliers(k);
  return static_cast<int>(sol.status);
}
