// projection_jacobian against central finite differences of each cone's own projection, in
// every region (interior, polar, boundary) and for the degenerate cones (mu = 0, mu_t = 0),
// at seeded random points; points within a step of a region's edge, where P is not
// differentiable, are skipped and counted, and every region must be reached often.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include <grip/contact/coulomb_cone.hpp>
#include <grip/contact/normal_cone.hpp>
#include <grip/contact/soft_finger_cone.hpp>
#include <grip/solve/projection_jacobian.hpp>

#include "support/random.hpp"

namespace projection_jacobian_test {

using namespace grip;

/// Tested points per region (Interior, Polar, Boundary) and skipped ones.
struct Tally {
  std::array<int, 3> tested{};
  int skipped{0};
};

/// Checks J(v) against (P(v + h e_k) - P(v - h e_k)) / 2h column by column, to `tol`, when v
/// and all the perturbed points lie in one region; else counts a skip. Step h = step (1 + |v|):
/// the truncation error is h^2 times P's third derivative; the rounding error, eps |P| / h,
/// is larger for the soft finger, whose boundary projection is a root found iteratively and
/// whose moments scale by 1/mu_t (down to 1e-5 m here): step 1e-5 and tol 1e-5 there.
template <class Cone>
void check_point(const Cone& cone, const typename Cone::Vector& v, Tally& tally, double step = 1e-6,
                 double tol = 1e-6) {
  using V = typename Cone::Vector;
  constexpr int d = Cone::dim;
  const auto j = projection_jacobian(cone, v, cone.project(v));
  const double h = step * (1 + v.norm());
  Eigen::Matrix<double, d, d> fd;
  for (int k = 0; k < d; ++k) {
    V e = V::Zero();
    e(k) = h;
    const V vp = v + e, vm = v - e;
    if (projection_jacobian(cone, vp, cone.project(vp)).region != j.region ||
        projection_jacobian(cone, vm, cone.project(vm)).region != j.region) {
      ++tally.skipped;
      return;
    }
    fd.col(k) = (cone.project(vp) - cone.project(vm)) / (2 * h);
  }
  ++tally.tested[static_cast<std::size_t>(j.region)];
  CAPTURE(v.transpose());
  CHECK((j.matrix - fd).cwiseAbs().maxCoeff() <= tol);
  // A projection's generalised Jacobian is symmetric with eigenvalues in [0, 1].
  CHECK((j.matrix - j.matrix.transpose()).cwiseAbs().maxCoeff() <= 1e-12);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, d, d>> es(j.matrix);
  CHECK(es.eigenvalues().minCoeff() >= -1e-9);
  CHECK(es.eigenvalues().maxCoeff() <= 1 + 1e-9);
}

Vector3<double> unit(std::mt19937& rng) {
  const grip_test::Normal n01(0, 1);
  return grip_test::draw3(rng, n01).normalized();
}

TEST_CASE("projection_jacobian: the compression cone, by finite differences") {
  std::mt19937 rng(5);
  const grip_test::Normal n01(0, 1);
  Tally t;
  CompressionCone<double> cone;
  for (int i = 0; i < 200; ++i) check_point(cone, Eigen::Matrix<double, 1, 1>::Constant(n01(rng)), t);
  CHECK(t.tested[0] >= 80);  // interior (x > 0)
  CHECK(t.tested[1] >= 80);  // polar (x <= 0)
}

TEST_CASE("projection_jacobian: Coulomb cones, mu in [0, 1.5], by finite differences") {
  std::mt19937 rng(7);
  const grip_test::Normal n01(0, 1);
  const grip_test::Uniform u01(0, 1);
  Tally t;
  for (int i = 0; i < 3000; ++i) {
    const double mu = i % 10 == 0 ? 0.0 : 1.5 * u01(rng);  // one in ten: the ray mu = 0
    const CoulombCone<double> cone{unit(rng), mu};
    check_point(cone, Vector3<double>(grip_test::draw3(rng, n01)), t);
  }
  MESSAGE("Coulomb: interior ", t.tested[0], ", polar ", t.tested[1], ", boundary ", t.tested[2], ", skipped ",
          t.skipped);
  for (int r = 0; r < 3; ++r) CHECK(t.tested[static_cast<std::size_t>(r)] >= 200);
  CHECK(t.skipped <= 30);
}

TEST_CASE("projection_jacobian: elliptic soft-finger cones, mu_t = 0 and mu = 0 too, by finite differences") {
  std::mt19937 rng(11);
  const grip_test::Normal n01(0, 1);
  const grip_test::Uniform u01(0, 1);
  Tally t;
  std::array<int, 3> degenerate{};
  for (int i = 0; i < 3000; ++i) {
    const int kind = i % 10;  // 0: mu_t = 0; 1: mu = 0; else both positive
    SoftFingerCone<double, SoftFingerNorm::Elliptic> cone;
    cone.normal = unit(rng);
    cone.mu = kind == 1 ? 0.0 : 1.5 * u01(rng);
    cone.mu_t = kind == 0 ? 0.0 : 0.02 * u01(rng);
    Eigen::Matrix<double, 4, 1> v;
    v << n01(rng), n01(rng), n01(rng), 0.02 * n01(rng);  // moments on the scale of mu_t f
    if (i % 3 == 0) v.head<3>() += 2.0 * cone.normal;    // more points inside the cone
    const int before = t.tested[0] + t.tested[1] + t.tested[2];
    check_point(cone, v, t, 1e-5, 1e-5);
    if (kind < 2) degenerate[static_cast<std::size_t>(kind)] += t.tested[0] + t.tested[1] + t.tested[2] - before;
  }
  MESSAGE("soft finger: interior ", t.tested[0], ", polar ", t.tested[1], ", boundary ", t.tested[2], ", skipped ",
          t.skipped, "; mu_t = 0: ", degenerate[0], ", mu = 0: ", degenerate[1]);
  for (int r = 0; r < 3; ++r) CHECK(t.tested[static_cast<std::size_t>(r)] >= 200);
  CHECK(degenerate[0] >= 250);
  CHECK(degenerate[1] >= 250);
  CHECK(t.skipped <= 30);
}

TEST_CASE("projection_jacobian: float agrees with double at the same points") {
  std::mt19937 rng(13);
  const grip_test::Normal n01(0, 1);
  const grip_test::Uniform u01(0, 1);
  for (int i = 0; i < 500; ++i) {
    const Vector3<double> a = unit(rng);
    const double mu = 1.5 * u01(rng), mt = 0.02 * u01(rng);
    Eigen::Matrix<double, 4, 1> v;
    v << n01(rng), n01(rng), n01(rng), 0.02 * n01(rng);
    const SoftFingerCone<double, SoftFingerNorm::Elliptic> cd{a, mu, mt};
    const SoftFingerCone<float, SoftFingerNorm::Elliptic> cf{a.cast<float>(), float(mu), float(mt)};
    const auto jd = projection_jacobian(cd, v, cd.project(v));
    const Eigen::Matrix<float, 4, 1> vf = v.cast<float>();
    const auto jf = projection_jacobian(cf, vf, cf.project(vf));
    if (jd.region != jf.region) continue;  // a point on an edge in one precision only
    CHECK((jf.matrix.cast<double>() - jd.matrix).cwiseAbs().maxCoeff() <= 1e-2);  // float J of an LU-solved 5x5
  }
}

}  // namespace projection_jacobian_test
