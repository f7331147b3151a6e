// Collision detection: analytic cases (sphere, box, cylinder) at known depths, accuracy per
// octree depth, no contact when apart, pruned == exhaustive, bad input, no heap per frame.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include <grip/collision/collision.hpp>

#include "support/allocation_counter.hpp"
#include "support/hand_postures.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

template class grip::HandCollisionModel<double, 8>;
template class grip::HandCollisionModel<float, 4>;
template struct grip::HandContacts<double>;
template struct grip::HandContacts<float>;

namespace {
template <class S>
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
constexpr int octree_capacity = 32768;
template <class S>
SphericalOctree<S, octree_capacity>& octree() {
  static SphericalOctree<S, octree_capacity> t;
  return t;
}
template <class S>
HandPosture<S> single(int k, const Vector3<S>& a, const Vector3<S>& b, S r) {
  return grip_test::single_phalanx<S>(k, a, b, r);
}
// The documented accuracy of an octree leaf model (spherical_octree.hpp): e = 3 h^2 (R + s) / (2 R^2).
template <class S>
double curved_tolerance(const SphericalOctree<S, octree_capacity>& oct, int depth, double R, double s) {
  const double h = double(oct.cell_half_edge(depth));
  return 3 * h * h * (R + std::max(s, 0.0)) / (2 * R * R);
}
// The round-off of one contact's depth or point (support/tolerance.hpp), on M (m), the largest
// coordinate the phalanx, the pose's shift and the leaves are made of: the leaf's centre,
// radius and plane are built in S (4 roundings of M), the sample's coordinates and the pose's
// inverse take 6, the plane distance 4, r minus it 1: k = 16, condition 1 (a distance is
// 1-Lipschitz). Where the test itself moves points through a rotated pose, 8 more (k = 24).
template <class S>
double round_off(double k, double M) {
  return grip_test::roundoff<S>(k, 1, M);
}
// A unit normal: the leaf's normal from its plane (4 roundings of 1) and the pose's rotation
// (3 more), k = 8, scale 1.
template <class S>
double normal_round_off() {
  return grip_test::roundoff<S>(8, 1, 1);
}
}  // namespace

TEST_CASE_TEMPLATE("a sphere pressed into a sphere: depth, normal, point within the depth's tolerance", S, double,
                   float) {
  // Object: sphere R = 40 mm at the origin. Phalanx: a capsule of zero length (a sphere) of
  // radius r = 10 mm centred at x with |x| = 48 mm: depth = R + r - |x| = 2 mm, inward normal
  // -x/|x|, contact point R x/|x| on the object's surface.
  auto& oct = octree<S>();
  const double R = 0.04, r = 0.01, dist = 0.048;
  std::mt19937 rng(3);
  grip_test::Normal g(0, 1);
  double prev_worst = 1;
  for (int depth = 2; depth <= 5; ++depth) {
    REQUIRE(oct.build(Shape<S>(make_sphere<S>(S(R))), depth) == Status::Ok);
    // Not round-off: the leaf model's documented accuracy e(depth) (spherical_octree.hpp); then
    // round-off on M = |x| = 48 mm.
    const double ro = round_off<S>(16, dist);
    const double tol = curved_tolerance(oct, depth, R, dist - R) + ro;
    const double h = double(oct.cell_half_edge(depth));
    double worst = 0;
    for (int t = 0; t < 20; ++t) {
      const Vector3<double> u = grip_test::draw3(rng, g).normalized();
      const Vector3<S> x = (dist * u).cast<S>();
      HandCollisionModel<S> hand;
      REQUIRE(hand.set_posture(single<S>(5, x, x, S(r))) == Status::Ok);
      HandContacts<S> out;
      REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::Ok);
      REQUIRE(out.count == 1);
      CHECK(out[0].finger == Finger::Long);
      CHECK(out[0].phalanx == Phalanx::Proximal);
      const double err = double(out[0].depth) - (R + r - dist);
      worst = std::max(worst, std::abs(err));
      CHECK(err >= -ro);  // each leaf is a lower bound of the distance: depth from above
      CHECK(err <= tol);
      // The normal: a leaf's plane is within sqrt(3) h / R of the true normal (the leaf's
      // half-diagonal seen from the centre; geometry, not round-off); acos near 1 turns the
      // dot product's rounding (4 roundings of 1 and the normal's 8) into an angle sqrt(2 d).
      const double acos_ro = std::sqrt(2 * (grip_test::roundoff<S>(4, 1, 1) + normal_round_off<S>()));
      CHECK(std::acos(std::min(1.0, -out[0].normal.template cast<double>().dot(u))) <=
            std::sqrt(3.0) * h / R + acos_ro);
      // The point: that angle over the distance dist - R, and the depth's tolerance. Not
      // round-off: 1e-4 (m) is this check's own allowance, documented nowhere, left as it was.
      CHECK((out[0].point.template cast<double>() - R * u).norm() <= std::sqrt(3.0) * h * (dist - R) / R + tol + 1e-4);
    }
    CHECK(worst <= prev_worst + 2 * ro);  // converges with depth (each worst within ro of its own)
    prev_worst = worst;
  }
  CHECK(prev_worst <= 1e-4);  // depth 5 (leaf edge 2.5 mm): below 0.1 mm (a stated accuracy, not round-off)
}

