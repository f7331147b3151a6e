// A grasp controller step for a Cortex-M4F microcontroller: float only, no heap, no
// exceptions, no RTTI, no I/O. Built (not linked) by cmake/check_embedded.sh, which checks
// with arm-none-eabi-nm that no malloc/free/new/delete/__cxa_throw is referenced and reports
// the .text size and the stack use of every function (-fstack-usage).
//
// One call per control period: five finger contacts (position, inward normal, friction,
// squeeze) and the external wrench come in; the optimal contact forces (solve_range_space,
// the O(n) solver) and each contact's friction-cone mode (StabilityMonitor) go out.
#include "grasp_io.hpp"

#include <grip/solve/solve_range_space.hpp>

using EmbeddedGrasp = grip::Grasp<kGripFingers, grip::HardFinger, float>;

extern "C" int grip_grasp_step(const GripContactIn* contacts, const float* w_ext, GripStepOut* out) {
  EmbeddedGrasp grasp;
  if (load_grasp(grasp, contacts) != grip::Status::Ok) return static_cast<int>(grip::Status::InvalidInput);
  const grip::Wrench<float> w = load_wrench(w_ext);
  const grip::Solution<EmbeddedGrasp> sol = grip::solve_range_space(grasp, w);
  monitor_and_store(grasp, sol.forces, sol.residual, out);
  return static_cast<int>(sol.status);
}
