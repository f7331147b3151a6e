#pragma once
/// \file
/// The exact friction cone of each contact model, as a trait.

#include "grip/contact/contact_model.hpp"
#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/normal_cone.hpp"
#include "grip/contact/soft_finger_cone.hpp"

namespace grip {

/// `ExactCone<Model, Scalar>::type` is the cone a contact of `Model` must keep its unknown in:
/// FrictionlessPoint -> CompressionCone, HardFinger -> CoulombCone (eq. 4-5),
/// SoftFinger -> SoftFingerCone (Elliptic). Every cone type has `dim == Model::dim`,
/// `Vector` (Eigen::Matrix<Scalar, dim, 1>), `from_contact(c)`, `is_inside(x)`, `margin(x)`,
/// `relative_margin(x)`, `measure(x)` (all of these in one pass, a ConeMeasure), `project(x)`,
/// `dual()`, `normal_part(x)`, `tangential_part(x)`,
/// `tangential_norm(x)`; so monitors and solvers take any of them as a policy.
template <class Model, class Scalar>
struct ExactCone;

/// A frictionless point keeps its normal force magnitude in {x >= 0}.
template <class Scalar>
struct ExactCone<FrictionlessPoint, Scalar> {
  using type = CompressionCone<Scalar>;  ///< the compression-only cone x >= 0
};
/// A hard finger keeps its force in the Coulomb cone |f_t| <= mu f_n.
template <class Scalar>
struct ExactCone<HardFinger, Scalar> {
  using type = CoulombCone<Scalar>;  ///< the Coulomb cone of eq. 4-5
};
/// A soft finger keeps its (f, m) in the elliptic soft-finger cone.
template <class Scalar>
struct ExactCone<SoftFinger, Scalar> {
  using type = SoftFingerCone<Scalar, SoftFingerNorm::Elliptic>;  ///< t^2/mu^2 + m^2/mu_t^2 <= f_n^2
};

/// Shorthand for `typename ExactCone<Model, Scalar>::type`.
template <class Model, class Scalar>
using ExactConeT = typename ExactCone<Model, Scalar>::type;

}  // namespace grip
