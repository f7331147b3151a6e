// The exact narrow phase of collision.hpp against independent exact geometry
// (support/exact_geometry.hpp): random phalanx poses aimed at the faces, edges, rims, corners
// and interiors of a sphere, a box, a cylinder, a capsule and a union, each contact's depth,
// point and normal within the bound stated in collision.hpp; no contact where the capsule is
// apart by more than the bound, none missed where it penetrates by more.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <type_traits>

#include <Eigen/Geometry>

#include <grip/collision/collision.hpp>
#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>
#include <grip/geometry/shape.hpp>

#include "geometry/mesh_test_support.hpp"

#include "support/allocation_counter.hpp"
#include "support/constants.hpp"
#include "support/exact_geometry.hpp"
#include "support/hand_postures.hpp"
#include "support/test_scale.hpp"

namespace collision_bounds_test {

using namespace grip;
using grip_test::uniform;
using grip_test::V3;

namespace {

template <class S>
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
constexpr int cap = 32768;
template <class S>
SphericalOctree<S, cap>& octree() {
  static SphericalOctree<S, cap> t;
  return t;
}

template <class S>
HandPosture<S> single(int k, const Vector3<S>& a, const Vector3<S>& b, S r) {
  return grip_test::single_phalanx<S>(k, a, b, r);
}

// The bound of collision.hpp for a convex field: the refinement's certified tolerance
// (ContactSettings::refine_tolerance, 0.1 um), plus rounding: 64 ulps of the largest
// coordinate (0.5 m here) for the transforms, norms and square roots on the way.
template <class S>
double bound(double) {
  return double(ContactSettings<S>{}.refine_tolerance) + 64 * double(std::numeric_limits<S>::epsilon()) * 0.5;
}

struct Tally {
  int contacts = 0, apart = 0, deep = 0, near = 0;
  int reached = 0;  // contacts within 1 um of the capsule's true depth (dense sampling)
};

// Checks the contacts of one phalanx [a, b] (object frame) of radius r against the exact
// field `exact` (object frame). convex: the capsule's exact deepest point is promised; else
// the any-field bounds. `off_surface(p)`: how far p is from a surface the contact point may
// lie on (the object's; for a union, any primitive's: collision.hpp).
template <class S, class Field, class Exact, class OffSurface>
double check_phalanx(const Field& field, const Exact& exact, const OffSurface& off_surface, const Iso<S>& pose,
                     const V3& a, const V3& b, double r, bool convex, Tally& tally, int grid = 2000) {
  const Iso<double> pose_d = pose.template cast<double>();
  HandCollisionModel<S> hand;
  REQUIRE(hand.set_posture(single<S>(5, (pose_d * a).cast<S>(), (pose_d * b).cast<S>(), S(r))) == Status::Ok);
  HandContacts<S> out;
  REQUIRE(detect_contacts(hand, octree<S>(), field, pose, out) == Status::Ok);
  const double spacing = (b - a).norm() / 7;
  const double tol = bound<S>(spacing);
  double t_star = 0;
  const double gap = grip_test::segment_minimum(exact, a, b, &t_star, grid);
  const double depth_true = r - gap;
  double deepest_sample = -1;
  for (int j = 0; j < 8; ++j) deepest_sample = std::max(deepest_sample, r - exact(a + (j / 7.0) * (b - a)));
  if (depth_true < -tol) {
    CHECK(out.count == 0);
    ++tally.apart;
    return gap;
  }
  const double lower = convex ? depth_true - tol : std::max(deepest_sample, depth_true - spacing / 2) - tol;
  if (lower <= 0) {
    ++tally.near;
    if (out.count == 0) return gap;
  }
  REQUIRE(out.count == 1);
  ++tally.contacts;
  if (gap < -r) ++tally.deep;
  const HandContact<S>& c = out[0];
  CHECK(c.finger == Finger::Long);
  CHECK(c.phalanx == Phalanx::Proximal);
  const double depth = double(c.depth);
  CHECK(depth <= depth_true + tol);  // a true penetration of the capsule
  CHECK(depth >= lower);
  if (depth >= depth_true - 1e-6) ++tally.reached;
  // The contact's axis point x, its distance r - depth, and the surface point nearest it.
  const V3 x = a + double(c.axis_parameter) * (b - a);
  const double phi = exact(x);
  CHECK(std::abs((r - depth) - phi) <= tol);
  const V3 point = pose_d.inverse() * c.point.template cast<double>();
  const V3 normal = pose_d.linear().transpose() * c.normal.template cast<double>();
  CHECK(off_surface(point) <= tol);
  CHECK(std::abs((point - x).norm() - std::abs(phi)) <= tol);
  CHECK(std::abs(normal.norm() - 1) <= tol);
  if (std::abs(phi) > 1e-3) {  // the normal points from the axis point to the surface point (outside)
    const V3 expected = (phi > 0 ? point - x : x - point) / std::abs(phi);
    CHECK((normal - expected).norm() <= tol / 1e-3);
  }
  return gap;
}

// A phalanx pose aimed at surface point f (outward normal nf): its axis passes r + g from f
// along nf, in a random direction, a random part of its length on either side; g mostly
// within a few millimetres of touching, sometimes deep, sometimes within 0.5 mm.
void aim(std::mt19937& rng, const V3& f, const V3& nf, double r, V3& a, V3& b) {
  const double kind = grip_test::u01(rng);
  const double g = kind < 0.7    ? uniform(rng, -0.005, 0.003)
                   : kind < 0.85 ? uniform(rng, -0.025, -0.005)
                                 : uniform(rng, -0.0005, 0.0005);
  const V3 x0 = f + (r + g) * nf;
  const V3 u = grip_test::unit_vector(rng);
  const double L = uniform(rng, 0.012, 0.045), lambda = grip_test::u01(rng);
  a = x0 - lambda * L * u;
  b = a + L * u;
}

template <class S>
Iso<S> random_pose(std::mt19937& rng);

// The distance from the surface of a solid given by its exact signed distance.
template <class Exact>
auto surface_of(const Exact& exact) {
  return [&exact](const V3& p) { return std::abs(exact(p)); };
}

// A phalanx of random radius aimed at surface point f (outward normal nf), checked against
// `exact` with the object at a random pose.
template <class S, class Field, class Exact>
void aim_and_check(const Field& field, const Exact& exact, std::mt19937& rng, const V3& f, const V3& nf, Tally& tally) {
  V3 a, b;
  const double r = uniform(rng, 0.006, 0.01);
  aim(rng, f, nf, r, a, b);
  check_phalanx<S>(field, exact, surface_of(exact), random_pose<S>(rng), a, b, r, true, tally);
}

// The coverage a case needs: enough contacts, poses apart, and deep axes; the bounds are for
// `full` trials (see grip_test::scaled_bound when GRIP_TEST_SCALE runs fewer).
void check_tally(const Tally& t, int contacts, int apart, int deep, int trials, int full) {
  CHECK(t.contacts > grip_test::scaled_bound(contacts, trials, full));
  CHECK(t.apart > grip_test::scaled_bound(apart, trials, full));
  CHECK(t.deep > grip_test::scaled_bound(deep, trials, full));
}

template <class S>
Iso<S> random_pose(std::mt19937& rng) {
  Iso<S> pose = Iso<S>::Identity();
  pose.linear() = grip_test::rotation(rng).cast<S>();
  const double x = uniform(rng, -0.2, 0.2), y = uniform(rng, -0.2, 0.2), z = uniform(rng, -0.2, 0.2);
  pose.translation() = Vector3<S>(S(x), S(y), S(z));
  return pose;
}

double sign(std::mt19937& rng) { return grip_test::u01(rng) < 0.5 ? -1.0 : 1.0; }

}  // namespace

TEST_CASE_TEMPLATE("box: faces, edges, corners and deep axes, the capsule's exact deepest point", S, double, float) {
  const V3 h(0.05, 0.04, 0.03), c(0.01, -0.02, 0.005);
  std::mt19937 rng(11);
  const Eigen::Matrix3d R = grip_test::rotation(rng);
  const grip_test::ExactBox exact{c, h, R};
  const Shape<S> shape(make_box<S>(h.cast<S>(), c.cast<S>(), R.cast<S>()));
  REQUIRE(octree<S>().build(shape, 4) == Status::Ok);
  Tally tally;
  int edges = 0, corners = 0;
  const int trials = grip_test::scaled(240, 30);
  for (int trial = 0; trial < trials; ++trial) {
    V3 q, n;  // local feature point and outward normal
    const int kind = trial % 3;
    if (kind == 0) {  // a face
      const int w = int(grip_test::u01(rng) * 3) % 3;
      for (int i = 0; i < 3; ++i) q(i) = uniform(rng, -h(i), h(i));
      n = V3::Zero();
      n(w) = sign(rng);
      q(w) = n(w) * h(w);
    } else if (kind == 1) {  // an edge: normals between its two faces
      const int w = int(grip_test::u01(rng) * 3) % 3, u = (w + 1) % 3, v = (w + 2) % 3;
      const double su = sign(rng), sv = sign(rng), th = uniform(rng, 0, 1.5707963);
      q(w) = uniform(rng, -h(w), h(w));
      q(u) = su * h(u);
      q(v) = sv * h(v);
      n = V3::Zero();
      n(u) = su * std::cos(th);
      n(v) = sv * std::sin(th);
      ++edges;
    } else {  // a corner: normals in its cone
      for (int i = 0; i < 3; ++i) {
        const double s = sign(rng);
        q(i) = s * h(i);
        n(i) = s * uniform(rng, 0.05, 1);
      }
      n.normalize();
      ++corners;
    }
    aim_and_check<S>(shape, exact, rng, c + R * q, R * n, tally);
  }
  check_tally(tally, 120, 20, 5, trials, 240);
  CHECK(edges == (trials + 1) / 3);  // trial % 3 == 1
  CHECK(corners == trials / 3);      // trial % 3 == 2
}

TEST_CASE_TEMPLATE("cylinder: side, caps and rims, and the rim case a user hit gets no contact", S, double, float) {
  const double radius = 0.035, half = 0.07;
  std::mt19937 rng(12);
  const Eigen::Matrix3d R = grip_test::rotation(rng);
  const V3 c(0.002, 0.001, -0.003);
  const grip_test::ExactCylinder exact{c, R, radius, half};
  const Shape<S> shape(make_cylinder<S>(S(radius), S(half), c.cast<S>(), R.cast<S>()));
  REQUIRE(octree<S>().build(shape, 5) == Status::Ok);
  Tally tally;
  const int trials = grip_test::scaled(240, 30);
  for (int trial = 0; trial < trials; ++trial) {
    const double phi = uniform(rng, 0, 2 * grip_test::pi), s = sign(rng);
    const V3 radial(std::cos(phi), std::sin(phi), 0);
    V3 q, n;
    if (trial % 3 == 0) {  // the side
      q = radius * radial + V3(0, 0, uniform(rng, -half, half));
      n = radial;
    } else if (trial % 3 == 1) {  // a cap
      q = uniform(rng, 0, radius) * radial + V3(0, 0, s * half);
      n = V3(0, 0, s);
    } else {  // a rim: normals between the side's and the cap's
      const double th = uniform(rng, 0, 1.5707963);
      q = radius * radial + V3(0, 0, s * half);
      n = std::cos(th) * radial + V3(0, 0, s * std::sin(th));
    }
    aim_and_check<S>(shape, exact, rng, c + R * q, R * n, tally);
  }
  check_tally(tally, 120, 20, 5, trials, 240);

  // The minimal case: a phalanx (r = 8 mm) 0.5 to 1 mm above the cap, lying across the rim.
  // The paper mode reported a contact 8.77 mm deep with a horizontal normal; there is none.
  const Shape<S> upright(make_cylinder<S>(S(radius), S(half)));
  REQUIRE(octree<S>().build(upright, 5) == Status::Ok);
  for (double lift = 0.0005; lift <= 0.001; lift += 0.0001) {
    const V3 a(radius - 0.02, 0.003, half + 0.008 + lift), b(radius + 0.02, 0.003, half + 0.008 + lift);
    const grip_test::ExactCylinder up{V3::Zero(), Eigen::Matrix3d::Identity(), radius, half};
    check_phalanx<S>(upright, up, surface_of(up), Iso<S>::Identity(), a, b, 0.008, true, tally);
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(single<S>(5, a.cast<S>(), b.cast<S>(), S(0.008))) == Status::Ok);
    HandContacts<S> out;
    REQUIRE(detect_contacts(hand, octree<S>(), upright, Iso<S>::Identity(), out) == Status::Ok);
    CHECK(out.count == 0);
  }
}

