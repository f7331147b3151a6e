// Signed distance shapes: exact distances and normals at hand-derived points, unions, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Geometry>

#include <grip/geometry/shape.hpp>
#include "support/random.hpp"

using namespace grip;

template struct grip::ShapePrimitive<double>;
template struct grip::ShapePrimitive<float>;
template class grip::Shape<double, 4>;
template class grip::Shape<float, 2>;

namespace {
template <class S>
S eps() {
  return std::is_same<S, float>::value ? S(1e-5) : S(1e-12);
}
}  // namespace

TEST_CASE_TEMPLATE("primitive distances and outward normals at derived points", S, double, float) {
  Vector3<S> n;
  // Sphere r = 0.04 at (0.01, 0, 0): point (0.01, 0.05, 0) is 0.01 outside, normal +y.
  const auto sp = make_sphere<S>(S(0.04), Vector3<S>(S(0.01), S(0), S(0)));
  CHECK(std::abs(sp.distance(Vector3<S>(S(0.01), S(0.05), S(0)), n) - S(0.01)) <= eps<S>());
  CHECK((n - Vector3<S>::UnitY()).norm() <= eps<S>());
  // Box half (0.05, 0.04, 0.03): inside point (0, 0, 0.025) is 0.005 below the top face.
  const auto bx = make_box<S>(Vector3<S>(S(0.05), S(0.04), S(0.03)));
  CHECK(std::abs(bx.distance(Vector3<S>(S(0), S(0), S(0.025)), n) + S(0.005)) <= eps<S>());
  CHECK((n - Vector3<S>::UnitZ()).norm() <= eps<S>());
  // Outside near the edge (x = 0.05, z = 0.03): point (0.08, 0, 0.07): distance = |(0.03, 0, 0.04)| = 0.05.
  CHECK(std::abs(bx.distance(Vector3<S>(S(0.08), S(0), S(0.07)), n) - S(0.05)) <= eps<S>());
  CHECK((n - Vector3<S>(S(0.6), S(0), S(0.8))).norm() <= eps<S>());
  // Below the bottom face: normal -z.
  CHECK(std::abs(bx.distance(Vector3<S>(S(0.01), S(0.01), S(-0.04)), n) - S(0.01)) <= eps<S>());
  CHECK((n + Vector3<S>::UnitZ()).norm() <= eps<S>());
  // Cylinder r = 0.035, half height 0.07, axis z: side point at radius 0.04 -> 0.005 outside.
  const auto cy = make_cylinder<S>(S(0.035), S(0.07));
  CHECK(std::abs(cy.distance(Vector3<S>(S(0.024), S(0.032), S(0.01)), n) - S(0.005)) <= eps<S>());
  CHECK((n - Vector3<S>(S(0.6), S(0.8), S(0))).norm() <= eps<S>());
  // Inside near the cap: 0.002 below the top cap, far from the side.
  CHECK(std::abs(cy.distance(Vector3<S>(S(0), S(0.01), S(0.068)), n) + S(0.002)) <= eps<S>());
  CHECK((n - Vector3<S>::UnitZ()).norm() <= eps<S>());
  // Beyond the rim: (0.035 + 0.003, 0, 0.07 + 0.004) -> 0.005 from the rim circle.
  CHECK(std::abs(cy.distance(Vector3<S>(S(0.038), S(0), S(0.074)), n) - S(0.005)) <= eps<S>());
  // Capsule r = 0.01, half length 0.02 along z, turned so its axis is x: end cap point.
  Matrix3<S> R;
  R << S(0), S(0), S(1), S(0), S(1), S(0), S(-1), S(0), S(0);  // local z -> object x
  const auto ca = make_capsule<S>(S(0.01), S(0.02), Vector3<S>::Zero(), R);
  CHECK(std::abs(ca.distance(Vector3<S>(S(0.035), S(0), S(0)), n) - S(0.005)) <= eps<S>());
  CHECK((n - Vector3<S>::UnitX()).norm() <= S(10) * eps<S>());
  CHECK(std::abs(ca.distance(Vector3<S>(S(0.01), S(0), S(-0.004)), n) + S(0.006)) <= eps<S>());
  CHECK((n + Vector3<S>::UnitZ()).norm() <= S(10) * eps<S>());
}

