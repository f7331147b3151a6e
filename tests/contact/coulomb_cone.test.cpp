// CoulombCone: eq. 4-5 of the paper, margins, closed-form projection, dual cone, edge cases.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/contact/coulomb_cone.hpp>

#include "support/allocation_counter.hpp"
#include "support/cone_sampling.hpp"
#include "support/random.hpp"

using namespace grip;
using grip_test::rel_tol;

template struct grip::CoulombCone<double>;
template struct grip::CoulombCone<float>;

namespace {

// Eq. 4 and 5 exactly as the paper writes them: f.a / |f| >= 1/sqrt(1 + mu^2) and f.a > 0.
template <class S>
bool paper_eq_4_5(const Vector3<S>& f, const Vector3<S>& a, S mu) {
  const S fa = f.dot(a);
  return fa / f.norm() >= S(1) / std::sqrt(S(1) + mu * mu) && fa > S(0);
}

}  // namespace

TEST_CASE_TEMPLATE("Coulomb: inside iff margin >= 0, and eq. 4-5 agree off the boundary", S, double, float) {
  std::mt19937 rng(41);
  grip_test::Uniform u01(0.0, 1.0);
  int inside = 0, outside = 0;
  grip_test::NoHeapScope scope;
  for (int k = 0; k < 10000; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const S mu = S(0.05 + 2.0 * u01(rng));
    const CoulombCone<S> cone{ad.cast<S>(), mu};
    const Vector3<S> f = grip_test::random_force(rng, ad, -3.0, 5.0, 6.0).cast<S>();
    const S m = cone.margin(f);
    CHECK(cone.is_inside(f) == (m >= S(0)));
    CHECK((cone.relative_margin(f) >= S(0)) == (m >= S(0)));
    CHECK(cone.relative_margin(f) <= S(1));
    // Hand derivation of the margin: mu (f.a) - |f - (f.a) a| for f.a >= 0.
    const S fn = f.dot(cone.normal);
    if (fn >= S(0)) CHECK(std::abs(m - (mu * fn - (f - fn * cone.normal).norm())) <= rel_tol<S>() * S(10));
    // f.a/|f| >= 1/sqrt(1+mu^2) <=> (f.a)^2 (1 + mu^2) >= |f|^2 = (f.a)^2 + |f_t|^2 (f.a > 0)
    // <=> mu f.a >= |f_t|: the same set as margin >= 0, so they agree wherever |margin| is
    // above round-off.
    if (std::abs(m) > S(10) * rel_tol<S>() * f.norm()) {
      CHECK(paper_eq_4_5(f, cone.normal, mu) == (m > S(0)));
      (m > S(0) ? inside : outside)++;
    }
  }
  CHECK(scope.allocations() == 0);
  CHECK(inside > 2000);  // both sides were exercised
  CHECK(outside > 2000);
}