TEST_CASE_TEMPLATE("sphere and capsule: curved surfaces and deep axes, exact", S, double, float) {
  std::mt19937 rng(13);
  Tally tally;
  const V3 c(0.004, -0.002, 0.001);
  const grip_test::ExactSphere ball{c, 0.04};
  const Shape<S> sphere(make_sphere<S>(S(0.04), c.cast<S>()));
  REQUIRE(octree<S>().build(sphere, 5) == Status::Ok);
  const int trials = grip_test::scaled(120, 15);
  for (int trial = 0; trial < trials; ++trial) {
    const V3 u = grip_test::unit_vector(rng);
    aim_and_check<S>(sphere, ball, rng, c + 0.04 * u, u, tally);
  }
  const Eigen::Matrix3d R = grip_test::rotation(rng);
  const grip_test::ExactCapsule pill{c, R, 0.02, 0.03};
  const Shape<S> capsule(make_capsule<S>(S(0.02), S(0.03), c.cast<S>(), R.cast<S>()));
  REQUIRE(octree<S>().build(capsule, 5) == Status::Ok);
  for (int trial = 0; trial < trials; ++trial) {
    const V3 u = grip_test::unit_vector(rng);
    const V3 axis_point = c + R * V3(0, 0, uniform(rng, -0.04, 0.04));
    const V3 q = c + R * V3(0, 0, std::clamp((R.transpose() * (axis_point - c)).z(), -0.03, 0.03));
    aim_and_check<S>(capsule, pill, rng, q + 0.02 * u, u, tally);
  }
  check_tally(tally, 100, 10, 5, trials, 120);
}

