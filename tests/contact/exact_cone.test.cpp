// CompressionCone (frictionless point) and the ExactCone trait that maps models to cones.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include <grip/contact/exact_cone.hpp>
#include <grip/contact/pyramid_cone.hpp>

#include "support/allocation_counter.hpp"
#include "support/constants.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

template struct grip::CompressionCone<double>;
template struct grip::CompressionCone<float>;

static_assert(std::is_same<ExactConeT<FrictionlessPoint, double>, CompressionCone<double>>::value, "");
static_assert(std::is_same<ExactConeT<HardFinger, float>, CoulombCone<float>>::value, "");
static_assert(std::is_same<ExactConeT<SoftFinger, double>, SoftFingerCone<double, SoftFingerNorm::Elliptic>>::value,
              "");
static_assert(ExactConeT<FrictionlessPoint, double>::dim == FrictionlessPoint::dim, "");
static_assert(ExactConeT<HardFinger, double>::dim == HardFinger::dim, "");
static_assert(ExactConeT<SoftFinger, double>::dim == SoftFinger::dim, "");

TEST_CASE_TEMPLATE("Compression cone: push only, self-dual, defined answers", S, double, float) {
  using V = Eigen::Matrix<S, 1, 1>;
  Contact<S> c;
  c.normal = Vector3<S>::UnitX();
  const auto cone = ExactConeT<FrictionlessPoint, S>::from_contact(c);
  grip_test::NoHeapScope scope;
  CHECK(cone.normal == c.normal);
  CHECK(cone.is_inside(V(S(2))));
  CHECK(cone.margin(V(S(2))) == S(2));
  CHECK(cone.relative_margin(V(S(2))) == S(1));
  CHECK(cone.is_inside(V(S(0))));
  CHECK(cone.margin(V(S(0))) == S(0));
  CHECK(cone.relative_margin(V(S(0))) == S(0));
  CHECK_FALSE(cone.is_inside(V(S(-1))));
  CHECK(cone.margin(V(S(-1))) == S(-1));
  CHECK(cone.relative_margin(V(S(-1))) == cone_margin_floor<S>());
  CHECK(cone.project(V(S(-1)))(0) == S(0));
  CHECK(cone.project(V(S(3)))(0) == S(3));
  CHECK(cone.normal_part(V(S(3))) == S(3));
  CHECK(cone.tangential_norm(V(S(3))) == S(0));
  const V nan(std::numeric_limits<S>::quiet_NaN());
  CHECK_FALSE(cone.is_inside(nan));
  CHECK(cone.margin(nan) == cone_margin_floor<S>());
  CHECK(cone.project(nan)(0) == S(0));
  // Self-dual: y >= 0 iff y x >= 0 for all x >= 0.
  CHECK(cone.dual().is_inside(V(S(1))));
  CHECK_FALSE(cone.dual().is_inside(V(S(-1))));
  CHECK(scope.allocations() == 0);
}

TEST_CASE_TEMPLATE("ExactCone: from_contact reads the contact's coefficients", S, double, float) {
  Contact<S> c;
  c.normal = Vector3<S>::UnitY();
  c.friction = S(0.8);
  c.torsional_friction = S(0.02);
  const auto hard = ExactConeT<HardFinger, S>::from_contact(c);
  CHECK(hard.mu == S(0.8));
  const auto soft = ExactConeT<SoftFinger, S>::from_contact(c);
  CHECK(soft.mu == S(0.8));
  CHECK(soft.mu_t == S(0.02));
  CHECK(soft.normal == c.normal);
}