TEST_CASE_TEMPLATE("SDFs are 1-Lipschitz with unit gradients, the gradient matches finite differences", S, double,
                   float) {
  Matrix3<S> R = Eigen::AngleAxis<S>(S(0.4), Vector3<S>(S(1), S(1), S(0)).normalized()).toRotationMatrix();
  const ShapePrimitive<S> prims[4] = {make_sphere<S>(S(0.03)), make_box<S>(Vector3<S>(S(0.03), S(0.02), S(0.01)), Vector3<S>::Zero(), R),
                                      make_cylinder<S>(S(0.02), S(0.03), Vector3<S>::Zero(), R),
                                      make_capsule<S>(S(0.015), S(0.02), Vector3<S>::Zero(), R)};
  std::mt19937 rng(7);
  grip_test::Uniform u(-0.06, 0.06);
  const S h = std::is_same<S, float>::value ? S(1e-3) : S(1e-6);
  for (const auto& p : prims) {
    for (int t = 0; t < 200; ++t) {
      const Vector3<S> x = grip_test::draw3(rng, u).cast<S>();
      Vector3<S> n;
      const S d = p.distance(x, n);
      CHECK(std::abs(n.norm() - S(1)) <= S(10) * eps<S>());
      Vector3<S> fd;
      Vector3<S> dummy;
      for (int i = 0; i < 3; ++i) {
        Vector3<S> e = Vector3<S>::Zero();
        e(i) = h;
        fd(i) = (p.distance(x + e, dummy) - p.distance(x - e, dummy)) / (S(2) * h);
      }
      // Away from the medial axis (where the gradient jumps) central differences agree.
      if (std::abs(fd.norm() - S(1)) < S(1e-2)) CHECK((fd - n).norm() <= S(2e-2));
      // The surface point x - d n is on the surface.
      CHECK(std::abs(p.distance(Vector3<S>(x - d * n), dummy)) <= (std::is_same<S, float>::value ? S(1e-5) : S(1e-10)));
    }
  }
}

TEST_CASE_TEMPLATE("union: minimum of the primitives, validation of bad primitives", S, double, float) {
  Shape<S, 2> two;
  CHECK(two.add(make_sphere<S>(S(0.02), Vector3<S>(S(-0.05), S(0), S(0)))) == Status::Ok);
  CHECK(two.add(make_box<S>(Vector3<S>(S(0.01), S(0.01), S(0.01)), Vector3<S>(S(0.05), S(0), S(0)))) == Status::Ok);
  CHECK(two.add(make_sphere<S>(S(1))) == Status::InvalidInput);  // full
  CHECK(two.size() == 2);
  Vector3<S> n;
  CHECK(std::abs(two.distance(Vector3<S>(S(-0.05), S(0.03), S(0)), n) - S(0.01)) <= eps<S>());
  CHECK(std::abs(two.distance(Vector3<S>(S(0.065), S(0), S(0)), n) - S(0.005)) <= eps<S>());
  CHECK((n - Vector3<S>::UnitX()).norm() <= eps<S>());
  Vector3<S> lo, hi;
  REQUIRE(two.bounding_box(lo, hi));
  CHECK((lo - Vector3<S>(S(-0.07), S(-0.02), S(-0.02))).norm() <= eps<S>());
  CHECK((hi - Vector3<S>(S(0.06), S(0.02), S(0.02))).norm() <= eps<S>());
  CHECK(std::abs(two.primitive(0).volume() - S(4.0 / 3.0 * 3.141592653589793 * 8e-6)) <= S(1e-9));

  Shape<S> s;
  Vector3<S> lo2, hi2;
  CHECK_FALSE(s.bounding_box(lo2, hi2));
  const S nan = std::numeric_limits<S>::quiet_NaN();
  CHECK(s.add(make_sphere<S>(S(-1))) == Status::InvalidInput);
  CHECK(s.add(make_sphere<S>(nan)) == Status::InvalidInput);
  CHECK(s.add(make_box<S>(Vector3<S>(S(1), S(0), S(1)))) == Status::InvalidInput);
  CHECK(s.add(make_cylinder<S>(S(1), S(0))) == Status::InvalidInput);
  CHECK(s.add(make_capsule<S>(S(1), S(0))) == Status::Ok);  // a capsule of zero length is a sphere
  CHECK(s.add(make_box<S>(Vector3<S>::Ones(), Vector3<S>::Zero(), Matrix3<S>(S(2) * Matrix3<S>::Identity()))) ==
        Status::InvalidInput);
  CHECK(s.size() == 1);
}
