#pragma once
/// \file
/// Obstacle contacts as data, turned into spring-damper (penalty) forces on the object.

#include <cmath>

#include <Eigen/Geometry>

#include "grip/contact/contact.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// One contact between the object and an obstacle (a table, a wall), as the geometry
/// layer reports it. Same frame conventions as Contact: `point` is measured from the
/// object's centre of mass in world axes, `normal` is unit and points INTO the object
/// (the direction in which the obstacle pushes).
template <class Scalar>
struct PenaltyContact {
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};   ///< r (m), from the centre of mass
  Vector3<Scalar> normal{Vector3<Scalar>::Zero()};  ///< n, unit, INTO the object
  Scalar depth{0};                                  ///< interpenetration d (m); <= 0: touching or apart, no force
  Scalar depth_rate{0};                             ///< d' (m/s), > 0 while the object moves deeper into the obstacle
};

/// Spring-damper law of a penalty contact.
template <class Scalar>
struct PenaltyMaterial {
  Scalar stiffness{Scalar(2e4)};  ///< k (N/m), >= 0
  Scalar damping{Scalar(50)};     ///< c (N s/m), >= 0
};

/// Ok if the contact and material are finite, in range, with |normal| = 1 (within
/// ScalarTraits::normal_tolerance) and k, c >= 0; InvalidInput otherwise.
template <class Scalar>
Status validate(const PenaltyContact<Scalar>& c, const PenaltyMaterial<Scalar>& m) {
  if (!detail::all_in_range(c.point) || !detail::all_in_range(c.normal) || !detail::in_range(c.depth) ||
      !detail::in_range(c.depth_rate) || !detail::in_range(m.stiffness) || !detail::in_range(m.damping))
    return Status::InvalidInput;
  if (m.stiffness < Scalar(0) || m.damping < Scalar(0)) return Status::InvalidInput;
  if (!(std::abs(c.normal.squaredNorm() - Scalar(1)) <= Scalar(2) * ScalarTraits<Scalar>::normal_tolerance))
    return Status::InvalidInput;
  return Status::Ok;
}

/// The normal force magnitude (N) of one penalty contact: `max(0, k d + c d')` while
/// d > 0, else 0. The clamp keeps the obstacle from pulling the object back as it
/// separates (d' < 0). Assumes valid input (see validate()).
template <class Scalar>
Scalar penalty_force(const PenaltyContact<Scalar>& c, const PenaltyMaterial<Scalar>& m) {
  if (!(c.depth > Scalar(0))) return Scalar(0);
  const Scalar f = m.stiffness * c.depth + m.damping * c.depth_rate;
  return f > Scalar(0) ? f : Scalar(0);
}

/// The wrench `[f n; r x f n]` (N, N m about the centre of mass) one penalty contact
/// applies on the object, f = penalty_force(). Assumes valid input.
template <class Scalar>
Wrench<Scalar> penalty_wrench(const PenaltyContact<Scalar>& c, const PenaltyMaterial<Scalar>& m) {
  const Vector3<Scalar> f = penalty_force(c, m) * c.normal;
  // Fixed-size halves, not the comma initializer: g++ 12 -O3 with AVX2 reports a false
  // array-bounds warning on the initializer's dynamic-size blocks (packets of 4 over 3 values).
  Wrench<Scalar> w;
  w.template head<3>() = f;
  w.template tail<3>() = c.point.cross(f);
  return w;
}

}  // namespace grip