TEST_CASE_TEMPLATE("a box face: exact depth (planar), and the leaf over-reach the correction removes", S, double,
                   float) {
  // Box half sizes (50, 40, 30) mm, turned and moved by the object pose. A phalanx lies flat
  // 8 mm radius, its axis z0 = 30 + 8 - 1.5 mm above the top face: depth 1.5 mm, normal -z
  // (into the box, object frame), point on the face below the axis midpoint.
  auto& oct = octree<S>();
  REQUIRE(oct.build(Shape<S>(make_box<S>(Vector3<S>(S(0.05), S(0.04), S(0.03)))), 4) == Status::Ok);
  Iso<S> pose = Iso<S>::Identity();
  pose.linear() = Eigen::AngleAxis<S>(S(0.8), Vector3<S>(S(1), S(2), S(3)).normalized()).toRotationMatrix();
  pose.translation() = Vector3<S>(S(0.2), S(-0.1), S(0.3));
  const S r = S(0.008), z0 = S(0.03) + r - S(0.0015);
  const Vector3<S> a(S(-0.02), S(0.005), z0), b(S(0.015), S(-0.01), z0);
  HandCollisionModel<S> hand;
  REQUIRE(hand.set_posture(single<S>(13, pose * a, pose * b, r)) == Status::Ok);
  HandContacts<S> out;
  REQUIRE(detect_contacts(hand, oct, pose, out) == Status::Ok);
  REQUIRE(out.count == 1);
  CHECK(out[0].finger == Finger::Little);
  CHECK(out[0].phalanx == Phalanx::Distal);
  // Planar: exact but for round-off, on M = |pose translation| + |a| = 0.42 m, the test's own
  // pose * a and pose.inverse() included (k = 24).
  const double M = double(pose.translation().norm() + a.norm());
  CHECK(std::abs(double(out[0].depth) - 0.0015) <= round_off<S>(24, M));
  CHECK(double((out[0].normal - pose.linear() * Vector3<S>(S(0), S(0), S(-1))).norm()) <= normal_round_off<S>());
  const Vector3<S> mid((a.x() + b.x()) / S(2), (a.y() + b.y()) / S(2), S(0.03));
  CHECK(double((pose.inverse() * out[0].point - mid).norm()) <= round_off<S>(24, M));
  CHECK(out[0].samples == HandCollisionModel<S>::samples_per_phalanx);

  // The uncorrected estimate, depth against the leaf spheres themselves, over-reaches by at
  // least (sqrt(3) - 1) / 2 of the leaf edge (hand derivation in spherical_octree.hpp).
  double naive = -1;
  const Vector3<S> x = (a + b) / S(2);
  for (int i = 0; i < oct.tree().size(); ++i)
    if (oct.is_solid_leaf(i))
      naive = std::max(naive, double(r + oct.tree().node(i).radius - (x - oct.tree().node(i).center).norm()));
  // 0.366 is (sqrt(3) - 1) / 2 rounded down; naive's r + radius - |x - c| takes 8 roundings
  // of |x| + |c| <= 0.13 m (support/tolerance.hpp), and 0.0015 its own round-off as above.
  CHECK(naive - 0.0015 >= 0.366 * 2 * double(oct.cell_half_edge(4)) - round_off<S>(8, 0.13) - round_off<S>(24, M));

  // 0.1 mm apart: no contact (planar faces are exact).
  const Vector3<S> lift(S(0), S(0), S(0.0016));
  REQUIRE(hand.set_posture(single<S>(13, pose * Vector3<S>(a + lift), pose * Vector3<S>(b + lift), r)) == Status::Ok);
  REQUIRE(detect_contacts(hand, oct, pose, out) == Status::Ok);
  CHECK(out.count == 0);
}

