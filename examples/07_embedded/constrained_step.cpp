// The same controller step with the friction cones imposed (solve_constrained, warm-started
// from the previous period's multipliers) instead of monitored. Built by
// cmake/check_embedded.sh like grasp_step.cpp.
#include "grasp_io.hpp"

#include <grip/monitor/stability_monitor.hpp>
#include <grip/solve/solve_constrained.hpp>

using EmbeddedGrasp = grip::Grasp<kGripFingers, grip::HardFinger, float>;

extern "C" int grip_constrained_step(const GripContactIn* contacts, const float* w_ext, float* multipliers,
                                     GripStepOut* out) {
  EmbeddedGrasp grasp;
  if (load_grasp(grasp, contacts) != grip::Status::Ok) return static_cast<int>(grip::Status::InvalidInput);
  const grip::Wrench<float> w = load_wrench(w_ext);
  const grip::Wrench<float> warm = load_wrench(multipliers);
  const grip::ConstrainedSolution<EmbeddedGrasp> sol =
      grip::solve_constrained(grasp, w, grip::ConstrainedSettings<float>{}, warm);
  const grip::GraspState<EmbeddedGrasp> state = grip::monitor_grasp(grasp, sol.forces);
  store(sol.forces, sol.residual, state, out);
  for (int k = 0; k < 6; ++k) multipliers[k] = sol.multipliers(k);
  return static_cast<int>(sol.status);
}
