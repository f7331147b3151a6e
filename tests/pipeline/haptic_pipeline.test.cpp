// The closed haptic loop: what the hand feels while holding, accelerating, hitting, releasing.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/pipeline/frame_solver.hpp>

#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/tolerance.hpp"

using namespace grip;

template class grip::HapticPipeline<double, CylinderScene<double>>;
template class grip::HapticPipeline<float, CylinderScene<float>, KktFrameSolver>;
template struct grip::CylinderScene<float, 2>;

namespace {
// The tolerance of a frame's forces, from round-off (support/tolerance.hpp): k = 1 unit of
// u * grasp_condition * force scale, the first-order error of a backward-stable solve with its
// constant taken as 1; observed at most 0.03 of it in both scalar types and both scenes (float:
// about 1.4e-4 N on the held cylinder's 0.4 kg, where a fixed 2e-3 N stood before). A moment's
// tolerance is the force tolerance times the object's reach (the largest |r_i|).
template <class S, class P>
double force_tol(const P& p, const grip::HapticFrame<S>& f) {
  return grip_test::frame_force_tolerance(p, f, 1);
}

// What a frame solver's answer may differ from the optimum by, per unit of grasp_condition and
// of the force scale, beyond round-off: nothing for the direct solves; for the constrained
// one its own acceptance max(settings.tolerance, 16 eps) (|w_ext| + |x|) (solve_constrained.hpp,
// as in solve_constrained.test.cpp), ConstrainedSettings' contract per type, not round-off.
inline double solver_stop(const grip::RangeSpaceFrameSolver&) { return 0; }
inline double solver_stop(const grip::KktFrameSolver&) { return 0; }
template <class S>
double solver_stop(const grip::ConstrainedFrameSolver<S>& s) {
  return std::max(double(s.settings.tolerance), 16 * double(std::numeric_limits<S>::epsilon()));
}
}  // namespace

TEST_CASE_TEMPLATE("a held object at rest feels its weight, moments balanced", S, double, float) {
  grip_test::HeldCylinder<S> h;
  REQUIRE(h.touching >= 10);
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  CHECK(f.sliding == 0);
  // Statics (eq. 1-2): sum f_i + m g = 0 and sum r_i x f_i = 0 (gravity acts at the centre
  // of mass). The hand feels -f_i, so its forces add up to +m g = (0, 0, -0.4 * 9.81) N.
  const Vector3<S> expected(S(0), S(0), S(-0.4 * 9.81));
  CHECK(double((grip_test::total_feedback(f) - expected).norm()) <= force_tol(p, f));
  CHECK(double(grip_test::finger_moment(f, p).norm()) <= force_tol(p, f) * grip_test::contact_reach(p));
  // The accessors: held, the settings given, the last grasp (its contacts are among the frame's),
  // the posture forward kinematics gives for the wrist and joint angles.
  CHECK(p.held());
  CHECK(p.settings().device_limit == h.settings.device_limit);
  CHECK(p.settings().hand.thumb_cmc == h.settings.hand.thumb_cmc);
  CHECK(p.grasp().size() >= 1);
  CHECK(p.grasp().size() <= f.contacts);
  HandPosture<S> expect_posture;
  REQUIRE(forward_kinematics(h.settings.hand, h.wrist.pose, h.closed, expect_posture) == Status::Ok);
  // The same forward kinematics of the same inputs: at most two evaluations' 24 roundings of
  // the hand length plus |t| apart (the count of hand_kinematics.test.cpp; support/tolerance.hpp).
  const double fk =
      grip_test::roundoff<S>(48, 1, double(h.settings.hand.hand_length + h.wrist.pose.translation().norm()));
  for (std::size_t k = 0; k < expect_posture.phalanges.size(); ++k) {
    CHECK(double((p.posture().phalanges[k].base - expect_posture.phalanges[k].base).norm()) <= fk);
    CHECK(double((p.posture().phalanges[k].tip - expect_posture.phalanges[k].tip).norm()) <= fk);
    CHECK(p.posture().phalanges[k].radius == expect_posture.phalanges[k].radius);
  }
  // The object stays where it is.
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  // Held, it follows wrist.pose * offset with offset = wrist.pose^-1 * object: the round trip
  // takes about 12 roundings of |x| + |t| (support/tolerance.hpp).
  CHECK(double((p.object().position - h.object.position).norm()) <=
        grip_test::roundoff<S>(12, 1, double(h.object.position.norm() + h.wrist.pose.translation().norm())));
}