TEST_CASE_TEMPLATE("a union (not convex): true penetrations, at least the deepest sample's", S, double, float) {
  // A box with a ball on one corner: grooves where the two meet. The union's field is the
  // minimum of the two (its own bound inside); the any-field bounds of collision.hpp hold.
  std::mt19937 rng(14);
  const grip_test::ExactBox box{V3::Zero(), V3(0.04, 0.03, 0.02), Eigen::Matrix3d::Identity()};
  const grip_test::ExactSphere ball{V3(0.04, 0.03, 0.02), 0.025};
  const auto exact = [&](const V3& p) { return std::min(box(p), ball(p)); };
  Shape<S, 2> shape;
  REQUIRE(shape.add(make_box<S>(Vector3<S>(S(0.04), S(0.03), S(0.02)))) == Status::Ok);
  REQUIRE(shape.add(make_sphere<S>(S(0.025), Vector3<S>(S(0.04), S(0.03), S(0.02)))) == Status::Ok);
  REQUIRE(octree<S>().build(shape, 5) == Status::Ok);
  Tally tally;
  const int trials = grip_test::scaled(200, 50);
  for (int trial = 0; trial < trials; ++trial) {
    // Aim at the seam: a point on the ball's surface near where it leaves the box.
    const V3 u = grip_test::unit_vector(rng);
    const V3 f = ball.c + ball.radius * u;
    V3 a, b;
    const double r = uniform(rng, 0.006, 0.01);
    aim(rng, f, u, r, a, b);
    const auto off = [&](const V3& p) { return std::min(std::abs(box(p)), std::abs(ball(p))); };
    check_phalanx<S>(shape, exact, off, random_pose<S>(rng), a, b, r, false, tally);
  }
  CHECK(tally.contacts > grip_test::scaled_bound(100, trials, 200));
  CHECK(tally.apart > grip_test::scaled_bound(10, trials, 200));
}

TEST_CASE_TEMPLATE("without refinement, depths are the deepest sample's, exactly", S, double, float) {
  std::mt19937 rng(15);
  const V3 h(0.05, 0.04, 0.03);
  const grip_test::ExactBox exact{V3::Zero(), h, Eigen::Matrix3d::Identity()};
  const Shape<S> shape(make_box<S>(h.cast<S>()));
  REQUIRE(octree<S>().build(shape, 4) == Status::Ok);
  ContactSettings<S> samples_only;
  samples_only.refine_iterations = 0;
  int touching = 0;
  const int trials = grip_test::scaled(100, 12);
  for (int trial = 0; trial < trials; ++trial) {
    const double sx = sign(rng), sy = sign(rng), z = uniform(rng, -h.z(), h.z());
    V3 q(sx * h.x(), sy * h.y(), z);
    const V3 n = V3(q.x(), q.y(), 0).normalized();
    V3 a, b;
    aim(rng, q, n, 0.008, a, b);
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(single<S>(2, a.cast<S>(), b.cast<S>(), S(0.008))) == Status::Ok);
    HandContacts<S> out;
    REQUIRE(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), out, samples_only) == Status::Ok);
    double deepest = -1;
    int j_deepest = -1, penetrating = 0;
    for (int j = 0; j < 8; ++j) {
      const double p = 0.008 - exact(a + (j / 7.0) * (b - a));
      penetrating += p > 0 ? 1 : 0;
      if (p > deepest) {
        deepest = p;
        j_deepest = j;
      }
    }
    if (std::abs(deepest) < bound<S>(0)) continue;  // touching within rounding: either answer
    REQUIRE(out.count == (deepest > 0 ? 1 : 0));
    if (out.count == 0) continue;
    ++touching;
    CHECK(std::abs(double(out[0].depth) - deepest) <= bound<S>(0));
    CHECK(out[0].sample == j_deepest);
    CHECK(out[0].samples == penetrating);
    CHECK(std::abs(double(out[0].axis_parameter) - j_deepest / 7.0) <= 1e-6);
  }
  CHECK(touching > grip_test::scaled_bound(40, trials, 100));
}

