// SoftFingerCone: elliptic, linear and decoupled coupling of force and torsion; margins,
// projection (Moreau conditions, brute force), duals by the definition, degenerate cases.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

#include <grip/contact/coulomb_cone.hpp>
#include <grip/contact/soft_finger_cone.hpp>

#include "support/allocation_counter.hpp"
#include "support/cone_sampling.hpp"
#include "support/random.hpp"

using namespace grip;
using grip_test::rel_tol;

template struct grip::SoftFingerCone<double, SoftFingerNorm::Elliptic>;
template struct grip::SoftFingerCone<float, SoftFingerNorm::Linear>;
template struct grip::SoftFingerCone<double, SoftFingerNorm::Decoupled>;
template struct grip::SoftFingerCone<float, SoftFingerNorm::Elliptic>;

namespace {

template <class S>
Eigen::Matrix<S, 4, 1> soft_vec(const Vector3<double>& f, double m) {
  Eigen::Matrix<S, 4, 1> x;
  x << f.cast<S>(), S(m);
  return x;
}

// A random (f, m): f_n in [-2, 4], |f_t| in [0, 4], m in [-0.08, 0.08] N m.
template <class S>
Eigen::Matrix<S, 4, 1> random_soft(std::mt19937& rng, const Vector3<double>& a) {
  grip_test::Uniform u(-1.0, 1.0);
  return soft_vec<S>(grip_test::random_force(rng, a, -2.0, 4.0, 4.0), 0.08 * u(rng));
}

template <class S, SoftFingerNorm N>
void check_projection(std::mt19937& rng) {
  grip_test::Uniform u01(0.0, 1.0);
  for (int k = 0; k < 2500; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const SoftFingerCone<S, N> c{ad.cast<S>(), S(0.2 + 1.2 * u01(rng)), S(0.005 + 0.02 * u01(rng))};
    const auto x = random_soft<S>(rng, ad);
    const auto p = c.project(x);
    const S tol = S(20) * rel_tol<S>() * (S(1) + x.norm());
    CHECK(c.margin(p) >= -tol);
    CHECK((c.project(p) - p).norm() <= tol);
    if (c.is_inside(x)) CHECK(p == x);
    // Moreau: p - x in the dual cone, p.(x - p) = 0.
    CHECK(c.dual().margin(decltype(p)(p - x)) >= -tol * S(10));
    CHECK(std::abs(p.dot(x - p)) <= tol * (S(1) + x.norm()));
  }
}

}  // namespace

TEST_CASE_TEMPLATE("Soft finger: inside iff margin >= 0, and the models nest", S, double, float) {
  std::mt19937 rng(61);
  grip_test::Uniform u01(0.0, 1.0);
  grip_test::NoHeapScope scope;
  int inside = 0;
  for (int k = 0; k < 10000; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const S mu = S(0.2 + 1.2 * u01(rng)), mt = S(0.005 + 0.02 * u01(rng));
    const Vector3<S> a = ad.cast<S>();
    const SoftFingerCone<S> ell{a, mu, mt};
    const SoftFingerCone<S, SoftFingerNorm::Linear> lin{a, mu, mt};
    const SoftFingerCone<S, SoftFingerNorm::Decoupled> dec{a, mu, mt};
    const auto x = random_soft<S>(rng, ad);
    const S tol = S(10) * rel_tol<S>() * (S(1) + x.norm());
    CHECK(ell.is_inside(x) == (ell.margin(x) >= S(0)));
    CHECK((ell.relative_margin(x) >= S(0)) == ell.is_inside(x));
    CHECK((lin.relative_margin(x) >= S(0)) == lin.is_inside(x));
    CHECK((dec.relative_margin(x) >= S(0)) == dec.is_inside(x));
    // The elliptic model as written: |f_t|^2/mu^2 + m^2/mu_t^2 <= f_n^2 with f_n >= 0.
    const S fn = x.template head<3>().dot(a);
    const S ft = (x.template head<3>() - fn * a).norm();
    const S lhs = ft * ft / (mu * mu) + x(3) * x(3) / (mt * mt);
    if (std::abs(lhs - fn * fn) > S(100) * rel_tol<S>() * (S(1) + lhs + fn * fn))
      CHECK(ell.is_inside(x) == (lhs < fn * fn && fn > S(0)));
    // Norms nest (1-norm >= 2-norm >= max-norm): Linear inside Elliptic inside Decoupled.
    if (lin.margin(x) >= S(0)) CHECK(ell.margin(x) >= -tol);
    if (ell.margin(x) >= S(0)) CHECK(dec.margin(x) >= -tol);
    // With m = 0 the elliptic cone is the Coulomb cone, margin included.
    auto x0 = x;
    x0(3) = S(0);
    CHECK(std::abs(ell.margin(x0) - CoulombCone<S>{a, mu}.margin(Vector3<S>(x0.template head<3>()))) <= tol);
    inside += ell.is_inside(x) ? 1 : 0;
  }
  CHECK(inside > 700);
  CHECK(scope.allocations() == 0);
}

