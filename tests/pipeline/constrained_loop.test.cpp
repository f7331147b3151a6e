// The haptic loop with the friction-constrained solver, warm-started frame to frame.
#include <doctest/doctest.h>

#include <grip/pipeline/frame_solver.hpp>

#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"

using namespace grip;

TEST_CASE_TEMPLATE("constrained loop: weight balanced inside the cones, few iterations per frame", S, double, float) {
  grip_test::HeldCylinder<S> h;
  HapticPipeline<S, CylinderScene<S>, ConstrainedFrameSolver<S>> p(h.settings, h.scene, h.object);
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  const int cold = f.iterations;
  // Statics as in the range-space loop: the hand feels +m g in all; no contact slides.
  const S tol = std::is_same<S, float>::value ? S(5e-3) : S(1e-6);
  CHECK((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), S(-0.4 * 9.81))).norm() <= tol);
  CHECK(f.sliding == 0);
  // A slowly accelerating hand: each frame starts from the previous multipliers.
  WristState<S> w = h.wrist;
  int warm_total = 0, frames = 0;
  {
    grip_test::NoHeapScope scope;
    for (int i = 1; i <= 20; ++i) {
      w.linear_acceleration.z() = S(0.05) * S(i);
      REQUIRE(p.step(w, h.closed, f) == Status::Ok);
      REQUIRE(f.held);
      warm_total += f.iterations;
      ++frames;
      const S a = S(0.05) * S(i);
      CHECK(std::abs(-grip_test::total_feedback(f).z() - S(0.4) * (a + S(9.81))) <= tol);
    }
    CHECK(scope.allocations() == 0);
  }
  // This grasp is well inside its cones: a cold solve takes solve_constrained's fast path (one
  // iteration); warm-started solves skip the fast path (as documented there) and take a
  // couple of Newton iterations. Either way the bound per frame is small.
  CHECK(cold <= 2);
  CHECK(warm_total <= 3 * frames);
}
