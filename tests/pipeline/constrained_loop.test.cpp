// The haptic loop with the friction-constrained solver, warm-started frame to frame.
#include <doctest/doctest.h>

#include <limits>

#include <grip/pipeline/frame_solver.hpp>

#include "../../examples/06_haptic_loop/session.hpp"
#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {
// The total feedback is minus the force part of the solve's residual. Not round-off: the
// constrained solver accepts |G x + w_ext| <= max(settings.tolerance, 16 eps) (|w_ext| + |x|)
// (solve_constrained.hpp; ConstrainedSettings' contract per type). Then round-off
// (support/tolerance.hpp): the feedback's sum over the n contacts, n + 4 roundings of the
// scale |w_ext| + sum |x_i|, as in the frame's own force scale.
template <class S, class P>
double equilibrium_tol(const P& p, const HapticFrame<S>& f) {
  double scale = double(f.external.total().norm());
  for (const auto& ph : f.phalanges) scale += double(ph.force.norm());
  const double stop = std::max(double(p.solver().settings.tolerance), 16 * double(std::numeric_limits<S>::epsilon()));
  return stop * scale + grip_test::roundoff<S>(f.contacts + 4, 1, scale);
}
}  // namespace

TEST_CASE_TEMPLATE("constrained loop: weight balanced inside the cones, few iterations per frame", S, double, float) {
  grip_test::HeldCylinder<S> h;
  HapticPipeline<S, CylinderScene<S>, ConstrainedFrameSolver<S>> p(h.settings, h.scene, h.object);
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  const int cold = f.iterations;
  // Statics as in the range-space loop: the hand feels +m g in all; no contact slides.
  CHECK(double((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), S(-0.4 * 9.81))).norm()) <= equilibrium_tol(p, f));
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
      CHECK(double(std::abs(-grip_test::total_feedback(f).z() - S(0.4) * (a + S(9.81)))) <= equilibrium_tol(p, f));
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
  CHECK(free_run.solver().settings.max_passes == ConstrainedFrameSolver<S>::default_max_passes);
  free_run.solver().settings.max_passes = std::numeric_limits<int>::max();
  bounded.solver().settings.max_passes = 1;
  REQUIRE(bounded.solver().settings.max_passes == 1);
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

TEST_CASE("constrained loop: the default deadline bounds every solve of a slipping grasp") {
  // The first 0.32 s of example 06's scripted session: the hand closes on the bottle standing
  // on the table, and the grasp slips while it closes (solves without a deadline need about a
  // hundred passes there). The default pipeline spends at most default_max_passes passes per
  // solve; run beside it, the same loop without a deadline needs several times more on some
  // frame (121 to 160 passes, by instruction set).
  using S = haptic_session::S;
  const haptic_session::Script script;
  using Pipeline = HapticPipeline<S, CylinderScene<S>, ConstrainedFrameSolver<S>>;
  Pipeline exact(haptic_session::settings(), haptic_session::scene(), haptic_session::object());
  Pipeline bounded(haptic_session::settings(), haptic_session::scene(), haptic_session::object());
  exact.solver().settings.max_passes = std::numeric_limits<int>::max();
  const int limit = ConstrainedFrameSolver<S>::default_max_passes;
  REQUIRE(bounded.solver().settings.max_passes == limit);
  HapticFrame<S> f, g;
  int exact_most = 0, bounded_most = 0, cut = 0;
  for (int i = 0; i < 320; ++i) {
    const S t = S(i) / haptic_session::rate;
    REQUIRE(exact.step(script.wrist(t), script.angles(t), f) == Status::Ok);
    REQUIRE(bounded.step(script.wrist(t), script.angles(t), g) == Status::Ok);
    exact_most = std::max(exact_most, exact.solver().passes);
    bounded_most = std::max(bounded_most, bounded.solver().passes);
    CHECK(bounded.solver().passes <= limit);
    if (g.solve_status == Status::IterationLimit) ++cut;
    for (const auto& ph : g.phalanges) CHECK(ph.force.allFinite());
  }
  CHECK(exact_most > 4 * limit);
  CHECK(bounded_most == limit);
  CHECK(cut >= 1);
}

// ConstrainedFrameSolver keeping the residual |G x + w_ext| of its last solve.
struct ResidualKeepingSolver : ConstrainedFrameSolver<haptic_session::S> {
  double residual{0};
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<haptic_session::S>& w_ext) {
    const Solution<GraspT> sol = ConstrainedFrameSolver<haptic_session::S>::operator()(grasp, w_ext);
    residual = double(sol.residual);
    return sol;
  }
};

TEST_CASE("constrained loop: separating contacts are dropped without a second solve") {
  // The same 0.32 s (the bottle closing on the table: contacts at their apex in every frame).
  // A cone-enforcing solver answers a separating contact with zero force and the rest are the
  // answer without it (tests/solve: "a contact at its apex can be dropped"), so the pipeline
  // solves once per frame; the range-space solver beside it needs the re-solves. On frames that
  // solve Ok with separating contacts, what the fingers transmit balances w_ext as the solve
  // did: the force part of the feedback's residual is within the solve's own residual, plus
  // the rounding of the feedback's sum (n + 4 roundings of its scale, as equilibrium_tol).
  using S = haptic_session::S;
  const haptic_session::Script script;
  HapticPipeline<S, CylinderScene<S>, ResidualKeepingSolver> p(haptic_session::settings(), haptic_session::scene(),
                                                                haptic_session::object());
  HapticPipeline<S, CylinderScene<S>, RangeSpaceFrameSolver> range(haptic_session::settings(), haptic_session::scene(),
                                                                    haptic_session::object());
  p.solver().settings.max_passes = std::numeric_limits<int>::max();  // more frames solve Ok
  HapticFrame<S> f, g;
  int balanced = 0, range_resolves = 0;
  for (int i = 0; i < 320; ++i) {
    const S t = S(i) / haptic_session::rate;
    REQUIRE(p.step(script.wrist(t), script.angles(t), f) == Status::Ok);
    REQUIRE(range.step(script.wrist(t), script.angles(t), g) == Status::Ok);
    if (g.solves > 1) ++range_resolves;
    if (f.contacts == 0) continue;
    CHECK(f.solves == 1);
    if (f.held) CHECK((f.solve_status == Status::Ok && f.sliding == 0));
    if (f.solve_status == Status::Ok && f.separating > 0) {
      const Vector3<S> load = f.external.total().template head<3>();
      double scale = double(load.norm());
      for (const auto& ph : f.phalanges) scale += double(ph.force.norm());
      CHECK(double((grip_test::total_feedback(f) - load).norm()) <=
            p.solver().residual + grip_test::roundoff<S>(f.contacts + 4, 1, scale));
      ++balanced;
    }
  }
  CHECK(balanced >= 10);
  CHECK(range_resolves >= 10);
}