namespace {
// An L-shaped union: a floor (top face z = 0) and a wall (inner face y = -0.03) meeting in a
// right-angled groove along x.
template <class S>
Shape<S, 2> l_shape() {
  Shape<S, 2> s;
  s.add(make_box<S>(Vector3<S>(S(0.05), S(0.05), S(0.01)), Vector3<S>(S(0), S(0), S(-0.01))));
  s.add(make_box<S>(Vector3<S>(S(0.05), S(0.01), S(0.04)), Vector3<S>(S(0), S(-0.04), S(0.03))));
  return s;
}

// Random whole-hand postures with the fingers around the origin (the wrist 10 cm away).
template <class S>
HandPosture<S> random_hand(std::mt19937& rng) {
  JointAngles<S> q;
  for (int k = 0; k < 14; ++k) q(k) = S(uniform(rng, 0, 1.2));
  Iso<S> wrist = Iso<S>::Identity();
  const Eigen::Matrix3d R = grip_test::rotation(rng);
  wrist.linear() = R.cast<S>();
  const V3 jitter(uniform(rng, -0.03, 0.03), uniform(rng, -0.03, 0.03), uniform(rng, -0.03, 0.03));
  wrist.translation() = (jitter - R * V3(0.1, 0, -0.03)).cast<S>();
  HandPosture<S> h;
  forward_kinematics(HandDimensions<S>::standard(), wrist, q, h);
  return h;
}

template <class S, int K>
void same_contacts(const HandContacts<S, K>& x, const HandContacts<S, K>& y) {
  REQUIRE(x.count == y.count);
  for (int i = 0; i < x.count; ++i) {  // the same computation on the same samples: bit for bit
    CHECK(x[i].finger == y[i].finger);
    CHECK(x[i].phalanx == y[i].phalanx);
    CHECK(x[i].depth == y[i].depth);
    CHECK(x[i].point == y[i].point);
    CHECK(x[i].normal == y[i].normal);
    CHECK(x[i].samples == y[i].samples);
    CHECK(x[i].sample == y[i].sample);
  }
}

template <class S, class Field>
int compare_broad_phase(const Field& field, int depth, std::mt19937& rng, int trials) {
  REQUIRE(octree<S>().build(field, depth) == Status::Ok);
  int total = 0;
  for (int trial = 0; trial < trials; ++trial) {
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(random_hand<S>(rng)) == Status::Ok);
    Iso<S> pose = random_pose<S>(rng);
    pose.translation() *= S(0.05);
    HandContacts<S> pruned, direct;
    REQUIRE(detect_contacts(hand, octree<S>(), field, pose, pruned) == Status::Ok);
    REQUIRE(detect_contacts_direct(hand, field, pose, direct) == Status::Ok);
    same_contacts(pruned, direct);
    HandContacts<S, 3> pruned3, direct3;
    REQUIRE(detect_contacts(hand, octree<S>(), field, pose, pruned3) == Status::Ok);
    REQUIRE(detect_contacts_direct(hand, field, pose, direct3) == Status::Ok);
    same_contacts(pruned3, direct3);
    total += pruned.count;
  }
  return total;
}
}  // namespace

TEST_CASE_TEMPLATE("the octree's broad phase drops nothing: the contacts of every sample evaluated", S, double, float) {
  std::mt19937 rng(16);
  const int trials = grip_test::scaled(40, 5);  // per shape; at least 30 contacts per 40 trials
  const int least = grip_test::scaled_bound(30, trials, 40);
  CHECK(compare_broad_phase<S>(Shape<S>(make_box<S>(Vector3<S>(S(0.05), S(0.04), S(0.03)))), 4, rng, trials) > least);
  CHECK(compare_broad_phase<S>(Shape<S>(make_cylinder<S>(S(0.035), S(0.07))), 5, rng, trials) > least);
  CHECK(compare_broad_phase<S>(l_shape<S>(), 4, rng, trials) > least);
}

TEST_CASE_TEMPLATE("several contacts per phalanx: a groove's two walls, a box edge's faces", S, double, float) {
  const double tol = bound<S>(0.006);
  // A phalanx (r = 8 mm) lying along the groove, 2 mm into the floor and 1.5 mm into the wall.
  const Shape<S, 2> groove = l_shape<S>();
  REQUIRE(octree<S>().build(groove, 5) == Status::Ok);
  const Vector3<S> a(S(-0.02), S(-0.03 + 0.0065), S(0.006)), b(S(0.02), S(-0.03 + 0.0065), S(0.006));
  HandCollisionModel<S> hand;
  REQUIRE(hand.set_posture(single<S>(8, a, b, S(0.008))) == Status::Ok);
  HandContacts<S, 2> two;
  REQUIRE(detect_contacts(hand, octree<S>(), groove, Iso<S>::Identity(), two) == Status::Ok);
  REQUIRE(two.count == 2);
  CHECK(two.count_of(Finger::Ring, Phalanx::Proximal) == 2);
  CHECK(std::abs(double(two[0].depth) - 0.002) <= tol);  // the floor, deeper, first
  CHECK((two[0].normal + Vector3<S>::UnitZ()).norm() <= S(tol));
  CHECK(std::abs(double(two[1].depth) - 0.0015) <= tol);  // the wall
  CHECK((two[1].normal + Vector3<S>::UnitY()).norm() <= S(tol));
  CHECK(two[1].samples == 8);
  CHECK(std::abs(double(two[1].point.y()) + 0.03) <= tol);
  HandContacts<S> one;  // one contact per phalanx: the floor's
  REQUIRE(detect_contacts(hand, octree<S>(), groove, Iso<S>::Identity(), one) == Status::Ok);
  REQUIRE(one.count == 1);
  CHECK(std::abs(double(one[0].depth) - 0.002) <= tol);

  // A phalanx pressed 5 mm onto a box edge, across it: each face, and the edge between.
  const V3 h(0.03, 0.03, 0.03);
  const grip_test::ExactBox exact{V3::Zero(), h, Eigen::Matrix3d::Identity()};
  const Shape<S> box(make_box<S>(h.cast<S>()));
  REQUIRE(octree<S>().build(box, 4) == Status::Ok);
  const V3 diag = V3(1, 0, 1).normalized(), along = V3(1, 0, -1).normalized();
  const V3 mid = V3(0.03, 0.004, 0.03) + 0.003 * diag + 0.0011 * along;
  const V3 ea = mid - 0.02 * along, eb = mid + 0.02 * along;
  REQUIRE(hand.set_posture(single<S>(8, ea.cast<S>(), eb.cast<S>(), S(0.008))) == Status::Ok);
  HandContacts<S, 3> three;
  REQUIRE(detect_contacts(hand, octree<S>(), box, Iso<S>::Identity(), three) == Status::Ok);
  REQUIRE(three.count == 3);
  CHECK(std::abs(double(three[0].depth) - 0.005) <= tol);  // the capsule's deepest point, at the edge
  CHECK((three[0].normal.template cast<double>() + diag).norm() <= 1e-3);
  bool top = false, side = false;
  for (int i = 1; i < 3; ++i) {
    const V3 n = three[i].normal.template cast<double>();
    top = top || (n + V3::UnitZ()).norm() <= tol;
    side = side || (n + V3::UnitX()).norm() <= tol;
    const V3 x = ea + double(three[i].axis_parameter) * (eb - ea);
    CHECK(std::abs(0.008 - double(three[i].depth) - exact(x)) <= tol);
    CHECK(std::abs(exact(three[i].point.template cast<double>())) <= tol);
  }
  CHECK(top);
  CHECK(side);
}