namespace {
// The sizes a cone's margin is made of (support/tolerance.hpp), per newton of the force's parts:
// margin = C - L with C = c f_n the capacity and L the load, whose terms are at most
// cf |f| + ct |f| + cq |m| (m the moment of a soft finger, divided by mu_t in the load).
struct MarginTerms {
  double cf, ct, cq, c;
};

// measure(x) must report what the separate calls report, for any cone policy.
template <class Cone>
void check_measure(std::mt19937& rng, const Cone& cone, const MarginTerms& mt) {
  using S = typename Cone::ScalarType;
  grip_test::Normal n01(0.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    typename Cone::Vector x;
    for (int i = 0; i < Cone::dim; ++i) x(i) = S(2.0 * n01(rng));
    if (Cone::dim == 4) x(3) *= S(0.01);
    const ConeMeasure<S> m = cone.measure(x);
    // Tolerances from round-off (support/tolerance.hpp), condition 1: the two evaluations do the
    // same arithmetic, and differ only where the compiler rounds differently (FMA contraction,
    // the order of a sum), so each value differs by at most twice one evaluation's rounding.
    // With F = |f| (the first 3 coordinates) and |a| = 1: f_n = a.f takes 3 roundings of F;
    // f_t = f - f_n a 2 more and f_n's (5); |f_t| 3 more (8); the margin's combination and
    // difference about 4 more of its terms G = (cf + ct) F + cq |m| (12). Twice each: k = 6,
    // 10, 16 and 24.
    constexpr int nf = Cone::dim == 1 ? 1 : 3;  // the force's coordinates
    const double F = double(x.template head<nf>().norm()),
                 q = Cone::dim == 4 ? double(std::abs(x(Cone::dim - 1))) : 0.0;
    const double G = (mt.cf + mt.ct) * F + mt.cq * q;
    const double tol_n = grip_test::roundoff<S>(6, 1, F), tol_t = grip_test::roundoff<S>(10, 1, F);
    const double tol_tn = grip_test::roundoff<S>(16, 1, F), tol_m = grip_test::roundoff<S>(24, 1, G);
    const double d_margin = std::abs(double(m.margin) - double(cone.margin(x)));
    const double d_rel = std::abs(double(m.relative_margin) - double(cone.relative_margin(x)));
    const double d_n = std::abs(double(m.normal_force) - double(cone.normal_part(x)));
    const double d_t = double((m.tangential_force - cone.tangential_part(x)).norm());
    const double d_tn = std::abs(double(m.tangential_norm) - double(cone.tangential_norm(x)));
    CHECK(d_margin <= tol_m);
    CHECK((m.margin >= S(0)) == cone.is_inside(x));
    // The relative margin 1 - L / C, C = c f_n: dL / C + (L / C) dC / C, each of L and C within
    // the margin's 24 roundings of G: the condition G / C (1 + |1 - rel|). For f_n <= 0 both
    // give the same convention (0 or cone_margin_floor()) exactly.
    const double rel = double(m.relative_margin), cap = mt.c * double(m.normal_force);
    const double tol_rel = m.normal_force > S(0) ? grip_test::roundoff<S>(24, (1 + std::abs(1 - rel)) / cap, G) : 0.0;
    CHECK(d_rel <= tol_rel);
    CHECK(d_n <= tol_n);
    CHECK(d_t <= tol_t);
    CHECK(d_tn <= tol_tn);
  }
  typename Cone::Vector bad = Cone::Vector::Zero();
  bad(0) = std::numeric_limits<S>::quiet_NaN();
  CHECK(cone.measure(bad).margin == cone_margin_floor<S>());
  CHECK(cone.measure(bad).relative_margin == cone_margin_floor<S>());
}
}  // namespace

TEST_CASE_TEMPLATE("measure(x) agrees with the separate calls for every cone", S, double, float) {
  std::mt19937 rng(91);
  const Vector3<S> a = Vector3<S>(S(1), S(2), S(2)) / S(3);
  grip_test::NoHeapScope scope;
  // MarginTerms: Coulomb mu f_n - |f_t|; the pyramids r f_n - (the largest face load, at most
  // |f_t|), r = mu cos(pi / 6) inscribed, mu circumscribed; the soft fingers mu (f_n - L(|f_t| /
  // mu, |m| / mu_t)), and with mu = 0 f_n - |f_t| - |m| / mu_t; the compression cone f_n.
  const double mu = double(S(0.7)), mu_t = double(S(0.01)), r6 = mu * std::cos(grip_test::pi / 6);
  check_measure(rng, CoulombCone<S>{a, S(0.7)}, {mu, 1, 0, mu});
  check_measure(rng, PyramidCone<6, S>(a, S(0.7)), {r6, 1, 0, r6});
  check_measure(rng, PyramidCone<4, S, PyramidFit::Circumscribed>(a, S(0.7), 1), {mu, 1, 0, mu});
  check_measure(rng, SoftFingerCone<S>{a, S(0.7), S(0.01)}, {mu, 1, mu / mu_t, mu});
  check_measure(rng, SoftFingerCone<S, SoftFingerNorm::Linear>{a, S(0.7), S(0.01)}, {mu, 1, mu / mu_t, mu});
  check_measure(rng, SoftFingerCone<S, SoftFingerNorm::Decoupled>{a, S(0), S(0.01)}, {1, 1, 1 / mu_t, 1});
  check_measure(rng, CompressionCone<S>{a}, {1, 0, 0, 1});
  CHECK(scope.allocations() == 0);
}
