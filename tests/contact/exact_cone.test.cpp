// CompressionCone (frictionless point) and the ExactCone trait that maps models to cones.
#include <doctest/doctest.h>

#include <limits>
#include <type_traits>

#include <grip/contact/exact_cone.hpp>

#include "support/allocation_counter.hpp"

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
