#pragma once
/// \file
/// Settings of solve_constrained: tolerances (float-appropriate defaults) and bounds.

#include <type_traits>

namespace grip {

/// Tolerances and bounds of solve_constrained for scalar type Scalar.
///
/// The defaults depend on Scalar (double: tolerance 1e-12; float: 1e-5) and are what the
/// tests hold the solver to. Every member must be finite and positive (iteration counts >= 1)
/// or the solver answers InvalidInput.
template <class Scalar>
struct ConstrainedSettings {
  /// True when Scalar is float: selects the float defaults below.
  static constexpr bool is_float = std::is_same<Scalar, float>::value;

  /// Relative equilibrium tolerance: Ok when |G x + w_ext| <= tolerance * (|w_ext| + sum_i |x_i|)
  /// and the duality gap |lambda.(G x + w_ext)| <= gap_tolerance * F2(x) (or the residual is at
  /// round-off, 16 eps times that scale).
  Scalar tolerance{is_float ? Scalar(1e-5f) : Scalar(1e-12)};
  /// Relative duality-gap tolerance (see tolerance); the objective is then within about this
  /// relative error of the optimum.
  Scalar gap_tolerance{is_float ? Scalar(1e-5f) : Scalar(1e-10)};
  /// Smallest Levenberg-Marquardt regularisation of the Jacobi-scaled 6x6 Newton matrix (the
  /// regularisation follows the residual down to it near the optimum).
  Scalar regularisation{is_float ? Scalar(1e-6f) : Scalar(1e-13)};
  /// Relative slack of the infeasibility certificate: a unit y is accepted when every G_i^T y
  /// lies in the dual cone up to certificate_tolerance * (1 + |r_i|) and y.w_ext exceeds
  /// certificate_tolerance * |w_ext| (float: a tenth of it, so that nearly feasible grasps,
  /// whose genuine certificates have small y.w_ext, are still decided).
  Scalar certificate_tolerance{is_float ? Scalar(2e-3f) : Scalar(1e-5)};
  /// Weight delta (relative to the largest Jacobi entry of G W^-1 G^T) of F2 in the
  /// least-residual problem min |G x + w_ext|^2/2 + delta F2(x)/2 over the cones, solved when
  /// the Newton iteration stalls, to decide infeasibility and give the closest forces.
  Scalar least_residual_weight{is_float ? Scalar(1e-6f) : Scalar(1e-12)};
  /// Bound on Newton iterations (each O(n)); the worst-case time is proportional to it.
  int max_iterations{60};
  /// Bound on step halvings per line search (each one more O(n) pass).
  int max_line_search{30};
};

}  // namespace grip