TEST_CASE_TEMPLATE("query_samples: each sample's exact distance, and every one near enough in reach", S, double,
                   float) {
  std::mt19937 rng(17);
  const grip_test::ExactCylinder exact{V3::Zero(), Eigen::Matrix3d::Identity(), 0.035, 0.07};
  const Shape<S> shape(make_cylinder<S>(S(0.035), S(0.07)));
  REQUIRE(octree<S>().build(shape, 4) == Status::Ok);
  int near = 0, far = 0;
  for (int trial = 0; trial < 30; ++trial) {
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(random_hand<S>(rng)) == Status::Ok);
    for (int k = 0; k < hand_phalanx_count; ++k) {
      PhalanxSamples<S, 8> q;
      REQUIRE(query_samples(hand, octree<S>(), shape, Iso<S>::Identity(), k, q) == Status::Ok);
      const PhalanxCapsule<S>& c = hand.capsule(k);
      const double margin = 0.5 * double((c.tip - c.base).norm()) / 7;
      for (std::size_t j = 0; j < 8; ++j) {
        const V3 x = (c.base + (S(j) / S(7)) * (c.tip - c.base)).template cast<double>();
        CHECK((q.center[j].template cast<double>() - x).norm() <= bound<S>(0));
        CHECK(std::abs(double(q.distance[j]) - exact(x)) <= bound<S>(0));
        if (exact(x) < double(c.radius) + margin) {
          CHECK(q.in_reach[j]);
          ++near;
        } else {
          ++far;
        }
      }
    }
  }
  CHECK(near > 100);
  CHECK(far > 100);
  HandCollisionModel<S> hand;
  PhalanxSamples<S, 8> q;
  CHECK(query_samples(hand, octree<S>(), shape, Iso<S>::Identity(), 0, q) == Status::InvalidInput);  // unposed
  REQUIRE(hand.set_posture(random_hand<S>(rng)) == Status::Ok);
  CHECK(query_samples(hand, octree<S>(), shape, Iso<S>::Identity(), 14, q) == Status::InvalidInput);
  CHECK(query_samples(hand, octree<S>(), shape, Iso<S>::Identity(), -1, q) == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("exact mode: bad settings and input refused, no heap per frame", S, double, float) {
  const Shape<S> shape(make_cylinder<S>(S(0.035), S(0.07)));
  REQUIRE(octree<S>().build(shape, 5) == Status::Ok);
  std::mt19937 rng(18);
  HandCollisionModel<S> hand;
  HandContacts<S, 2> out;
  out.count = 5;
  CHECK(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), out) == Status::InvalidInput);  // unposed
  CHECK(out.count == 0);
  const HandDimensions<S> dims = HandDimensions<S>::standard();
  HandPosture<S> posture;
  JointAngles<S> q = JointAngles<S>::Constant(S(0.5));
  Iso<S> wrist = Iso<S>::Identity();
  wrist.translation() = Vector3<S>(S(-0.08), S(0), S(0.05));
  {
    grip_test::NoHeapScope scope;  // one whole frame: kinematics, hierarchy, detection
    REQUIRE(forward_kinematics(dims, wrist, q, posture) == Status::Ok);
    REQUIRE(hand.set_posture(posture) == Status::Ok);
    REQUIRE(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), out) == Status::Ok);
    REQUIRE(detect_contacts_direct(hand, shape, Iso<S>::Identity(), out) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  CHECK(out.count > 0);
  ContactSettings<S> bad;
  bad.refine_iterations = -1;
  CHECK(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), out, bad) == Status::InvalidInput);
  CHECK(out.count == 0);
  bad.refine_iterations = 65;
  CHECK(detect_contacts_direct(hand, shape, Iso<S>::Identity(), out, bad) == Status::InvalidInput);
  bad = ContactSettings<S>{};
  bad.cluster_angle = std::numeric_limits<S>::quiet_NaN();
  CHECK(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), out, bad) == Status::InvalidInput);
  Iso<S> skewed = Iso<S>::Identity();
  skewed.linear()(0, 1) = S(0.5);
  CHECK(detect_contacts(hand, octree<S>(), shape, skewed, out) == Status::InvalidInput);
  CHECK(detect_contacts_direct(hand, Shape<S>(), Iso<S>::Identity(), out) == Status::InvalidInput);  // empty
  static SphericalOctree<S, 8> empty;
  CHECK(detect_contacts(hand, empty, shape, Iso<S>::Identity(), out) == Status::InvalidInput);
}

namespace {
using BoxMesh = TriangleMesh<double, 16, 16>;
template <class S>
using Mug = TriangleMesh<S, 2048, 4096>;
template <class S>
using MugShape = MeshShape<S, 2048, 4096>;

// The half sizes of the box mesh, and the box's exact distance.
const V3 box_half(0.05, 0.04, 0.03);
const grip_test::ExactBox exact_box{V3::Zero(), box_half, Eigen::Matrix3d::Identity()};

// The mug of tests/data/meshes (handle and cavity: not convex).
template <class S>
const MugShape<S>& mug_shape() {
  static Mug<S> mug;
  static MugShape<S> shape;
  static const bool loaded = [] {
    static char buffer[1 << 19];
    return read_mesh_file(GRIP_TEST_DATA_DIR "/meshes/mug.stl", buffer, sizeof buffer, mug).status == Status::Ok &&
           shape.build(mug) == Status::Ok;
  }();
  REQUIRE(loaded);
  return shape;
}

// A 12-triangle mesh of that box (a convex field equal to the box's exact distance,
// mesh_shape.test.cpp), with octree<double>() built from it at depth 3.
const MeshShape<double, 16, 16>& box_mesh_shape() {
  static BoxMesh mesh;
  REQUIRE(grip_mesh_test::load(grip_mesh_test::box_soup(box_half), mesh).status == Status::Ok);
  static MeshShape<double, 16, 16> shape;
  REQUIRE(shape.build(mesh) == Status::Ok);
  REQUIRE(octree<double>().build(winding_signed(shape), 3) == Status::Ok);
  return shape;
}
}  // namespace

