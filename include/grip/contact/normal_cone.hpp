#pragma once
/// \file
/// The compression-only "cone" of a frictionless point contact.

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// The cone {x >= 0} of a FrictionlessPoint contact, whose unknown is the normal force
/// magnitude x (N; the force on the object is x a). A finger can push, never pull.
///
/// Margin (N): x itself (how much pull can still be added before the contact separates).
/// Relative margin: 1 for x > 0 (no friction is used), 0 for x = 0, cone_margin_floor() for
/// x < 0. Projection: max(x, 0). The cone is self-dual. Invalid input follows
/// cone_support.hpp (outside, margins cone_margin_floor(), projection 0).
template <class Scalar>
struct CompressionCone {
  using ScalarType = Scalar;                   ///< the scalar type (float or double)
  static constexpr int dim = 1;                ///< size of the contact unknown
  using Vector = Eigen::Matrix<Scalar, 1, 1>;  ///< the normal magnitude x (N)

  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};  ///< a, unit, into the object (for reports)

  /// The cone of contact c (only its normal is kept; friction plays no part).
  static CompressionCone from_contact(const Contact<Scalar>& c) { return CompressionCone{c.normal}; }

  /// f_n = x (N).
  Scalar normal_part(const Vector& x) const { return x(0); }
  /// f_t = 0: a frictionless contact has no tangential force.
  Vector3<Scalar> tangential_part(const Vector&) const { return Vector3<Scalar>::Zero(); }
  /// |f_t| = 0.
  Scalar tangential_norm(const Vector&) const { return Scalar(0); }

  /// True iff x >= 0 (false for invalid x).
  bool is_inside(const Vector& x) const { return margin(x) >= Scalar(0); }
  /// x (N), or cone_margin_floor() for invalid x.
  Scalar margin(const Vector& x) const { return detail::cone_input_valid(x) ? x(0) : cone_margin_floor<Scalar>(); }
  /// 1 (x > 0), 0 (x = 0), cone_margin_floor() (x < 0 or invalid).
  Scalar relative_margin(const Vector& x) const {
    if (!detail::cone_input_valid(x) || x(0) < Scalar(0)) return cone_margin_floor<Scalar>();
    return x(0) > Scalar(0) ? Scalar(1) : Scalar(0);
  }
  /// The monitor's slip test: margin(x) < -slack, for a valid x with f_n > 0 and slack >= 0 (N).
  bool slips(const Vector& x, Scalar slack) const { return margin(x) < -slack; }

  /// normal_part, margin and relative_margin of x in one pass (tangential parts are 0).
  ConeMeasure<Scalar> measure(const Vector& x) const {
    ConeMeasure<Scalar> m;
    if (!detail::cone_input_valid(x)) return m;
    m.normal_force = x(0);
    m.margin = margin(x);
    m.relative_margin = relative_margin(x);
    return m;
  }
  /// max(x, 0); 0 for invalid x.
  Vector project(const Vector& x) const {
    return Vector::Constant(detail::cone_input_valid(x) && x(0) > Scalar(0) ? x(0) : Scalar(0));
  }
  /// The dual of {x >= 0} in R is itself.
  CompressionCone dual() const { return *this; }
};

}  // namespace grip