TEST_CASE_TEMPLATE("Soft finger: margins by hand", S, double, float) {
  // mu = 0.5, mu_t = 0.01 m, f_n = 4, |f_t| = 1.2, m = 0.016:
  // rho = sqrt((1.2/0.5)^2 + (0.016/0.01)^2) = sqrt(5.76 + 2.56) = 2.8844; margin 0.5 (4 - 2.8844)
  // = 0.5578 N, relative 1 - 2.8844/4 = 0.2789. Linear: rho = 2.4 + 1.6 = 4: margin 0, relative 0.
  // Decoupled: rho = 2.4: margin 0.8, relative 0.4.
  Eigen::Matrix<S, 4, 1> x;
  x << S(1.2), S(0), S(4), S(0.016);
  const Vector3<S> z = Vector3<S>::UnitZ();
  const SoftFingerCone<S> ell{z, S(0.5), S(0.01)};
  CHECK(ell.margin(x) == doctest::Approx(0.5 * (4.0 - std::sqrt(8.32))).epsilon(1e-5));
  CHECK(ell.relative_margin(x) == doctest::Approx(1.0 - std::sqrt(8.32) / 4.0).epsilon(1e-5));
  const SoftFingerCone<S, SoftFingerNorm::Linear> lin{z, S(0.5), S(0.01)};
  CHECK(std::abs(lin.margin(x)) <= S(1e-5));
  const SoftFingerCone<S, SoftFingerNorm::Decoupled> dec{z, S(0.5), S(0.01)};
  CHECK(dec.margin(x) == doctest::Approx(0.8).epsilon(1e-5));
  CHECK(dec.relative_margin(x) == doctest::Approx(0.4).epsilon(1e-5));
  CHECK(ell.moment(x) == S(0.016));
}

TEST_CASE_TEMPLATE("Soft finger: projection is idempotent, inside and satisfies Moreau", S, double, float) {
  std::mt19937 rng(62);
  grip_test::NoHeapScope scope;
  check_projection<S, SoftFingerNorm::Elliptic>(rng);
  check_projection<S, SoftFingerNorm::Linear>(rng);
  check_projection<S, SoftFingerNorm::Decoupled>(rng);
  CHECK(scope.allocations() == 0);
}

TEST_CASE("Soft finger: elliptic projection beats a brute-force search over the boundary") {
  // Boundary points s (a + mu cos(psi) u(phi), mu_t sin(psi)), grid over s, phi, psi.
  std::mt19937 rng(63);
  grip_test::Uniform u01(0.0, 1.0);
  int tested = 0;
  for (int k = 0; k < 40 && tested < 12; ++k) {
    const Vector3<double> a = grip_test::random_unit(rng);
    const double mu = 0.3 + u01(rng), mt = 0.3 * u01(rng) + 0.05;  // mu_t large: torsion matters
    const SoftFingerCone<double> c{a, mu, mt};
    const Vector3<double> f = grip_test::random_force(rng, a, -2.0, 3.0, 4.0);
    const auto x = soft_vec<double>(f, 2.0 * u01(rng) - 1.0);
    if (c.is_inside(x)) continue;
    ++tested;
    const Vector3<double> t1 = grip_test::random_tangent(rng, a), t2 = a.cross(t1);
    const double xn = f.dot(a), x1 = f.dot(t1), x2 = f.dot(t2), xm = x(3);
    double best2 = x.squaredNorm();
    for (int ip = 0; ip < 90; ++ip) {
      const double cp = std::cos(6.283185307179586 * ip / 90), sp = std::sin(6.283185307179586 * ip / 90);
      for (int iq = 0; iq < 90; ++iq) {
        const double cq = std::cos(6.283185307179586 * iq / 90), sq = std::sin(6.283185307179586 * iq / 90);
        for (int is = 0; is <= 150; ++is) {
          const double s = 6.0 * is / 150;
          const double d0 = xn - s, d1 = x1 - s * mu * cq * cp, d2 = x2 - s * mu * cq * sp, d3 = xm - s * mt * sq;
          best2 = std::min(best2, d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3);
        }
      }
    }
    const double d = (x - c.project(x)).norm(), best = std::sqrt(best2);
    CHECK(d <= best + 1e-9);
    CHECK(d >= best - 0.15);
  }
  CHECK(tested >= 10);
}

