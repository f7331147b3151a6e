// CylinderScene: hand contacts on the side, the end caps and the rims against closed forms,
// and its obstacles (any shape) against the rim points.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <grip/pipeline/cylinder_scene.hpp>

#include "support/exact_geometry.hpp"
#include "support/hand_postures.hpp"

namespace cylinder_scene_test {

using namespace grip;
using grip_test::V3;

namespace {
template <class S>
HandPosture<S> single(int k, const V3& a, const V3& b, double r) {
  return grip_test::single_phalanx<S>(k, a.cast<S>(), b.cast<S>(), S(r));
}
template <class S>
double tol() {  // the narrow phase's bound: its refine_tolerance (0.1 um), and 64 ulps of 0.5 m
  return double(ContactSettings<S>{}.refine_tolerance) + 64 * double(std::numeric_limits<S>::epsilon()) * 0.5;
}
}  // namespace

TEST_CASE_TEMPLATE("cylinder scene: side, end caps and rims at their closed-form depths", S, double, float) {
  // Cylinder radius 35 mm, half length 60 mm, its axis (body z) along world y, centred at c.
  CylinderScene<S> scene;
  RigidBody<S> body;
  body.position = Vector3<S>(S(0.1), S(0.2), S(0.5));
  Matrix3<S> r;
  r.col(0) = Vector3<S>::UnitZ();
  r.col(1) = Vector3<S>::UnitX();
  r.col(2) = Vector3<S>::UnitY();
  body.orientation = Eigen::Quaternion<S>(r);
  const V3 c(0.1, 0.2, 0.5);
  HandContacts<S> out;

  // The side: a phalanx parallel to the axis, 2 mm into it from above (+z).
  scene.hand_contacts(single<S>(3, c + V3(0, -0.02, 0.041), c + V3(0, 0.02, 0.041), 0.008), body, out);
  REQUIRE(out.count == 1);
  CHECK(std::abs(double(out[0].depth) - 0.002) <= tol<S>());
  CHECK((out[0].normal.template cast<double>() - V3(0, 0, -1)).norm() <= tol<S>());
  CHECK(std::abs(double(out[0].point.z()) - (0.5 + 0.035)) <= tol<S>());

  // An end cap (world +y): a fingertip pushed 3 mm in along -y, off the axis.
  scene.hand_contacts(
      single<S>(4, c + V3(0.01, 0.06 + 0.008 - 0.003 + 0.02, 0.005), c + V3(0.01, 0.06 + 0.005, 0.005), 0.008), body,
      out);
  REQUIRE(out.count == 1);
  CHECK(out[0].finger == Finger::Index);
  CHECK(out[0].phalanx == Phalanx::Distal);
  CHECK(std::abs(double(out[0].depth) - 0.003) <= tol<S>());
  CHECK((out[0].normal.template cast<double>() - V3(0, -1, 0)).norm() <= tol<S>());
  CHECK(std::abs(double(out[0].point.y()) - (0.2 + 0.06)) <= tol<S>());

  // Across a rim: the capsule's deepest point against the exact distance of the solid.
  const grip_test::ExactCylinder exact{c, r.template cast<double>(), 0.035, 0.06};
  std::mt19937 rng(21);
  int touching = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const double th = grip_test::uniform(rng, 0, 6.283185307179586), s = grip_test::u01(rng) < 0.5 ? -1 : 1;
    const V3 rim = c + r.template cast<double>() * V3(0.035 * std::cos(th), 0.035 * std::sin(th), s * 0.06);
    const V3 out_dir = (r.template cast<double>() * V3(std::cos(th), std::sin(th), s)).normalized();
    const V3 x0 = rim + (0.008 + grip_test::uniform(rng, -0.004, 0.002)) * out_dir;
    const V3 u = grip_test::unit_vector(rng);
    const V3 a = x0 - 0.015 * u, b = x0 + 0.02 * u;
    scene.hand_contacts(single<S>(7, a, b, 0.008), body, out);
    const double depth = 0.008 - grip_test::segment_minimum(exact, a, b);
    if (std::abs(depth) <= tol<S>()) continue;
    REQUIRE(out.count == (depth > 0 ? 1 : 0));
    if (out.count == 0) continue;
    ++touching;
    CHECK(std::abs(double(out[0].depth) - depth) <= tol<S>());
  }
  CHECK(touching > 20);
}

TEST_CASE_TEMPLATE("cylinder scene: a rotated slab obstacle meets the rim points it covers", S, double, float) {
  CylinderScene<S> scene;
  scene.rim_points = 8;
  RigidBody<S> body;
  body.position = Vector3<S>(S(0), S(0), S(0.1));  // axis along world z: rims at z = 0.04 and 0.16
  // A slab whose top face is the plane z = 0.041 tilted 0.2 rad about x, through (0, 0, 0.041).
  const Matrix3<S> R = Eigen::AngleAxis<S>(S(0.2), Vector3<S>::UnitX()).toRotationMatrix();
  const Vector3<S> up = R.col(2);
  const Vector3<S> top(S(0), S(0), S(0.041));
  REQUIRE(scene.obstacles.add(
              Shape<S>(make_box<S>(Vector3<S>(S(1), S(1), S(0.05)), Vector3<S>(top - S(0.05) * up), R))) == Status::Ok);
  ObstacleContactSet<S> set;
  const int n = scene.obstacle_contacts(body, set);
  // Each lower-rim point p = (0.035 cos a, 0.035 sin a, 0.04) is below the plane by
  // up . (top - p) when that is positive: a contact of that depth along up.
  int expected = 0;
  for (int j = 0; j < 8; ++j) {
    const double a = 6.283185307179586 * j / 8;
    const Vector3<S> p(S(0.035 * std::cos(a)), S(0.035 * std::sin(a)), S(0.04));
    const S below = up.dot(top - p);
    if (below <= S(0)) continue;
    REQUIRE(expected < n);
    const PenaltyContact<S>& pc = set.items[static_cast<std::size_t>(expected)];
    CHECK((pc.point - (p - body.position)).norm() <= S(1e-6));
    CHECK(std::abs(pc.depth - below) <= S(1e-6));
    CHECK((pc.normal - up).norm() <= S(1e-6));
    ++expected;
  }
  CHECK(n == expected);
  CHECK(n >= 3);
  CHECK(scene.obstacles.add_box(Vector3<S>::Zero(), Vector3<S>(S(1), S(0), S(1))) == Status::InvalidInput);  // empty
}

}  // namespace cylinder_scene_test