namespace {
// The held cylinder at rest with frame solver `Solver`: statics, and each phalanx against
// an independent solve of the same contacts (with no contact outside its cone, the
// constrained optimum is the unconstrained one).
template <class S, class Solver>
void check_per_phalanx(const char* name) {
  INFO("frame solver: ", name);
  grip_test::HeldCylinder<S> h;
  auto p = h.template pipeline_with<Solver>();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  REQUIRE(f.sliding == 0);
  REQUIRE(f.separating == 0);
  REQUIRE(f.contacts >= 10);
  // Two solves of the same contacts, each within force_tol (k = 1 each), and for the
  // constrained solver its acceptance times grasp_condition (solver_stop above).
  double scale = double(f.external.total().template head<3>().norm());
  for (const auto& ph : f.phalanges) scale += double(ph.force.norm());
  const double tol = 2 * force_tol(p, f) + grip_test::grasp_condition(p.grasp()) * solver_stop(p.solver()) * scale;
  const auto feel = grip_test::independent_feedback<S>(p, h.settings);
  int felt = 0;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    CAPTURE(k);
    CHECK(double((f.phalanges[sk].force - feel[sk]).norm()) <= tol);
    felt += f.phalanges[sk].in_contact ? 1 : 0;
  }
  CHECK(felt == f.contacts);
}
}  // namespace

TEST_CASE_TEMPLATE("each phalanx feels what an independent solve gives, with every frame solver", S, double, float) {
  check_per_phalanx<S, RangeSpaceFrameSolver>("range space");
  check_per_phalanx<S, KktFrameSolver>("KKT");
  check_per_phalanx<S, ConstrainedFrameSolver<S>>("constrained");
}

TEST_CASE_TEMPLATE("during a vertical acceleration a the fingers push m (a - g)", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  for (const double a : {4.0, -3.0, 9.0}) {
    WristState<S> w = h.wrist;
    w.linear_acceleration << S(0), S(0), S(a);
    REQUIRE(p.step(w, h.closed, f) == Status::Ok);
    REQUIRE(f.held);
    // Newton: sum f_i + m g = m a_vec  =>  sum f_i = m (a_vec - g_vec), g_vec = (0, 0, -9.81);
    // the hand feels the opposite: -m (a + 9.81) along z.
    const Vector3<S> fingers = -grip_test::total_feedback(f);
    CHECK(double(std::abs(fingers.z() - S(0.4 * (a + 9.81)))) <= force_tol(p, f));
    CHECK(double(std::abs(fingers.x())) <= force_tol(p, f));
    CHECK(double(std::abs(fingers.y())) <= force_tol(p, f));
  }
}

TEST_CASE_TEMPLATE("an impact raises the forces on the phalanges that resist it", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> before, during;
  REQUIRE(p.step(h.wrist, h.closed, before) == Status::Ok);
  REQUIRE(before.held);
  // A wall on the thumb's side (-x) pushing the cylinder by 2 mm: its face at x = x_c - r + 2 mm.
  // The rim points facing -x (two of them, one per end) penetrate by 2 mm: 2 * k * d = 2 *
  // 2e4 * 0.002 = 80 N? no: the default material k = 2e4 N/m per point, so 40 N each, 80 N in
  // all along +x. The fingers on the far side (+x: the distal phalanges, pushing -x) must resist.
  auto& sc = p.scene();
  REQUIRE(sc.obstacles.add_box(Vector3<S>(S(-1), S(-1), S(-1)),
                               Vector3<S>(h.object.position.x() - S(0.035) + S(0.002), S(1), S(1))) == Status::Ok);
  REQUIRE(p.step(h.wrist, h.closed, during) == Status::Ok);
  REQUIRE(during.obstacles == 2);
  const Vector3<S> push = during.external.obstacles.template head<3>();
  // Round-off (support/tolerance.hpp): each depth is the wall's x minus a rim point's, both
  // from coordinates of size M = |x_c| + the rim's reach 0.08 m (the wall's sum and the
  // literals 3 roundings, the object pose applied to the rim point 6, the difference 1: k = 10),
  // times 2 points of 2e4 N/m; and the force's own 2 roundings. The condition M / depth is in
  // the absolute depth error: k u M is 2e4 times larger in newtons.
  const double wall_M = std::abs(double(h.object.position.x())) + 0.08;
  CHECK(std::abs(double(push.x()) - 80) <=
        2 * 2e4 * grip_test::roundoff<S>(10, 1, wall_M) + grip_test::roundoff<S>(2, 1, 80));
  // 80 N is more than the grasp holds inside its cones: the object is free this frame, and
  // what is left unbalanced is w_ext plus the forces the fingers transmit (documented on
  // HapticFrame): the hand feels minus those. It pushes the object away from the wall (+x).
  REQUIRE_FALSE(during.held);
  REQUIRE(during.clamped == 0);
  const Vector3<S> left = during.external.total().template head<3>() - grip_test::total_feedback(during);
  CHECK(double((during.unbalanced.template head<3>() - left).norm()) <= force_tol(p, during));
  CHECK(during.unbalanced.x() > S(1));
  // Each distal phalanx of the four fingers (on the +x side) feels more along its actuation
  // direction; the thumb, on the wall's side, feels less.
  for (const Finger fi : {Finger::Index, Finger::Long, Finger::Ring, Finger::Little}) {
    const auto k = static_cast<std::size_t>(phalanx_index(fi, Phalanx::Distal));
    CHECK(during.phalanges[k].actuated > before.phalanges[k].actuated + S(1));
  }
  const auto thumb = static_cast<std::size_t>(phalanx_index(Finger::Thumb, Phalanx::Distal));
  CHECK(during.phalanges[thumb].force.norm() < before.phalanges[thumb].force.norm());
}