TEST_CASE_TEMPLATE("a cylinder: side (curved) and cap (planar) at known depths, apart gives nothing", S, double,
                   float) {
  // Cylinder R = 35 mm, half height 70 mm, axis z. A phalanx of radius 8 mm parallel to the
  // axis at radial distance R + r - 2 mm along direction (cos 0.3, sin 0.3): depth 2 mm, normal
  // -radial, point on the side at the axis midpoint's height.
  auto& oct = octree<S>();
  const double R = 0.035, r = 0.008;
  REQUIRE(oct.build(Shape<S>(make_cylinder<S>(S(R), S(0.07))), 5) == Status::Ok);
  const Vector3<double> radial(std::cos(0.3), std::sin(0.3), 0);
  const Vector3<double> a = (R + r - 0.002) * radial + Vector3<double>(0, 0, -0.01);
  const Vector3<double> b = (R + r - 0.002) * radial + Vector3<double>(0, 0, 0.03);
  HandCollisionModel<S> hand;
  REQUIRE(hand.set_posture(single<S>(0, a.cast<S>(), b.cast<S>(), S(r))) == Status::Ok);
  HandContacts<S> out;
  REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::Ok);
  REQUIRE(out.count == 1);
  CHECK(out[0].finger == Finger::Thumb);
  // Not round-off: e(5) of spherical_octree.hpp; then round-off on M = |b| = 0.05 m.
  const double ro = round_off<S>(16, b.norm());
  const double tol = curved_tolerance(oct, 5, R, r - 0.002) + ro;
  CHECK(double(out[0].depth) >= 0.002 - ro);
  CHECK(double(out[0].depth) <= 0.002 + tol);
  // Not round-off: the normal and point of a leaf's plane on the curved side; 0.05 and 2e-3 (m)
  // are these checks' own allowances, documented nowhere, left as they were.
  CHECK((out[0].normal.template cast<double>() + radial).norm() <= 0.05);
  CHECK((out[0].point.template cast<double>() - (R * radial + Vector3<double>(0, 0, 0.01))).norm() <= 2e-3);

  // A fingertip pushed 3 mm into the top cap along -z: planar, exact; normal -z.
  const Vector3<S> tip(S(0.01), S(-0.005), S(0.07 + r - 0.003));
  REQUIRE(hand.set_posture(single<S>(4, Vector3<S>(tip + Vector3<S>(S(0.005), S(0), S(0.02))), tip, S(r))) ==
          Status::Ok);
  REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::Ok);
  REQUIRE(out.count == 1);
  CHECK(out[0].finger == Finger::Index);
  CHECK(out[0].phalanx == Phalanx::Distal);
  // Planar: round-off on M = |tip| + 0.02 (the base) = 0.11 m.
  CHECK(std::abs(double(out[0].depth) - 0.003) <= round_off<S>(16, double(tip.norm()) + 0.02));
  CHECK(double((out[0].normal + Vector3<S>::UnitZ()).norm()) <= normal_round_off<S>());

  // 1 mm off the side (more than the depth-5 tolerance): no contact.
  REQUIRE(tol < 0.001);
  const Vector3<double> a2 = (R + r + 0.001) * radial, b2 = a2 + Vector3<double>(0, 0, 0.03);
  REQUIRE(hand.set_posture(single<S>(0, a2.cast<S>(), b2.cast<S>(), S(r))) == Status::Ok);
  REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::Ok);
  CHECK(out.count == 0);
}

TEST_CASE_TEMPLATE("pruned descent finds the same contacts as the exhaustive leaf-pair loop", S, double, float) {
  auto& oct = octree<S>();
  Shape<S, 2> shape;
  shape.add(make_box<S>(Vector3<S>(S(0.04), S(0.03), S(0.02))));
  shape.add(make_sphere<S>(S(0.03), Vector3<S>(S(0.03), S(0), S(0.02))));
  REQUIRE(oct.build(shape, 4) == Status::Ok);
  const HandDimensions<S> dims = HandDimensions<S>::standard();
  std::mt19937 rng(5);
  grip_test::Uniform u(-1, 1);
  int total = 0;
  for (int t = 0; t < 8; ++t) {
    JointAngles<S> q;
    for (int k = 0; k < 14; ++k) q(k) = S(0.6 + 0.6 * u(rng));
    Iso<S> wrist = Iso<S>::Identity();
    const Vector3<double> r = grip_test::draw3(rng, u);
    wrist.translation() = Vector3<S>(S(-0.09 + 0.03 * r.x()), S(0.02 * r.y()), S(0.05 + 0.02 * r.z()));
    HandPosture<S> h;
    REQUIRE(forward_kinematics(dims, wrist, q, h) == Status::Ok);
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(h) == Status::Ok);
    HandContacts<S> fast, slow;
    REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), fast) == Status::Ok);
    REQUIRE(detect_contacts_exhaustive(hand, oct, Iso<S>::Identity(), slow) == Status::Ok);
    REQUIRE(fast.count == slow.count);
    total += fast.count;
    for (int i = 0; i < fast.count; ++i) {
      CHECK(fast[i].finger == slow[i].finger);
      CHECK(fast[i].phalanx == slow[i].phalanx);
      // The same leaves and samples by two descents: at most twice one contact's round-off,
      // on M = the hand's reach from the object's origin, 0.25 m.
      CHECK(double(std::abs(fast[i].depth - slow[i].depth)) <= 2 * round_off<S>(16, 0.25));
      CHECK(double((fast[i].normal - slow[i].normal).norm()) <= 2 * normal_round_off<S>());
    }
  }
  CHECK(total > 5);  // the poses do touch
}

