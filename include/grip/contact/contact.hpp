#pragma once
/// \file
/// One contact between a finger (or phalanx) and the grasped object.

#include <cmath>
#include <limits>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// One contact point, in grip's conventions (docs/conventions.md).
///
/// Invariants checked by validate() (and by every Grasp and solver that takes it):
/// all fields finite and within ScalarTraits::max_magnitude (max_normal_force may also be
/// +infinity); |normal| = 1 within ScalarTraits::normal_tolerance; friction,
/// torsional_friction, squeeze >= 0; weight >= ScalarTraits::min_weight; max_normal_force > 0.
template <class Scalar>
struct Contact {
  Vector3<Scalar> position{Vector3<Scalar>::Zero()};  ///< r_i (m), from the object's centre of mass.
  Vector3<Scalar> normal{Vector3<Scalar>::Zero()};    ///< a_i, unit, pointing INTO the object.
  Scalar friction{0};                                 ///< Coulomb coefficient mu_i (dimensionless), >= 0.
  Scalar torsional_friction{0};                       ///< Soft-finger torsional coefficient mu_t (m): |m| <= mu_t f_n.
  Scalar squeeze{0};                                  ///< s_i (N), the squeezing force magnitude of eq. 7-8, >= 0.
  Scalar weight{1};                                   ///< w_i > 0, the weight of this contact in F2.
  /// The largest normal force f_n the contact can apply (N): a finger's strength or a device
  /// channel's limit, kept by solve_constrained (the cone truncated at f_n <= max_normal_force);
  /// +infinity (the default) for none. The other solvers do not read it.
  Scalar max_normal_force{std::numeric_limits<Scalar>::infinity()};
};

namespace detail {
template <class Scalar>
bool in_range(Scalar x) {
  return std::isfinite(x) && std::abs(x) <= ScalarTraits<Scalar>::max_magnitude;
}
template <class Derived>
bool all_in_range(const Eigen::MatrixBase<Derived>& v) {
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!in_range(v(i))) return false;
  return true;
}
}  // namespace detail

/// Ok if `c` satisfies the invariants of Contact, InvalidInput otherwise.
template <class Scalar>
Status validate(const Contact<Scalar>& c) {
  using T = ScalarTraits<Scalar>;
  if (!detail::all_in_range(c.position) || !detail::all_in_range(c.normal)) return Status::InvalidInput;
  if (!detail::in_range(c.friction) || !detail::in_range(c.torsional_friction) || !detail::in_range(c.squeeze) ||
      !detail::in_range(c.weight))
    return Status::InvalidInput;
  if (c.friction < Scalar(0) || c.torsional_friction < Scalar(0) || c.squeeze < Scalar(0) || c.weight < T::min_weight)
    return Status::InvalidInput;
  if (!(c.max_normal_force > Scalar(0)) ||
      (!detail::in_range(c.max_normal_force) && c.max_normal_force != std::numeric_limits<Scalar>::infinity()))
    return Status::InvalidInput;
  const Scalar n2 = c.normal.squaredNorm();
  // |n|^2 - 1 ~ 2 (|n| - 1): compare against twice the tolerance.
  if (!(std::abs(n2 - Scalar(1)) <= Scalar(2) * T::normal_tolerance)) return Status::InvalidInput;
  return Status::Ok;
}

/// Ok if the wrench is finite and within ScalarTraits::max_magnitude, InvalidInput otherwise.
template <class Scalar>
Status validate(const Wrench<Scalar>& w) {
  return detail::all_in_range(w) ? Status::Ok : Status::InvalidInput;
}

}  // namespace grip