TEST_CASE_TEMPLATE("Soft finger: duals by the definition", S, double, float) {
  // y in the dual iff y.x >= 0 for x on the cone's generators (f_n = 1 boundary), sampled.
  std::mt19937 rng(64);
  grip_test::Uniform u01(0.0, 1.0);
  double cs[180], sn[180];
  for (int i = 0; i < 180; ++i) {
    cs[i] = std::cos(6.283185307179586 * i / 180);
    sn[i] = std::sin(6.283185307179586 * i / 180);
  }
  for (int k = 0; k < 1000; ++k) {
    const Vector3<double> ad = grip_test::random_unit(rng);
    const double mu = 0.3 + u01(rng), mt = 0.3 + u01(rng);
    const SoftFingerCone<S> ell{ad.cast<S>(), S(mu), S(mt)};
    const SoftFingerCone<S, SoftFingerNorm::Linear> lin{ad.cast<S>(), S(mu), S(mt)};
    CHECK(ell.dual().mu == doctest::Approx(1.0 / mu).epsilon(1e-5));
    CHECK(ell.dual().mu_t == doctest::Approx(1.0 / mt).epsilon(1e-5));
    const Vector3<double> t1 = grip_test::random_tangent(rng, ad), t2 = ad.cross(t1);
    const Vector3<double> yf = grip_test::random_force(rng, ad, -1.0, 3.0, 3.0);
    const double ym = 4.0 * u01(rng) - 2.0, yn = yf.dot(ad), y1 = yf.dot(t1), y2 = yf.dot(t2);
    double worst_ell = 1e300, worst_lin = 1e300;
    for (int ip = 0; ip < 180; ++ip) {
      const double cp = cs[ip], sp = sn[ip];
      const double yt = y1 * cp + y2 * sp;
      // Linear cone generators: (1, mu u, 0), (1, 0, +-mu_t); the 2-D fan between them.
      worst_lin = std::min({worst_lin, yn + mu * yt, yn + mt * ym, yn - mt * ym});
      for (int iq = 0; iq < 180; ++iq) {
        const double cq = cs[iq], sq = sn[iq];
        worst_ell = std::min(worst_ell, yn + mu * cq * yt + mt * sq * ym);
      }
    }
    const auto y = soft_vec<S>(yf, ym);
    const S me = ell.dual().margin(y), ml = lin.dual().margin(y);
    if (std::abs(me) > S(0.03) * S(1 + y.norm())) CHECK((me > S(0)) == (worst_ell >= 0.0));
    if (std::abs(ml) > S(0.03) * S(1 + y.norm())) CHECK((ml > S(0)) == (worst_lin >= 0.0));
  }
}

TEST_CASE_TEMPLATE("Soft finger: degenerate coefficients and bad input", S, double, float) {
  const S floor = cone_margin_floor<S>();
  const Vector3<S> z = Vector3<S>::UnitZ();
  using V = Eigen::Matrix<S, 4, 1>;
  grip_test::NoHeapScope scope;
  // mu_t = 0: no torsion; the force part is Coulomb's.
  const SoftFingerCone<S> no_torsion{z, S(0.5), S(0)};
  CHECK(no_torsion.is_inside(V(S(1), S(0), S(4), S(0))));
  CHECK(no_torsion.margin(V(S(1), S(0), S(4), S(0))) == doctest::Approx(1.0));
  CHECK_FALSE(no_torsion.is_inside(V(S(1), S(0), S(4), S(0.001))));
  CHECK(no_torsion.relative_margin(V(S(1), S(0), S(4), S(0.001))) == floor);
  CHECK(no_torsion.project(V(S(1), S(0), S(4), S(0.3))) == V(S(1), S(0), S(4), S(0)));
  // mu = 0: torsion only: |m| <= mu_t f_n, f_t = 0.
  const SoftFingerCone<S> torsion_only{z, S(0), S(0.01)};
  CHECK(torsion_only.is_inside(V(S(0), S(0), S(4), S(0.03))));
  CHECK(torsion_only.margin(V(S(0), S(0), S(4), S(0.03))) == S(0));
  CHECK_FALSE(torsion_only.is_inside(V(S(0), S(0), S(4), S(0.05))));
  CHECK_FALSE(torsion_only.is_inside(V(S(0.1), S(0), S(4), S(0))));
  const V pr = torsion_only.project(V(S(3), S(0), S(4), S(0.03)));
  CHECK(pr == V(S(0), S(0), S(4), S(0.03)));
  // Both zero: the ray.
  const SoftFingerCone<S, SoftFingerNorm::Linear> ray{z, S(0), S(0)};
  CHECK(ray.is_inside(V(S(0), S(0), S(2), S(0))));
  CHECK_FALSE(ray.is_inside(V(S(0), S(0), S(2), S(0.01))));
  CHECK_FALSE(ray.is_inside(V(S(0), S(0), S(-2), S(0))));
  CHECK(ray.project(V(S(1), S(2), S(2), S(3))) == V(S(0), S(0), S(2), S(0)));
  CHECK(ray.dual().mu == cone_half_space_mu<S>());
  // Zero, zero normal part, NaN.
  const SoftFingerCone<S> c{z, S(0.5), S(0.01)};
  CHECK(c.is_inside(V::Zero()));
  CHECK(c.margin(V::Zero()) == S(0));
  CHECK(c.relative_margin(V::Zero()) == S(0));
  CHECK(c.project(V::Zero()) == V::Zero());
  CHECK_FALSE(c.is_inside(V(S(1), S(0), S(0), S(0))));
  CHECK(c.relative_margin(V(S(1), S(0), S(0), S(0))) == floor);
  const S nan = std::numeric_limits<S>::quiet_NaN();
  CHECK_FALSE(c.is_inside(V(S(0), S(0), S(1), nan)));
  CHECK(c.margin(V(S(0), S(0), S(1), nan)) == floor);
  CHECK(c.project(V(S(0), S(0), S(1), nan)) == V::Zero());
  CHECK(scope.allocations() == 0);
}
