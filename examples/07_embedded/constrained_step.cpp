// The same controller step with the friction cones imposed (solve_constrained, warm-started
// from the previous period's multipliers) instead of monitored. Built by
// cmake/check_embedded.sh like grasp_step.cpp.
#include "grasp_io.hpp"

#include <grip/solve/solve_constrained.hpp>

using EmbeddedGrasp = grip::Grasp<kGripFingers, grip::HardFinger, float>;

// The solver's settings, constant (in flash, not on the stack), with a deadline: at most 8
// passes over the contacts, so that a slipping grasp answers IterationLimit (forces inside their
// cones) within a bounded time: about 8 600 + 8 x 12 000 cycles for five fingers by
// bench/m4_cycles.py's estimate (0.6 ms at 168 MHz). Warm-started from the previous period's
// multipliers, a feasible grasp usually needs fewer.
constexpr grip::ConstrainedSettings<float> step_settings() {
  grip::ConstrainedSettings<float> s{};
  s.max_passes = 8;
  return s;
}
constexpr grip::ConstrainedSettings<float> kSettings = step_settings();

extern "C" int grip_constrained_step(const GripContactIn* contacts, const float* w_ext, float* multipliers,
                                     GripStepOut* out) {
  EmbeddedGrasp grasp;
  if (load_grasp(grasp, contacts) != grip::Status::Ok) return static_cast<int>(grip::Status::InvalidInput);
  const grip::Wrench<float> w = load_wrench(w_ext);
  const grip::Wrench<float> warm = load_wrench(multipliers);
  const grip::ConstrainedSolution<EmbeddedGrasp> sol =
      grip::solve_constrained(grasp, w, kSettings, warm);
  monitor_and_store(grasp, sol.forces, sol.residual, out);
  for (int k = 0; k < 6; ++k) multipliers[k] = sol.multipliers(k);
  return static_cast<int>(sol.status);
}