TEST_CASE_TEMPLATE("a light push is held: the fingers cancel it", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  // The wall of the case above 0.1 mm deep: two rim points, 2e4 N/m each, 2 * 2 N = 4 N along +x.
  auto& sc = p.scene();
  REQUIRE(sc.obstacles.add_box(Vector3<S>(S(-1), S(-1), S(-1)),
                               Vector3<S>(h.object.position.x() - S(0.035) + S(0.0001), S(1), S(1))) == Status::Ok);
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.obstacles == 2);
  const Vector3<S> push = f.external.obstacles.template head<3>();
  // Round-off as in the case above.
  const double wall_M = std::abs(double(h.object.position.x())) + 0.08;
  CHECK(std::abs(double(push.x()) - 4) <=
        2 * 2e4 * grip_test::roundoff<S>(10, 1, wall_M) + grip_test::roundoff<S>(2, 1, 4));
  REQUIRE(f.held);
  // Equilibrium: the fingers' forces (minus what the hand feels) cancel weight and push.
  const Vector3<S> fingers = -grip_test::total_feedback(f);
  CHECK(double((fingers + push + Vector3<S>(S(0), S(0), S(-0.4 * 9.81))).norm()) <= force_tol(p, f));
}

TEST_CASE_TEMPLATE("releasing the grasp makes the object fall with g", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  // Let go: the hand opens in place (the object is no longer held), then moves 0.5 m aside,
  // out of the way of the falling object.
  const JointAngles<S> open = JointAngles<S>::Zero();
  REQUIRE(p.step(h.wrist, open, f) == Status::Ok);
  REQUIRE_FALSE(f.held);
  WristState<S> aside = h.wrist;
  aside.pose.translation().y() += S(0.5);
  REQUIRE(p.step(aside, open, f) == Status::Ok);
  REQUIRE(f.contacts == 0);
  // From the first frame without contact: free fall, x(t) = x_a + v_a t + g t^2 / 2 and
  // v(t) = v_a + g t, exact for the integrator under a constant force (g = (0, 0, -9.81)).
  const Vector3<S> xa = p.object().position, va = p.object().linear_velocity;
  const int n = 150;
  for (int i = 0; i < n; ++i) {
    REQUIRE(p.step(aside, open, f) == Status::Ok);
    CHECK(f.contacts == 0);
    CHECK_FALSE(f.held);
  }
  const S t = S(0.15);
  const Vector3<S> g(S(0), S(0), S(-9.81));
  // Round-off (support/tolerance.hpp), as in integrator.test.cpp's free fall, over the n steps
  // of 1 ms, with V = |v_a| + g t and X = |x_a| + V t bounding |v| and |x|: the velocity 2
  // roundings of V per step, g's and dt's 4 and the reference's 2; the position 1 of X + dt V
  // per step, the reference's 6, and the velocity's error carried over t.
  const double V = double(va.norm()) + 9.81 * 0.15, X = double(xa.norm()) + V * 0.15;
  const double tol_v = grip_test::roundoff<S>(2 * n + 6, 1, V);
  const double tol_x = grip_test::roundoff<S>(n + 6, 1, X + 1e-3 * V) + 0.15 * tol_v;
  CHECK(double((p.object().position - (xa + va * t + S(0.5) * g * t * t)).norm()) <= tol_x);
  CHECK(double((p.object().linear_velocity - (va + g * t)).norm()) <= tol_v);
  CHECK(p.object().position.z() < xa.z() - S(0.1));  // it fell at least g t^2 / 2 = 0.11 m
}

