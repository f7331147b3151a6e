// The closed haptic loop: what the hand feels while holding, accelerating, hitting, releasing.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/pipeline/frame_solver.hpp>

#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"

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
  for (std::size_t k = 0; k < expect_posture.phalanges.size(); ++k) {
    CHECK((p.posture().phalanges[k].base - expect_posture.phalanges[k].base).norm() <= S(1e-6));
    CHECK((p.posture().phalanges[k].tip - expect_posture.phalanges[k].tip).norm() <= S(1e-6));
    CHECK(p.posture().phalanges[k].radius == expect_posture.phalanges[k].radius);
  }
  // The object stays where it is.
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  CHECK((p.object().position - h.object.position).norm() <= S(1e-6));
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
  const S tol = std::is_same<S, float>::value ? S(5e-3) : S(1e-6);  // the constrained solver's tolerance
  const auto feel = grip_test::independent_feedback<S>(p, h.settings);
  int felt = 0;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    CAPTURE(k);
    CHECK((f.phalanges[sk].force - feel[sk]).norm() <= tol);
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
  CHECK(push.x() == doctest::Approx(80).epsilon(0.01));
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
  CHECK(push.x() == doctest::Approx(4).epsilon(0.01));
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
  const S tol = std::is_same<S, float>::value ? S(1e-4) : S(1e-9);
  CHECK((p.object().position - (xa + va * t + S(0.5) * g * t * t)).norm() <= tol);
  CHECK((p.object().linear_velocity - (va + g * t)).norm() <= tol);
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
  CHECK(first.z() >= S(-0.4 * 9.81) - S(1e-3));
  for (int i = 0; i < 100; ++i) {
    REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
    sliding_frames += f.held ? 0 : 1;
  }
  CHECK(sliding_frames > 50);
  // The unbalanced wrench moves the object: it slides down out of the hand.
  CHECK(p.object().position.z() < x0.z() - S(1e-4));
}

TEST_CASE_TEMPLATE("feedback is clamped to the device's limit and reported", S, double, float) {
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
    if (ph.in_contact) CHECK(std::abs(ph.actuation_direction.norm() - S(1)) <= S(1e-4));
  }
  CHECK(clamped == f.clamped);
  CHECK(clamped >= 1);  // the thumb's ~24 N at least
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