TEST_CASE("a box as a triangle mesh: the capsule's exact deepest point, as for the analytic box") {
  // A 12-triangle mesh of a box is a convex field equal to the box's exact distance
  // (mesh_shape.test.cpp): the convex bounds hold, against the independent box geometry.
  using S = double;
  const V3& h = box_half;
  const MeshShape<S, 16, 16>& shape = box_mesh_shape();
  const grip_test::ExactBox& exact = exact_box;
  std::mt19937 rng(19);
  Tally tally;
  const int trials = grip_test::scaled(150, 38);
  for (int trial = 0; trial < trials; ++trial) {
    V3 q, n = V3::Zero();  // an edge or a corner
    for (int i = 0; i < 3; ++i) q(i) = sign(rng) * h(i);
    const int free_axis = trial % 4;  // 3: a corner
    if (free_axis < 3) q(free_axis) = uniform(rng, -h(free_axis), h(free_axis));
    for (int i = 0; i < 3; ++i)
      if (i != free_axis) n(i) = (q(i) > 0 ? 1 : -1) * uniform(rng, 0.05, 1);
    n.normalize();
    aim_and_check<S>(shape, exact, rng, q, n, tally);
  }
  check_tally(tally, 70, 10, 3, trials, 150);
}

TEST_CASE("a phalanx buried in a box mesh: samples deeper than the band get their exact distance") {
  // A mesh's bounded query misses a sample whose centre lies farther than the band from the
  // surface, inside or outside; the narrow phase must then tell the two apart (a neighbour's
  // distance, else the octree's solid leaves) and evaluate the deep ones exactly. Axes fully
  // buried, entering through a face from outside, and leaving through it from inside: the
  // convex bounds against the analytic box, and the same contacts without the octree.
  using S = double;
  const MeshShape<S, 16, 16>& shape = box_mesh_shape();
  const grip_test::ExactBox& exact = exact_box;
  const double r = 0.008;
  const std::array<std::array<V3, 2>, 4> axes{{
      {V3(-0.01, 0.0, 0.005), V3(0.01, 0.0, 0.005)},  // buried: every sample 25 mm deep
      {V3(0.0, 0.0, -0.01), V3(0.0, 0.0, 0.05)},      // from 20 mm deep out through the top face
      {V3(0.0, 0.01, 0.05), V3(0.0, -0.01, -0.01)},   // from outside in, ending 20 mm deep
      {V3(-0.045, 0.0, 0.0), V3(0.045, 0.0, 0.0)},    // along the middle, 30 mm deep at most
  }};
  Tally tally;
  for (const auto& ab : axes) {
    check_phalanx<S>(
        shape, exact, [&](const V3& p) { return std::abs(exact(p)); }, Iso<S>::Identity(), ab[0], ab[1], r, true,
        tally);
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(single<S>(5, ab[0], ab[1], S(r))) == Status::Ok);
    HandContacts<S> with, without;
    REQUIRE(detect_contacts(hand, octree<S>(), shape, Iso<S>::Identity(), with) == Status::Ok);
    REQUIRE(detect_contacts_direct(hand, shape, Iso<S>::Identity(), without) == Status::Ok);
    REQUIRE(with.count == 1);
    REQUIRE(without.count == 1);
    CHECK(with[0].depth == without[0].depth);
    CHECK(with[0].point == without[0].point);
    CHECK(with[0].normal == without[0].normal);
    CHECK(with[0].depth > S(0.02 + r));  // deeper than any bounded query reaches
  }
  CHECK(tally.deep == 4);
}

TEST_CASE_TEMPLATE("a mesh with cavities and a handle (the mug): the bounds of any field", S, double, float) {
  // Not convex: depths are true penetrations of the capsule, at least the deepest sample's and
  // the true depth minus half a spacing, points and normals exact for their axis point. The
  // field (MeshShape::distance, checked against every triangle in mesh_shape.test.cpp) is the
  // reference; the axis minimum is found by dense sampling.
  const MugShape<S>& shape = mug_shape<S>();
  const Mug<S>& mug = *shape.mesh();
  REQUIRE(octree<S>().build(winding_signed(shape), 3) == Status::Ok);
  const auto exact = [&](const V3& p) { return double(shape.distance(p.cast<S>())); };
  std::mt19937 rng(20);
  Tally tally;
  const int trials = grip_test::scaled(60, 8);
  for (int trial = 0; trial < trials; ++trial) {
    const int v = int(grip_test::u01(rng) * mug.vertex_count()) % mug.vertex_count();
    const V3 n = mug.vertex_normal(v).template cast<double>();
    const V3 f = mug.vertex(v).template cast<double>() + (trial % 3 == 0 ? 0.003 : 0.0) * n;  // some pulled away
    V3 a, b;
    const double r = uniform(rng, 0.006, 0.01);
    aim(rng, f, n, r, a, b);
    check_phalanx<S>(shape, exact, surface_of(exact), Iso<S>::Identity(), a, b, r, false, tally, 300);
  }
  CHECK(tally.contacts > grip_test::scaled_bound(25, trials, 60));
  CHECK(tally.apart > grip_test::scaled_bound(3, trials, 60));
  // Refinement by triangles (narrow_phase.hpp) promises no more than the bounds above, but on
  // this smooth mesh it reaches the capsule's true depth (within 1 um) nine times in ten.
  CHECK(10 * tally.reached >= 9 * tally.contacts);
}

TEST_CASE_TEMPLATE("a mesh's own hierarchy as stage 2: the contacts of every sample evaluated", S, double, float) {
  // For a field with a bounded query the octree answers only stage 1 and the inside test
  // (collision.hpp): the contacts must be those of the direct loop over every sample.
  std::mt19937 rng(21);
  const int trials = grip_test::scaled(40, 5);
  CHECK(compare_broad_phase<S>(mug_shape<S>(), 3, rng, trials) > grip_test::scaled_bound(10, trials, 40));
}

namespace {
// A prism of `sides` sides around the z axis (radius to its vertices, half height): a convex
// mesh of a cylinder, its rings counter-clockwise seen from +z, triangles outward.
grip_mesh_test::Soup prism_soup(int sides, double radius, double half) {
  grip_mesh_test::Soup s;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * grip_test::pi * i / sides;
    s.v.push_back(V3(radius * std::cos(a), radius * std::sin(a), -half));
    s.v.push_back(V3(radius * std::cos(a), radius * std::sin(a), half));
  }
  const int bottom = 2 * sides, top = 2 * sides + 1;
  s.v.push_back(V3(0, 0, -half));
  s.v.push_back(V3(0, 0, half));
  for (int i = 0; i < sides; ++i) {
    const int b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * ((i + 1) % sides), t1 = b1 + 1;
    s.t.push_back({b0, b1, t1});
    s.t.push_back({b0, t1, t0});
    s.t.push_back({bottom, b1, b0});
    s.t.push_back({top, t0, t1});
  }
  return s;
}

