// Singular-value quality measures against a hand-built G.
#include <doctest/doctest.h>

#include <grip/analysis/quality.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"

using grip_test::pi;

using namespace grip;

TEST_CASE_TEMPLATE("singular values of three hard fingers at 120 degrees, by hand", S, double, float) {
  // r_i = R (cos phi_i, sin phi_i, 0), phi_i = 0, 120, 240 degrees. G G^T =
  // [[3 I, -[sum r]x], [[sum r]x, sum (|r|^2 I - r r^T)]] with sum r = 0 and
  // sum r r^T = (3 R^2 / 2) diag(1, 1, 0), so G G^T = diag(3, 3, 3, 1.5 R^2, 1.5 R^2, 3 R^2):
  // sigma = sqrt 3 (three times), R sqrt 3, R sqrt 1.5 (twice).
  const double R = 0.05;
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(1.5707963267948966, 2.0943951023931953 * i, R)) == Status::Ok);
  GraspQuality<S> q;
  {
    grip_test::NoHeapScope scope;
    q = grasp_quality(g);
    CHECK(scope.allocations() == 0);
  }
  REQUIRE(q.status == Status::Ok);
  const double s3 = std::sqrt(3.0);
  const double expect[6] = {s3, s3, s3, R * s3, R * std::sqrt(1.5), R * std::sqrt(1.5)};
  for (int k = 0; k < 6; ++k) CHECK(double(q.singular_values(k)) == doctest::Approx(expect[k]).epsilon(1e-4));
  CHECK(double(q.sigma_min) == doctest::Approx(R * std::sqrt(1.5)).epsilon(1e-4));
  CHECK(double(q.isotropy) == doctest::Approx(R * std::sqrt(0.5)).epsilon(1e-4));
  const double vol = pi * pi * pi / 6.0 * s3 * s3 * s3 * R * s3 * R * R * 1.5;
  CHECK(double(q.volume) == doctest::Approx(vol).epsilon(1e-4));
  // Torque scale rho = R: the moment rows become sqrt 3, sqrt 1.5 (twice).
  const auto qs = grasp_quality(g, S(R));
  CHECK(double(qs.sigma_min) == doctest::Approx(std::sqrt(1.5)).epsilon(1e-4));
  CHECK(double(qs.isotropy) == doctest::Approx(std::sqrt(0.5)).epsilon(1e-4));
}

TEST_CASE_TEMPLATE("singular values agree with an SVD of the explicit G (all models)", S, double, float) {
  std::mt19937 rng(17);
  auto check = [](const auto& g) {
    const auto q = grasp_quality(g, S(0.1));
    REQUIRE(q.status == Status::Ok);
    // The reference in double, one JacobiSVD instantiation for every grasp type and scalar.
    Eigen::MatrixXd G = g.grasp_matrix().template cast<double>();
    G.bottomRows(3) /= double(S(0.1));
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(G);
    for (int k = 0; k < 6; ++k)
      CHECK(q.singular_values(k) ==
            doctest::Approx(double(svd.singularValues()(k))).epsilon(double(grip_test::tight<S>()) * 10));
  };
  for (int rep = 0; rep < 10; ++rep) {
    check(grip_test::random_grasp<Grasp<4, HardFinger, S>>(rng, 4));
    check(grip_test::random_grasp<Grasp<Dynamic, SoftFinger, S, 5>>(rng, 3));
    check(grip_test::random_grasp<Grasp<Dynamic, FrictionlessPoint, S, 9>>(rng, 8));
  }
}

TEST_CASE_TEMPLATE("quality of a rank-deficient grasp and bad input", S, double, float) {
  Grasp<2, HardFinger, S> g;  // two hard fingers: no moment about the line through them
  REQUIRE(g.set(0, grip_test::sphere_contact<S>(1.5707963267948966, 0.0, 0.05)) == Status::Ok);
  REQUIRE(g.set(1, grip_test::sphere_contact<S>(1.5707963267948966, 3.141592653589793, 0.05)) == Status::Ok);
  const auto q = grasp_quality(g);
  CHECK(q.status == Status::Ok);
  CHECK(double(q.sigma_min) <= 1e-3);
  CHECK(grasp_quality(g, S(0)).status == Status::InvalidInput);
  CHECK(grasp_quality(g, std::numeric_limits<S>::quiet_NaN()).status == Status::InvalidInput);
  Grasp<3, HardFinger, S> incomplete;
  CHECK(grasp_quality(incomplete).status == Status::InvalidInput);
}

template struct grip::GraspQuality<float>;
template struct grip::GraspQuality<double>;
