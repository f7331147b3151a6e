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

TEST_CASE_TEMPLATE("constrained loop: a deadline set through solver() reaches every solve", S, double, float) {
  // The held cylinder with mu = 0.2, then a hand that accelerates and turns more each frame:
  // the first solve that the fast path cannot answer needs a Newton step (a second pass after
  // the start), which a deadline of one pass forbids.
  grip_test::HeldCylinder<S> h;
  h.settings.friction = S(0.2);
  HapticPipeline<S, CylinderScene<S>, ConstrainedFrameSolver<S>> free_run(h.settings, h.scene, h.object);
  HapticPipeline<S, CylinderScene<S>, ConstrainedFrameSolver<S>> bounded(h.settings, h.scene, h.object);
  bounded.solver().settings.max_passes = 1;
  REQUIRE(bounded.solver().settings.max_passes == 1);
  CHECK(free_run.solver().settings.max_passes == ConstrainedSettings<S>{}.max_passes);
  HapticFrame<S> f, g;
  // Cold: the fast path, which spends no pass, so both hold the cylinder.
  REQUIRE(free_run.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(bounded.step(h.wrist, h.closed, g) == Status::Ok);
  REQUIRE(f.held);
  CHECK(g.held);
  // A growing acceleration along the cylinder's axis (world y), which only friction resists,
  // and about the hand's x axis: while the fast path answers, both loops are the same; the
  // first frame whose free solve needs a Newton step (at least two passes) is cut short.
  WristState<S> w = h.wrist;
  bool stepped = false;
  for (int i = 1; i <= 40 && !stepped; ++i) {
    w.linear_acceleration.y() = S(2) * S(i);
    w.angular_acceleration.x() = S(20) * S(i);
    REQUIRE(free_run.step(w, h.closed, f) == Status::Ok);
    REQUIRE(bounded.step(w, h.closed, g) == Status::Ok);
    if (f.iterations == 0) {
      CHECK(g.iterations == 0);
      CHECK(g.held == f.held);
      continue;
    }
    stepped = true;
    REQUIRE(f.solve_status == Status::Ok);
    CHECK(g.solve_status == Status::IterationLimit);
    CHECK(!g.held);  // an answer cut short is not a stable grasp: the pipeline lets go
  }
  REQUIRE(stepped);
}