// The exact signed distance of that prism (a convex polygon extruded along z), independent of
// its triangles: the polygon's signed 2-D distance d (least distance to its edges, negative
// inside every edge's half-plane) and e = |z| - half combine as for a box: max(d, e) inside,
// else the length of (max(d, 0), max(e, 0)).
struct ExactPrism {
  int sides;
  double radius, half;
  double operator()(const V3& p) const {
    double d2 = 1e300;
    bool inside = true;
    for (int i = 0; i < sides; ++i) {
      const double a0 = 2 * grip_test::pi * i / sides, a1 = 2 * grip_test::pi * (i + 1) / sides;
      const Eigen::Vector2d v0(radius * std::cos(a0), radius * std::sin(a0)),
          v1(radius * std::cos(a1), radius * std::sin(a1));
      const Eigen::Vector2d e = v1 - v0, w = p.head<2>() - v0;
      const double t = std::clamp(w.dot(e) / e.squaredNorm(), 0.0, 1.0);
      d2 = std::min(d2, (w - t * e).squaredNorm());
      inside = inside && e.x() * w.y() - e.y() * w.x() >= 0;  // left of each counter-clockwise edge
    }
    const double d = inside ? -std::sqrt(d2) : std::sqrt(d2), e = std::abs(p.z()) - half;
    if (d <= 0 && e <= 0) return std::max(d, e);
    return std::hypot(std::max(d, 0.0), std::max(e, 0.0));
  }
};

// A phalanx axis through q (just inside a convex solid near an edge or corner) whose eight
// samples all lie outside it: the chord of the solid along a random direction through q is
// found by bisection, and when it is shorter than a spacing, the samples are placed so that it
// lies between two of them (the other samples, on the same line, are outside a convex solid).
// False when ten directions gave no such placement.
template <class Exact>
bool pierce_between_samples(std::mt19937& rng, const Exact& exact, const V3& q, V3& a, V3& b) {
  REQUIRE(exact(q) < 0);
  for (int attempt = 0; attempt < 10; ++attempt) {
    const V3 u = grip_test::unit_vector(rng);
    const auto exit = [&](double sign) {  // where the line leaves the solid, from q along sign u
      double in = 0, out = 0.1;
      for (int k = 0; k < 40; ++k) {
        const double m = 0.5 * (in + out);
        (exact(q + sign * m * u) < 0 ? in : out) = m;
      }
      return out;
    };
    const double s_out = exit(1), s_in = -exit(-1), chord = s_out - s_in;
    const double L = uniform(rng, 0.012, 0.045), spacing = L / 7;
    if (!(chord < 0.9 * spacing)) continue;
    // Sample j before the chord and j + 1 after it, each at least 5 % of a spacing outside.
    const int j = int(grip_test::u01(rng) * 7) % 7;
    const double before = s_in - 0.05 * spacing - grip_test::u01(rng) * (0.9 * spacing - chord);
    a = q + (before - j * spacing) * u;
    b = a + L * u;
    // Each sample at least 0.1 mm outside: beyond the rounding of float's poses, so that float
    // sees them outside too (a line grazing the surface can bring one closer).
    bool clear = true;
    for (int i = 0; i < 8 && clear; ++i) clear = exact(a + (i / 7.0) * (b - a)) > 1e-4;
    if (clear) return true;
  }
  return false;
}

// Convex meshes pierced near their edges and corners (the box's, and a prism's rims and side
// edges), every sample outside: the convex bounds against the exact distance. Returns the
// trials in which the capsule's true depth exceeds its deepest sample's by over 0.1 mm.
template <class S, class MeshT, class Exact, class Feature>
int pierce_and_check(const MeshShape<S, MeshT::max_vertices, MeshT::max_triangles>& shape, const Exact& exact,
                     std::mt19937& rng, int trials, Feature&& feature, Tally& tally) {
  int beyond_samples = 0;
  for (int trial = 0; trial < trials; ++trial) {
    V3 a, b;
    int features = 0;  // points whose chords are all too long are drawn again
    while (!pierce_between_samples(rng, exact, feature(rng, trial), a, b)) REQUIRE(++features < 100);
    const double r = uniform(rng, 0.006, 0.011);
    double deepest_sample = -1;
    for (int j = 0; j < 8; ++j) {
      const double phi = exact(a + (j / 7.0) * (b - a));
      CHECK(phi > 1e-4);  // every sample outside
      deepest_sample = std::max(deepest_sample, r - phi);
    }
    const double gap =
        check_phalanx<S>(shape, exact, surface_of(exact), random_pose<S>(rng), a, b, r, true, tally, 100);
    if (r - gap > deepest_sample + 1e-4) ++beyond_samples;
  }
  return beyond_samples;
}
}  // namespace

