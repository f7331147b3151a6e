#pragma once
/// \file
/// Settings of solve_constrained: its tolerances and bounds (the method: docs/solve.md). The
/// per-scalar defaults come from ScalarTraits.

#include <cmath>

#include "grip/core/scalar_traits.hpp"

namespace grip {

/// Tolerances and bounds of solve_constrained for scalar type Scalar. An aggregate: set members by
/// name after default construction. Reals must be finite and > 0 (least_residual_weight < 1,
/// tolerances < 1), counts >= 0 (max_iterations >= 1), or the solver answers InvalidInput.
template <class Scalar>
struct ConstrainedSettings {
  /// Ok when |G x + w_ext|_L <= tolerance (|w_ext|_L + |x| + max_i s_i) (docs/solve.md).
  Scalar tolerance{ScalarTraits<Scalar>::constrained_tolerance};
  /// Infeasible when y.w_ext > 0 and every G_i^T y is within certificate_tolerance (y.w_ext) / |w_ext|_L of K_i^*.
  Scalar certificate_tolerance{ScalarTraits<Scalar>::certificate_tolerance};
  /// delta / (largest diagonal entry of G W^-1 G^T in |.|_L's units): Infeasible forces minimise |r|_L^2/2 + delta F2.
  Scalar least_residual_weight{ScalarTraits<Scalar>::least_residual_weight};
  /// Interior-point iterations of a solve, both problems together (three O(n) passes each): the deadline.
  int max_iterations{40};
  /// Newton passes of the warm start and of the refinement, each (one O(n) pass and a 6x6 solve each).
  int newton_passes{8};
};

namespace detail {

/// True when every member of `s` is in its documented range (see ConstrainedSettings).
template <class Scalar>
bool valid_settings(const ConstrainedSettings<Scalar>& s) {
  const auto in_unit = [](Scalar v) { return std::isfinite(v) && v > Scalar(0) && v < Scalar(1); };
  return in_unit(s.tolerance) && in_unit(s.certificate_tolerance) && in_unit(s.least_residual_weight) &&
         s.max_iterations >= 1 && s.newton_passes >= 0;
}

}  // namespace detail

}  // namespace grip