TEST_CASE_TEMPLATE("a grasp the monitor finds slipping lets the object slip", S, double, float) {
  grip_test::HeldCylinder<S> h;
  h.settings.friction = S(0.02);  // almost frictionless skin: the weight cannot be held
  auto p = h.pipeline();
  HapticFrame<S> f;
  const Vector3<S> x0 = h.object.position;
  int sliding_frames = 0;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  CHECK_FALSE(f.held);
  CHECK(f.sliding > 0);
  // What is left unbalanced is part of the weight: it points down (the fingers under the
  // cylinder still carry most of it through their normal forces).
  const Wrench<S> first = f.unbalanced;
  CHECK(first.z() < S(0));
  CHECK(double(first.z()) >= -0.4 * 9.81 - force_tol(p, f));  // round-off of the unbalanced wrench
  for (int i = 0; i < 100; ++i) {
    REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
    sliding_frames += f.held ? 0 : 1;
  }
  CHECK(sliding_frames > 50);
  // The unbalanced wrench moves the object: it slides down out of the hand.
  CHECK(p.object().position.z() < x0.z() - S(1e-4));  // 0.1 mm: a distance it must slide, not a tolerance
}

TEST_CASE_TEMPLATE("feedback is clamped to the device's limit, which is the default device's", S, double, float) {
  grip_test::HeldCylinder<S> h;
  h.settings.device_limit.fill(S(2));
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  int clamped = 0;
  for (const auto& ph : f.phalanges) {
    CHECK(ph.command >= S(0));
    CHECK(ph.command <= S(2));
    if (ph.in_contact && ph.actuated > S(2)) {
      CHECK(ph.clamped);
      CHECK(ph.command == S(2));
    }
    clamped += ph.clamped ? 1 : 0;
    // The actuation direction is unit and perpendicular to... the flexion axis (world y here).
    // normalized(): the norm's and the division's roundings, k = 4 of 1 (support/tolerance.hpp).
    if (ph.in_contact) CHECK(double(std::abs(ph.actuation_direction.norm() - S(1))) <= grip_test::roundoff<S>(4, 1, 1));
  }
  CHECK(clamped == f.clamped);
  CHECK(clamped >= 1);  // the thumb's ~24 N at least
  // One source: the default device's limits are the feedback's.
  const int k = phalanx_index(Finger::Thumb, Phalanx::Distal);
  REQUIRE(f.phalanges[detail::idx(k)].actuated > S(3));  // pushed beyond both limits below
  CHECK(f.phalanges[detail::idx(k)].command == S(2));
  // Raised on the device only: the next frame's feedback follows it, and equals the device's.
  p.device().limit[detail::idx(k)] = S(3);
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  CHECK(f.phalanges[detail::idx(k)].command == S(3));
  for (int j = 0; j < hand_phalanx_count; ++j)
    CHECK(f.phalanges[detail::idx(j)].command == p.device_command().force[detail::idx(j)]);
  CHECK(f.clamped == p.device_command().clipped);
  // Another device: the feedback keeps the settings' limits (the paper's actuator view).
  auto v = h.template pipeline_with_device<VectorForces<S>>();
  REQUIRE(v.step(h.wrist, h.closed, f) == Status::Ok);
  CHECK(f.phalanges[detail::idx(k)].command == S(2));
}

