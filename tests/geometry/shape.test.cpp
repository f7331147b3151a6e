// Signed distance shapes: exact distances and normals at hand-derived points, unions, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Geometry>

#include <grip/geometry/shape.hpp>
#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

template struct grip::ShapePrimitive<double>;
template struct grip::ShapePrimitive<float>;
template class grip::Shape<double, 4>;
template class grip::Shape<float, 2>;

namespace {
// Tolerances from round-off (support/tolerance.hpp), condition 1 for a distance (the SDF is
// 1-Lipschitz). M is the largest of the coordinates and sizes a check's shape and point are
// made of (m): the decimal data are rounded once to S (3 u M for the point, the centre and the
// size), q = R^T (p - c) one more (R is the identity or a permutation here: exact), |q| or the
// like 3, and d = |q| - r 1: k = 8 u M.
template <class S>
double tol_d(double M) {
  return grip_test::roundoff<S>(8, 1, M);
}
// A normal v / |v|, v the vector from the nearest feature (|v| = L): v's error, 4 u M from the
// data's rounding and p - c, turns it by up to 4 u M / L; the norm and the division take 4 more
// roundings of 1: k = 8, condition 1 + M / L (a unit vector: scale 1).
template <class S>
double tol_n(double M, double L) {
  return grip_test::roundoff<S>(8, 1 + M / L, 1);
}
}  // namespace

TEST_CASE_TEMPLATE("primitive distances and outward normals at derived points", S, double, float) {
  Vector3<S> n;
  // Sphere r = 0.04 at (0.01, 0, 0): point (0.01, 0.05, 0) is 0.01 outside, normal +y.
  const auto sp = make_sphere<S>(S(0.04), Vector3<S>(S(0.01), S(0), S(0)));
  // M = |p| = 0.051; the normal is q / |q|, |q| = 0.05.
  CHECK(double(std::abs(sp.distance(Vector3<S>(S(0.01), S(0.05), S(0)), n) - S(0.01))) <= tol_d<S>(0.051));
  CHECK(double((n - Vector3<S>::UnitY()).norm()) <= tol_n<S>(0.051, 0.05));
  // Box half (0.05, 0.04, 0.03): inside point (0, 0, 0.025) is 0.005 below the top face.
  const auto bx = make_box<S>(Vector3<S>(S(0.05), S(0.04), S(0.03)));
  // M = |half extents| = 0.071; inside, the normal is an axis picked exactly (L = M).
  CHECK(double(std::abs(bx.distance(Vector3<S>(S(0), S(0), S(0.025)), n) + S(0.005))) <= tol_d<S>(0.071));
  CHECK(double((n - Vector3<S>::UnitZ()).norm()) <= tol_n<S>(0.071, 0.071));
  // Outside near the edge (x = 0.05, z = 0.03): point (0.08, 0, 0.07): distance = |(0.03, 0, 0.04)| = 0.05.
  // M = |p| = 0.106; the normal is (|q| - h)+ / d, d = 0.05.
  CHECK(double(std::abs(bx.distance(Vector3<S>(S(0.08), S(0), S(0.07)), n) - S(0.05))) <= tol_d<S>(0.106));
  CHECK(double((n - Vector3<S>(S(0.6), S(0), S(0.8))).norm()) <= tol_n<S>(0.106, 0.05));
  // Below the bottom face: normal -z.
  // M = |half extents| = 0.071; the normal (0, 0, 0.01) / 0.01 from the clipped e.
  CHECK(double(std::abs(bx.distance(Vector3<S>(S(0.01), S(0.01), S(-0.04)), n) - S(0.01))) <= tol_d<S>(0.071));
  CHECK(double((n + Vector3<S>::UnitZ()).norm()) <= tol_n<S>(0.071, 0.01));
  // Cylinder r = 0.035, half height 0.07, axis z: side point at radius 0.04 -> 0.005 outside.
  const auto cy = make_cylinder<S>(S(0.035), S(0.07));
  // M = |(r, h)| = 0.078; the normal q_xy / rho, rho = 0.04.
  CHECK(double(std::abs(cy.distance(Vector3<S>(S(0.024), S(0.032), S(0.01)), n) - S(0.005))) <= tol_d<S>(0.078));
  CHECK(double((n - Vector3<S>(S(0.6), S(0.8), S(0))).norm()) <= tol_n<S>(0.078, 0.04));
  // Inside near the cap: 0.002 below the top cap, far from the side.
  // M = 0.078; the normal an axis picked exactly (L = M).
  CHECK(double(std::abs(cy.distance(Vector3<S>(S(0), S(0.01), S(0.068)), n) + S(0.002))) <= tol_d<S>(0.078));
  CHECK(double((n - Vector3<S>::UnitZ()).norm()) <= tol_n<S>(0.078, 0.078));
  // Beyond the rim: (0.035 + 0.003, 0, 0.07 + 0.004) -> 0.005 from the rim circle.
  // M = |p| = 0.083.
  CHECK(double(std::abs(cy.distance(Vector3<S>(S(0.038), S(0), S(0.074)), n) - S(0.005))) <= tol_d<S>(0.083));
  // Capsule r = 0.01, half length 0.02 along z, turned so its axis is x: end cap point.
  Matrix3<S> R;
  R << S(0), S(0), S(1), S(0), S(1), S(0), S(-1), S(0), S(0);  // local z -> object x
  const auto ca = make_capsule<S>(S(0.01), S(0.02), Vector3<S>::Zero(), R);
  // M = |p| = 0.035, the normal v / |v| with |v| = 0.015; then M = 0.02 (the half length),
  // |v| = 0.004.
  CHECK(double(std::abs(ca.distance(Vector3<S>(S(0.035), S(0), S(0)), n) - S(0.005))) <= tol_d<S>(0.035));
  CHECK(double((n - Vector3<S>::UnitX()).norm()) <= tol_n<S>(0.035, 0.015));
  CHECK(double(std::abs(ca.distance(Vector3<S>(S(0.01), S(0), S(-0.004)), n) + S(0.006))) <= tol_d<S>(0.02));
  CHECK(double((n + Vector3<S>::UnitZ()).norm()) <= tol_n<S>(0.02, 0.004));
}

