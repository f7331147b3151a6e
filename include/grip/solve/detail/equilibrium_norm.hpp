#pragma once
/// \file
/// The norm in which solve_constrained weighs an equilibrium residual (namespace grip::detail):
/// moments in units of the grasp's longest lever arm, so that every test of the solver gives
/// the same verdict at every unit of length.

#include <cmath>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// |w|_L = |(f, m / L)| for a wrench w = (f, m), with L = max_i |r_i| the grasp's longest lever
/// arm (1 m when every contact sits within 1 / ScalarTraits::max_magnitude of the reference
/// point: then no contact makes a moment worth the name). A moment of the contacts is at
/// most L times their force, so |w|_L weighs both parts alike, and a change of the unit of
/// length leaves it unchanged (up to the unit of force).
///
/// Multipliers and certificates pair with wrenches (lambda.w is a power-like scalar, the same
/// in every unit), so they take the dual norm |y|_L* = |(y_f, L y_m)|, and |y.w| <= |y|_L* |w|_L.
///
/// Invariant: length > 0 and finite; inverse = 1 / length.
template <class S>
struct EquilibriumNorm {
  S length{1};   ///< L (m)
  S inverse{1};  ///< 1 / L

  /// L of a grasp (see the struct).
  template <class GraspT>
  static EquilibriumNorm of(const GraspT& grasp) {
    S l2 = S(0);
    for (int i = 0; i < grasp.size(); ++i) {
      const S r2 = grasp.contact(i).position.squaredNorm();
      l2 = r2 > l2 ? r2 : l2;
    }
    const S l = std::sqrt(l2);
    EquilibriumNorm n;
    if (l > S(1) / S(ScalarTraits<S>::max_magnitude)) {
      n.length = l;
      n.inverse = S(1) / l;
    }
    return n;
  }

  /// T w = (f, m / L): a wrench in the units of the norm.
  Wrench<S> to_units(const Wrench<S>& w) const {
    Wrench<S> out = w;
    out.template tail<3>() *= inverse;
    return out;
  }
  /// The diagonal of T = diag(1, 1, 1, 1/L, 1/L, 1/L).
  Wrench<S> weights() const {
    Wrench<S> t = Wrench<S>::Ones();
    t.template tail<3>().setConstant(inverse);
    return t;
  }
  /// |w|_L (no temporary: the frame's Newton iteration takes it several times per pass).
  S operator()(const Wrench<S>& w) const {
    return std::sqrt(w.template head<3>().squaredNorm() + inverse * inverse * w.template tail<3>().squaredNorm());
  }
  /// |y|_L* = |(y_f, L y_m)|, the dual norm of multipliers and certificates.
  S dual(const Wrench<S>& y) const {
    return std::sqrt(y.template head<3>().squaredNorm() + length * length * y.template tail<3>().squaredNorm());
  }
};

}  // namespace detail
}  // namespace grip