TEST_CASE_TEMPLATE("bad input: InvalidInput, object unchanged", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  WristState<S> w = h.wrist;
  w.linear_acceleration.x() = std::numeric_limits<S>::quiet_NaN();
  CHECK(p.step(w, h.closed, f) == Status::InvalidInput);
  CHECK(f.status == Status::InvalidInput);
  JointAngles<S> q = h.closed;
  q(3) = std::numeric_limits<S>::infinity();
  CHECK(p.step(h.wrist, q, f) == Status::InvalidInput);
  w = h.wrist;
  w.pose.linear() *= S(2);  // not a rotation
  CHECK(p.step(w, h.closed, f) == Status::InvalidInput);
  CHECK(p.object().position == h.object.position);
  RigidBody<S> bad = h.object;
  bad.mass = S(0);
  CHECK(p.set_object(bad) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("a whole frame does not touch the heap", S, double, float) {
  grip_test::HeldCylinder<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  WristState<S> w = h.wrist;
  int ok = 0, held = 0;
  grip_test::NoHeapScope scope;
  for (int i = 0; i < 20; ++i) {
    w.linear_acceleration.z() = S(i % 5);
    ok += p.step(w, i < 10 ? h.closed : JointAngles<S>(JointAngles<S>::Zero()), f) == Status::Ok ? 1 : 0;
    held += f.held ? 1 : 0;
  }
  CHECK(scope.allocations() == 0);
  // (checked outside the loop: a failing CHECK may allocate) every frame ran, and both the
  // held path (closed hand) and the free one (open hand) were taken.
  CHECK(ok == 20);
  CHECK(held == 10);
}

TEST_CASE_TEMPLATE("the command guard passes the device's commands through at its neutral settings", S, double, float) {
  grip_test::HeldCylinder<S> h;
  h.settings.guard_commands = true;
  h.settings.guard.update_rate = S(1) / h.settings.dt;  // every frame an update; no slew, ramp or steps
  auto p = h.pipeline();
  HapticFrame<S> f;
  WristState<S> w = h.wrist;
  int touching = 0;
  for (int i = 0; i < 40; ++i) {
    w.linear_acceleration.z() = S(i % 7);
    REQUIRE(p.step(w, h.closed, f) == Status::Ok);
    for (int k = 0; k < hand_phalanx_count; ++k) {
      CHECK(f.phalanges[detail::idx(k)].command == p.device_command().force[detail::idx(k)]);
      touching += f.phalanges[detail::idx(k)].command > S(0) ? 1 : 0;
    }
  }
  CHECK(touching > 0);  // the check compared commands that push
}

TEST_CASE_TEMPLATE("the command guard: slew-limited, to zero without a jump on bad or stale input", S, double, float) {
  grip_test::HeldCylinder<S> h;
  h.settings.guard_commands = true;
  h.settings.guard.update_rate = S(1) / h.settings.dt;
  h.settings.guard.slew_rate = S(1000);    // N/s: 1 N per 1 ms frame
  h.settings.guard.stale_after = S(0.01);  // s: 10 frames
  const S per_frame = h.settings.guard.slew_rate * h.settings.dt;
  const S slack = S(64) * std::numeric_limits<S>::epsilon() * S(100);  // the time's round-off
  auto p = h.pipeline();
  HapticFrame<S> f;
  WristState<S> bad = h.wrist;
  bad.linear_velocity.x() = std::numeric_limits<S>::quiet_NaN();
  std::array<S, hand_phalanx_count> last{};
  S peak(0);
  // 0-199: good input, fresh; 200-299: bad input; 300-399: good; 400-499: good but stale.
  for (int i = 0; i < 500; ++i) {
    const bool is_bad = i >= 200 && i < 300;
    const Status st = p.step(is_bad ? bad : h.wrist, h.closed, f, i < 400);
    CHECK(st == (is_bad ? Status::InvalidInput : Status::Ok));
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const auto j = detail::idx(k);
      const S c = f.phalanges[j].command;
      CHECK(std::abs(c - last[j]) <= per_frame + slack);  // no jump, whatever the input
      last[j] = c;
      peak = std::max(peak, c);
    }
    S most(0);
    for (const S c : last) most = std::max(most, c);
    // From the bad input's first frame the commands fall by the slew per frame, so they reach
    // zero within 100 frames of commands below 80 N (checked when the input turns bad); likewise
    // once the input is stale (after 10 frames).
    if (i == 299 || i == 499) CHECK(most == S(0));
    if (i == 199 || i == 399) CHECK(most < S(80) * per_frame);  // what the 100 frames allow
  }
  CHECK(peak > S(1));  // the guard had something to hold back
  CHECK(p.guard().stale());
}