TEST_CASE_TEMPLATE("SDFs are 1-Lipschitz with unit gradients, the gradient matches finite differences", S, double,
                   float) {
  Matrix3<S> R = Eigen::AngleAxis<S>(S(0.4), Vector3<S>(S(1), S(1), S(0)).normalized()).toRotationMatrix();
  const ShapePrimitive<S> prims[4] = {make_sphere<S>(S(0.03)),
                                      make_box<S>(Vector3<S>(S(0.03), S(0.02), S(0.01)), Vector3<S>::Zero(), R),
                                      make_cylinder<S>(S(0.02), S(0.03), Vector3<S>::Zero(), R),
                                      make_capsule<S>(S(0.015), S(0.02), Vector3<S>::Zero(), R)};
  std::mt19937 rng(7);
  grip_test::Uniform u(-0.06, 0.06);
  // The central differences' step, not a tolerance: it balances their truncation error
  // (~h^2) against the rounding of a difference of distances (~u M / h), so it is larger in
  // float: near u^(1/3) L with L = 0.2 m (9.6e-7 in double, 7.8e-4 in float).
  const S h = std::is_same<S, float>::value ? S(1e-3) : S(1e-6);
  for (const auto& p : prims) {
    for (int t = 0; t < 200; ++t) {
      const Vector3<S> x = grip_test::draw3(rng, u).cast<S>();
      Vector3<S> n;
      const S d = p.distance(x, n);
      // v / |v| (or an axis), then R's product: |n| within the division's and the norm's 4
      // roundings, R's 3 per coordinate and R's own departure from orthogonality (AngleAxis:
      // a few u): k = 10 of 1.
      CHECK(double(std::abs(n.norm() - S(1))) <= grip_test::roundoff<S>(10, 1, 1));
      Vector3<S> fd;
      Vector3<S> dummy;
      for (int i = 0; i < 3; ++i) {
        Vector3<S> e = Vector3<S>::Zero();
        e(i) = h;
        fd(i) = (p.distance(x + e, dummy) - p.distance(x - e, dummy)) / (S(2) * h);
      }
      // Away from the medial axis (where the gradient jumps) central differences agree.
      // Not round-off: a central difference's truncation error (h^2 / 6 times the distance's
      // third derivative, unbounded near the medial axis and a primitive's centre). 2e-2 is
      // this check's own allowance, documented nowhere and left as it was: it catches a wrong
      // sign or axis of the normal, not a small error.
      if (std::abs(fd.norm() - S(1)) < S(1e-2)) CHECK((fd - n).norm() <= S(2e-2));
      // The surface point x - d n is on the surface.
      // The SDF is 1-Lipschitz: d's error (8 u M), |d| times n's (8 u (|d| + M)), x - d n (2 u M)
      // and the second distance's own (8 u M): k = 26 of M = |x| + |d| + the primitive's size,
      // at most 0.06 sqrt(3) + 0.04 here, with R a general rotation (k covers its 3 products).
      const double M = double(x.norm() + std::abs(d)) + 0.04;
      CHECK(double(std::abs(p.distance(Vector3<S>(x - d * n), dummy))) <= grip_test::roundoff<S>(26, 1, M));
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
  // M = |p| = 0.058, then 0.065; the box's normal from the clipped e, |e| = 0.005.
  CHECK(double(std::abs(two.distance(Vector3<S>(S(-0.05), S(0.03), S(0)), n) - S(0.01))) <= tol_d<S>(0.058));
  CHECK(double(std::abs(two.distance(Vector3<S>(S(0.065), S(0), S(0)), n) - S(0.005))) <= tol_d<S>(0.065));
  CHECK(double((n - Vector3<S>::UnitX()).norm()) <= tol_n<S>(0.065, 0.005));
  Vector3<S> lo, hi;
  REQUIRE(two.bounding_box(lo, hi));
  // c -+ h: the data's rounding and the sum's, 2 roundings of each coordinate, and the
  // compared values' own rounding to S: k = 3 of the corner's norm.
  CHECK(double((lo - Vector3<S>(S(-0.07), S(-0.02), S(-0.02))).norm()) <= grip_test::roundoff<S>(3, 1, 0.076));
  CHECK(double((hi - Vector3<S>(S(0.06), S(0.02), S(0.02))).norm()) <= grip_test::roundoff<S>(3, 1, 0.067));
  // 4/3 pi r^3: r's rounding 3 u, 4/3 and pi 2, the 4 products 4, and the reference's rounding
  // to S 1: k = 10 of the volume.
  const double v = 4.0 / 3.0 * 3.141592653589793 * 8e-6;
  CHECK(std::abs(double(two.primitive(0).volume()) - double(S(v))) <= grip_test::roundoff<S>(10, 1, v));

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