TEST_CASE_TEMPLATE("Coulomb: relative margin is 1 - |f_t| / (mu f_n)", S, double, float) {
  const CoulombCone<S> cone{Vector3<S>::UnitZ(), S(0.5)};
  // f_n = 4, |f_t| = 1: margin 0.5*4 - 1 = 1 N; relative 1 - 1/2 = 0.5.
  const Vector3<S> f(S(0.6), S(0.8), S(4));
  CHECK(cone.margin(f) == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(cone.relative_margin(f) == doctest::Approx(0.5).epsilon(1e-6));
  CHECK(cone.normal_part(f) == S(4));
  CHECK((cone.tangential_part(f) - Vector3<S>(S(0.6), S(0.8), S(0))).norm() <= rel_tol<S>());
  CHECK(cone.tangential_norm(f) == doctest::Approx(1.0).epsilon(1e-6));
  // Pure normal push: no friction used.
  CHECK(cone.relative_margin(Vector3<S>(S(0), S(0), S(3))) == S(1));
  Contact<S> c;
  c.normal = Vector3<S>::UnitY();
  c.friction = S(0.7);
  const auto from = CoulombCone<S>::from_contact(c);
  CHECK(from.normal == c.normal);
  CHECK(from.mu == c.friction);
}

TEST_CASE_TEMPLATE("Coulomb: projection is idempotent, inside, and the nearest point", S, double, float) {
  std::mt19937 rng(42);
  grip_test::Uniform u01(0.0, 1.0);
  grip_test::NoHeapScope scope;
  for (int k = 0; k < 10000; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const CoulombCone<S> cone{ad.cast<S>(), S(0.05 + 2.0 * u01(rng))};
    const Vector3<S> f = grip_test::random_force(rng, ad, -5.0, 5.0, 6.0).cast<S>();
    const Vector3<S> p = cone.project(f);
    const S tol = S(10) * rel_tol<S>() * (S(1) + f.norm());
    CHECK(cone.margin(p) >= -tol);
    CHECK((cone.project(p) - p).norm() <= tol);
    if (cone.is_inside(f)) CHECK(p == f);
    // Moreau's decomposition (an independent characterisation of the projection onto a
    // closed convex cone K): p in K, f - p in the polar cone -K*, and p.(f - p) = 0.
    CHECK(cone.dual().margin(Vector3<S>(p - f)) >= -tol);
    CHECK(std::abs(p.dot(f - p)) <= tol * (S(1) + f.norm()));
  }
  CHECK(scope.allocations() == 0);
}

TEST_CASE("Coulomb: projection beats a brute-force search over the cone") {
  // Brute force: the nearest point of the outside force to points of the cone sampled on a
  // grid (apex, and boundary points f_n (a + mu u(phi)) for f_n in [0, 8], phi in [0, 2 pi)).
  std::mt19937 rng(43);
  grip_test::Uniform u01(0.0, 1.0);
  for (int k = 0; k < 30; ++k) {
    const Vector3<double> a = grip_test::random_unit(rng);
    const double mu = 0.1 + 1.5 * u01(rng);
    const CoulombCone<double> cone{a, mu};
    const Vector3<double> f = grip_test::random_force(rng, a, -3.0, 4.0, 6.0);
    if (cone.is_inside(f)) continue;  // inside: the projection is f itself (checked above)
    const Vector3<double> p = cone.project(f);
    // Coordinates of f in the frame (a, t1, t2); plain scalars keep the Debug build fast.
    const Vector3<double> t1 = grip_test::random_tangent(rng, a), t2 = a.cross(t1);
    const double fn = f.dot(a), f1 = f.dot(t1), f2 = f.dot(t2);
    double best2 = f.squaredNorm();
    for (int j = 0; j < 360; ++j) {
      const double c = mu * std::cos(6.283185307179586 * j / 360.0), s = mu * std::sin(6.283185307179586 * j / 360.0);
      for (int i = 0; i <= 400; ++i) {
        const double x = 8.0 * i / 400.0;
        const double d2 = (fn - x) * (fn - x) + (f1 - x * c) * (f1 - x * c) + (f2 - x * s) * (f2 - x * s);
        if (d2 < best2) best2 = d2;
      }
    }
    const double best = std::sqrt(best2);
    const double d = (f - p).norm();
    CHECK(d <= best + 1e-12);
    CHECK(d >= best - 0.05);  // the grid is fine enough that brute force comes close
  }
}

TEST_CASE_TEMPLATE("Coulomb: the dual of mu is 1/mu, checked against the definition", S, double, float) {
  // y is in the dual cone iff y.x >= 0 for every x of the cone; the cone is generated by its
  // boundary rays a + mu u(phi), sampled at 720 angles.
  std::mt19937 rng(44);
  grip_test::Uniform u01(0.0, 1.0);
  for (int k = 0; k < 3000; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const double mu = 0.1 + 2.0 * u01(rng);
    const CoulombCone<S> cone{ad.cast<S>(), S(mu)};
    const CoulombCone<S> d = cone.dual();
    CHECK(d.mu == doctest::Approx(1.0 / mu).epsilon(1e-6));
    CHECK(d.normal == cone.normal);
    const Vector3<double> t1 = grip_test::random_tangent(rng, ad), t2 = ad.cross(t1);
    const Vector3<double> y = grip_test::random_force(rng, ad, -2.0, 4.0, 5.0);
    const double yn = y.dot(ad), y1 = y.dot(t1), y2 = y.dot(t2);
    double worst = 1e300;
    for (int j = 0; j < 720; ++j) {
      const double phi = 6.283185307179586 * j / 720.0;
      worst = std::min(worst, yn + mu * (std::cos(phi) * y1 + std::sin(phi) * y2));
    }
    const S m = d.margin(y.cast<S>());
    if (std::abs(m) > S(1e-2) * S(1 + y.norm())) CHECK((m > S(0)) == (worst >= 0.0));
  }
}

TEST_CASE_TEMPLATE("Coulomb: edge cases have defined, finite answers", S, double, float) {
  const S floor = cone_margin_floor<S>();
  const CoulombCone<S> cone{Vector3<S>::UnitZ(), S(0.5)};
  grip_test::NoHeapScope scope;
  // Zero force: the apex, on the boundary.
  const Vector3<S> zero = Vector3<S>::Zero();
  CHECK(cone.is_inside(zero));
  CHECK(cone.margin(zero) == S(0));
  CHECK(cone.relative_margin(zero) == S(0));
  CHECK(cone.project(zero) == zero);
  // Zero normal part: purely tangential 2 N: margin -2, relative at the floor, projects onto
  // the boundary ray: f_n' = (0 + 0.5*2)/(1.25) = 0.8, f_t' = 0.4.
  const Vector3<S> tang(S(2), S(0), S(0));
  CHECK_FALSE(cone.is_inside(tang));
  CHECK(cone.margin(tang) == S(-2));
  CHECK(cone.relative_margin(tang) == floor);
  CHECK((cone.project(tang) - Vector3<S>(S(0.4), S(0), S(0.8))).norm() <= rel_tol<S>());
  // A pure pull is outside and projects to the apex.
  CHECK(cone.margin(Vector3<S>(S(0), S(0), S(-1))) < S(0));
  CHECK(cone.project(Vector3<S>(S(0), S(0), S(-1))) == zero);
  // NaN and Inf: outside, floor margins, zero projection.
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  for (const Vector3<S>& bad : {Vector3<S>(nan, S(0), S(1)), Vector3<S>(S(0), inf, S(1))}) {
    CHECK_FALSE(cone.is_inside(bad));
    CHECK(cone.margin(bad) == floor);
    CHECK(cone.relative_margin(bad) == floor);
    CHECK(cone.project(bad) == zero);
  }
  // mu = 0: the ray f_n a. On the ray: margin 0 (no tangential reserve), relative 1.
  const CoulombCone<S> ray{Vector3<S>::UnitZ(), S(0)};
  CHECK(ray.is_inside(Vector3<S>(S(0), S(0), S(3))));
  CHECK(ray.margin(Vector3<S>(S(0), S(0), S(3))) == S(0));
  CHECK(ray.relative_margin(Vector3<S>(S(0), S(0), S(3))) == S(1));
  CHECK_FALSE(ray.is_inside(Vector3<S>(S(0), S(0), S(-3))));  // pull: margin -3 despite mu = 0
  CHECK(ray.margin(Vector3<S>(S(0), S(0), S(-3))) == S(-3));
  CHECK_FALSE(ray.is_inside(Vector3<S>(S(0.001), S(0), S(3))));
  CHECK(ray.relative_margin(Vector3<S>(S(0.001), S(0), S(3))) == floor);
  CHECK(ray.project(Vector3<S>(S(1), S(2), S(3))) == Vector3<S>(S(0), S(0), S(3)));
  CHECK(ray.project(Vector3<S>(S(1), S(2), S(-3))) == zero);
  // The dual of the ray is the half-space y.a >= 0 (mu = cone_half_space_mu()), and back.
  const CoulombCone<S> half = ray.dual();
  CHECK(half.mu == cone_half_space_mu<S>());
  CHECK(half.is_inside(Vector3<S>(S(100), S(-50), S(0.01))));
  CHECK_FALSE(half.is_inside(Vector3<S>(S(1), S(0), S(-0.01))));
  CHECK(half.dual().mu == S(0));
  CHECK(scope.allocations() == 0);
}
