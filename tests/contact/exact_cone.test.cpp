// CompressionCone (frictionless point) and the ExactCone trait that maps models to cones.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include <grip/contact/exact_cone.hpp>
#include <grip/contact/pyramid_cone.hpp>

#include "support/allocation_counter.hpp"
#include "support/random.hpp"

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
// measure(x) must report what the separate calls report, for any cone policy.
template <class Cone>
void check_measure(std::mt19937& rng, const Cone& cone) {
  using S = typename Cone::ScalarType;
  grip_test::Normal n01(0.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    typename Cone::Vector x;
    for (int i = 0; i < Cone::dim; ++i) x(i) = S(2.0 * n01(rng));
    if (Cone::dim == 4) x(3) *= S(0.01);
    const ConeMeasure<S> m = cone.measure(x);
    const S tol = S(10) * (std::is_same<S, float>::value ? S(1e-5) : S(1e-13)) * (S(1) + x.norm());
    CHECK(std::abs(m.margin - cone.margin(x)) <= tol);
    CHECK((m.margin >= S(0)) == cone.is_inside(x));
    CHECK(std::abs(m.relative_margin - cone.relative_margin(x)) <= tol * (S(1) + std::abs(m.relative_margin)));
    CHECK(std::abs(m.normal_force - cone.normal_part(x)) <= tol);
    CHECK((m.tangential_force - cone.tangential_part(x)).norm() <= tol);
    CHECK(std::abs(m.tangential_norm - cone.tangential_norm(x)) <= tol);
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
  check_measure(rng, CoulombCone<S>{a, S(0.7)});
  check_measure(rng, PyramidCone<6, S>(a, S(0.7)));
  check_measure(rng, PyramidCone<4, S, PyramidFit::Circumscribed>(a, S(0.7), 1));
  check_measure(rng, SoftFingerCone<S>{a, S(0.7), S(0.01)});
  check_measure(rng, SoftFingerCone<S, SoftFingerNorm::Linear>{a, S(0.7), S(0.01)});
  check_measure(rng, SoftFingerCone<S, SoftFingerNorm::Decoupled>{a, S(0), S(0.01)});
  check_measure(rng, CompressionCone<S>{a});
  CHECK(scope.allocations() == 0);
}