TEST_CASE_TEMPLATE("bad input, and no heap per frame", S, double, float) {
  auto& oct = octree<S>();
  REQUIRE(oct.build(Shape<S>(make_cylinder<S>(S(0.035), S(0.07))), 5) == Status::Ok);
  HandCollisionModel<S> hand;
  HandContacts<S> out;
  out.count = 3;
  CHECK(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::InvalidInput);  // never posed
  CHECK(out.count == 0);
  const HandDimensions<S> dims = HandDimensions<S>::standard();
  HandPosture<S> h;
  JointAngles<S> q = JointAngles<S>::Constant(S(0.5));
  Iso<S> wrist = Iso<S>::Identity();
  wrist.translation() = Vector3<S>(S(-0.08), S(0), S(0.05));
  {
    grip_test::NoHeapScope scope;  // one whole frame: kinematics, hierarchy, detection
    REQUIRE(forward_kinematics(dims, wrist, q, h) == Status::Ok);
    REQUIRE(hand.set_posture(h) == Status::Ok);
    REQUIRE(detect_contacts(hand, oct, Iso<S>::Identity(), out) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  CHECK(out.count > 0);
  Iso<S> skewed = Iso<S>::Identity();
  skewed.linear()(0, 1) = S(0.5);
  CHECK(detect_contacts(hand, oct, skewed, out) == Status::InvalidInput);
  Iso<S> nan = Iso<S>::Identity();
  nan.translation()(2) = std::numeric_limits<S>::quiet_NaN();
  CHECK(detect_contacts(hand, oct, nan, out) == Status::InvalidInput);
  static SphericalOctree<S, 8> empty;
  CHECK(detect_contacts(hand, empty, Iso<S>::Identity(), out) == Status::InvalidInput);
  h.phalanges[3].radius = S(0);
  CHECK(hand.set_posture(h) == Status::InvalidInput);
  h.phalanges[3].radius = S(0.01);
  h.phalanges[3].tip(1) = std::numeric_limits<S>::infinity();
  CHECK(hand.set_posture(h) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("in_solid_leaf: a point is in a solid leaf's cube exactly when a loop over the leaves says so", S,
                   double, float) {
  // The narrow phase asks it of sample centres that no surface lies near: against every
  // solid leaf's cube, for points anywhere about a cylinder and on the cells' own corners
  // (where up to 8 cubes meet and the first child holding the point may be empty).
  auto& oct = octree<S>();
  REQUIRE(oct.build(Shape<S>(make_cylinder<S>(S(0.035), S(0.07))), 3) == Status::Ok);
  std::mt19937 rng(59);
  const grip_test::Uniform across(-0.06, 0.06), along(-0.1, 0.1);
  int inside = 0, trials = 0;
  auto check = [&](const Vector3<S>& p) {
    bool expect = false;
    for (int o = 0; o < oct.tree().size() && !expect; ++o)
      expect = oct.is_solid_leaf(o) &&
               (p - oct.tree().node(o).center).cwiseAbs().maxCoeff() <= oct.cell_half_edge(oct.tree().node(o).level);
    CHECK(detail::in_solid_leaf(oct, p) == expect);
    inside += expect ? 1 : 0;
    ++trials;
  };
  for (int t = 0; t < 2000; ++t) check(Vector3<S>(S(across(rng)), S(across(rng)), S(along(rng))));
  for (int o = 0; o < oct.tree().size(); ++o) {  // the corners of every cell
    const SphereNode<S>& nd = oct.tree().node(o);
    const S hc = oct.cell_half_edge(nd.level);
    for (int c = 0; c < 8; ++c)
      check(nd.center + hc * Vector3<S>(c & 1 ? S(1) : S(-1), c & 2 ? S(1) : S(-1), c & 4 ? S(1) : S(-1)));
  }
  CHECK(inside > trials / 10);
  CHECK(inside < trials);
}