TEST_CASE_TEMPLATE("convex meshes pierced near an edge or corner between samples: the exact deepest point", S, double,
                   float) {
  // Every sample outside, the axis inside the solid between two of them: the search by
  // triangles meets a triangle or stops on another face's, and the deepest point must still be
  // found (collision.hpp's convex bounds), against the exact distances of the box and the prism.
  std::mt19937 rng(23);
  const int trials = grip_test::scaled(60, 15);
  Tally tally;
  {
    const V3 h(0.0625, 0.046875, 0.03125);
    static TriangleMesh<S, 16, 16> mesh;
    REQUIRE(grip_mesh_test::load(grip_mesh_test::box_soup(h), mesh).status == Status::Ok);
    static MeshShape<S, 16, 16> shape;
    REQUIRE(shape.build(mesh) == Status::Ok);
    REQUIRE(octree<S>().build(winding_signed(shape), 3) == Status::Ok);
    const grip_test::ExactBox exact{V3::Zero(), h, Eigen::Matrix3d::Identity()};
    const auto feature = [&](std::mt19937& g, int trial) {  // within 1.5 mm of an edge (or a corner), inside
      V3 q;
      const int free_axis = trial % 4;  // 3: a corner
      for (int i = 0; i < 3; ++i) q(i) = sign(g) * (h(i) - uniform(g, 0.00005, 0.0015));
      if (free_axis < 3) q(free_axis) = uniform(g, -0.8, 0.8) * h(free_axis);
      return q;
    };
    const int beyond = pierce_and_check<S, TriangleMesh<S, 16, 16>>(shape, exact, rng, trials, feature, tally);
    CHECK(beyond > grip_test::scaled_bound(6, trials, 60));  // the deepest point lies between samples
  }
  {
    const double radius = 0.035, half = 0.05;
    const ExactPrism exact{16, radius, half};
    static TriangleMesh<S, 64, 128> mesh;
    REQUIRE(grip_mesh_test::load(prism_soup(16, radius, half), mesh).status == Status::Ok);
    static MeshShape<S, 64, 128> shape;
    REQUIRE(shape.build(mesh) == Status::Ok);
    REQUIRE(octree<S>().build(winding_signed(shape), 3) == Status::Ok);
    const auto feature = [&](std::mt19937& g, int trial) {  // inside, near a rim or a side edge
      const int i = int(grip_test::u01(g) * 16) % 16;
      const double a0 = 2 * grip_test::pi * i / 16, a1 = 2 * grip_test::pi * (i + 1) / 16;
      const double in = uniform(g, 0.00005, 0.0015);
      if (trial % 2 == 0) {  // a rim: a point of a rim edge, pulled in and down
        const double w = grip_test::u01(g);
        const V3 p = (1 - w) * V3(std::cos(a0), std::sin(a0), 0) + w * V3(std::cos(a1), std::sin(a1), 0);
        return V3((radius - in) * p.x(), (radius - in) * p.y(), sign(g) * (half - uniform(g, 0.00005, 0.0015)));
      }
      return V3((radius - in) * std::cos(a0), (radius - in) * std::sin(a0), uniform(g, -0.8, 0.8) * half);
    };
    const int beyond = pierce_and_check<S, TriangleMesh<S, 64, 128>>(shape, exact, rng, trials, feature, tally);
    CHECK(beyond > grip_test::scaled_bound(6, trials, 60));
  }
  CHECK(tally.contacts == 2 * trials);  // the axis pierces: every capsule penetrates
}

TEST_CASE_TEMPLATE("contact normals on curved surfaces: within sqrt(2 tol / R) of the deepest point's", S, double,
                   float) {
  // A sphere and a cylinder's side, whose deepest axis point and its normal are known in
  // closed form: the foot of the perpendicular from the centre, and the point of the axis
  // nearest the cylinder's axis line. A contact's axis point has a distance within tol of the
  // least; across a level surface of radius R that turns the normal by at most sqrt(2 tol / R)
  // (collision.hpp). tol: the depth bound of these tests (the search's tolerance and rounding).
  // The default tolerance that collision.hpp documents, and the settings' own.
  const double documented = std::is_same<S, float>::value ? 1e-7 : 1e-12;
  CHECK(double(ContactSettings<S>{}.refine_tolerance) == doctest::Approx(documented).epsilon(1e-6));
  std::mt19937 rng(24);
  const int trials = grip_test::scaled(300, 40);
  int checked = 0;
  double worst = 0;  // the largest turn over its bound
  const auto check_normal = [&](const auto& shape, const V3& n_star, double R, const V3& a, const V3& b, double r) {
    const Iso<S> pose = random_pose<S>(rng);
    const Iso<double> pose_d = pose.template cast<double>();
    HandCollisionModel<S> hand;
    REQUIRE(hand.set_posture(single<S>(5, (pose_d * a).cast<S>(), (pose_d * b).cast<S>(), S(r))) == Status::Ok);
    HandContacts<S> out;
    REQUIRE(detect_contacts(hand, octree<S>(), shape, pose, out) == Status::Ok);
    if (out.count != 1) return;
    const V3 normal = pose_d.linear().transpose() * out[0].normal.template cast<double>();
    const double tol = documented + 64 * double(std::numeric_limits<S>::epsilon()) * 0.5;  // and rounding
    const double turn = std::acos(std::clamp(-normal.dot(n_star), -1.0, 1.0));
    // The bound, plus the normal's own rounding (a few ulps of a unit vector over R).
    const double allowed = std::sqrt(2 * tol / R) + tol / R;
    worst = std::max(worst, turn / allowed);
    CHECK(turn <= allowed);
    ++checked;
  };
  const V3 c(0.004, -0.002, 0.001);
  const double ball_radius = 0.04;
  const Shape<S> sphere(make_sphere<S>(S(ball_radius), c.cast<S>()));
  REQUIRE(octree<S>().build(sphere, 5) == Status::Ok);
  for (int trial = 0; trial < trials; ++trial) {
    const V3 u = grip_test::unit_vector(rng);
    V3 a, b;
    const double r = uniform(rng, 0.006, 0.01);
    aim(rng, c + ball_radius * u, u, r, a, b);
    const double t = std::clamp((c - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const V3 x = a + t * (b - a);
    const double R = (x - c).norm();
    if (R < 0.01) continue;  // near the centre: no curvature to speak of
    check_normal(sphere, (x - c) / R, R, a, b, r);
  }
  const Eigen::Matrix3d Rc = grip_test::rotation(rng);
  const double radius = 0.035, half = 0.07;
  const Shape<S> cylinder(make_cylinder<S>(S(radius), S(half), c.cast<S>(), Rc.cast<S>()));
  REQUIRE(octree<S>().build(cylinder, 5) == Status::Ok);
  for (int trial = 0; trial < trials; ++trial) {
    const double angle = uniform(rng, 0, 2 * grip_test::pi);
    const V3 radial(std::cos(angle), std::sin(angle), 0);
    const V3 f = radius * radial + V3(0, 0, uniform(rng, -0.6, 0.6) * half);
    V3 a, b;
    const double r = uniform(rng, 0.006, 0.01);
    aim(rng, f, radial, r, a, b);  // local frame
    // The axis point nearest the cylinder's axis (local z): least x^2 + y^2 over [a, b].
    const Eigen::Vector2d a2 = a.head<2>(), d2 = (b - a).head<2>();
    const double t = d2.squaredNorm() > 0 ? std::clamp(-a2.dot(d2) / d2.squaredNorm(), 0.0, 1.0) : 0.0;
    const V3 x = a + t * (b - a);
    const double R = x.head<2>().norm();
    // Only where the side decides the distance near x (not a cap), away from the axis.
    if (R < 0.01 || std::abs(x.z()) > half - 0.02 || std::abs(x.z()) - half > R - radius) continue;
    const V3 n_local(x.x() / R, x.y() / R, 0);
    check_normal(cylinder, Rc * n_local, R, c + Rc * a, c + Rc * b, r);
  }
  MESSAGE("largest normal turn over its bound: " << worst);
  CHECK(checked > grip_test::scaled_bound(300, 2 * trials, 600));
}

}  // namespace collision_bounds_test
