#pragma once
/// \file
/// Tolerances and limits, specialised per scalar type (float vs double).

namespace grip {

/// Numerical tolerances of grip for one scalar type. Specialised for float and double;
/// a user type may specialise it too. Like Eigen's NumTraits, it is the place for per-scalar
/// values: an algorithm whose numbers depend on the precision reads these members (or settings
/// whose defaults come from them) rather than testing std::is_same<Scalar, float>.
template <class Scalar>
struct ScalarTraits;

/// Tolerances for double.
template <>
struct ScalarTraits<double> {
  /// False: double's defaults (tight tolerances, no float-specific safeguards) apply to the
  /// iterative solvers' settings (e.g. ConstrainedSettings).
  static constexpr bool is_single_precision = false;
  /// Largest accepted |normal| - 1 (a normal must be unit length within this).
  static constexpr double normal_tolerance = 1e-6;
  /// Relative pivot below which a (Jacobi-scaled) matrix is treated as rank deficient.
  static constexpr double rank_tolerance = 1e-10;
  /// Largest accepted magnitude of any input coordinate (m, N, N m, weight).
  static constexpr double max_magnitude = 1e15;
  /// Smallest accepted objective weight (weights are divided by).
  static constexpr double min_weight = 1e-12;
  /// Default relative tolerance for comparisons in tests and iterative solvers.
  static constexpr double default_tolerance = 1e-9;
  /// solve_constrained's relative tolerance of an Ok answer (ConstrainedSettings::tolerance).
  static constexpr double constrained_tolerance = 1e-12;
  /// The interior-point method's relative tolerance before solve_constrained's Newton refinement.
  static constexpr double interior_tolerance = 1e-7;
  /// The interior-point method's gap where Newton's refinement takes over (solve_constrained;
  /// the residuals to its square).
  static constexpr double interior_handover = 1e-3;
  /// The interior-point method's boundary test (solve_constrained): an iterate that meets the
  /// residual tolerances with tau below this fraction of its largest value is the answer.
  static constexpr double interior_boundary = 1e-3;
  /// The interior-point method's neighbourhood of the central path: a cone pair whose
  /// smallest scaled eigenvalue squared falls below this fraction of mu is centred toward it
  /// (Wright 1997, ch. 5, the wide neighbourhood N_-inf).
  static constexpr double interior_neighbourhood = 0.1;
  /// The fraction of the largest step into the cones that the interior-point method takes: near
  /// the boundary float computes that step to a few of its last places only.
  static constexpr double interior_step = 0.99;
  /// The relative slack of an infeasibility certificate (ConstrainedSettings::certificate_tolerance).
  static constexpr double certificate_tolerance = 1e-5;
  /// The relative weight of F2 in the least-residual problem (ConstrainedSettings::least_residual_weight).
  static constexpr double least_residual_weight = 1e-6;
  /// The contact search's certified depth tolerance (m; ContactSettings::refine_tolerance):
  /// far below a micrometre, so that the contact's point and normal are those of the deepest
  /// point to the precision docs/collision.md states.
  static constexpr double contact_tolerance = 1e-12;
  /// The scalar the offline conic analyses compute in (analysis/detail/conic_analysis.hpp).
  using Wide = double;
};

/// Tolerances for float.
template <>
struct ScalarTraits<float> {
  /// True: the iterative solvers' settings (e.g. ConstrainedSettings) take their single-precision
  /// defaults: looser tolerances, and the safeguards that round-off at 1e-7 needs.
  static constexpr bool is_single_precision = true;
  /// Largest accepted |normal| - 1 (a normal must be unit length within this).
  static constexpr float normal_tolerance = 1e-4f;
  /// Relative pivot below which a (Jacobi-scaled) matrix is treated as rank deficient.
  static constexpr float rank_tolerance = 1e-5f;
  /// Largest accepted magnitude of any input coordinate (m, N, N m, weight).
  static constexpr float max_magnitude = 1e9f;
  /// Smallest accepted objective weight (weights are divided by).
  static constexpr float min_weight = 1e-6f;
  /// Default relative tolerance for comparisons in tests and iterative solvers.
  static constexpr float default_tolerance = 1e-4f;
  /// solve_constrained's relative tolerance of an Ok answer (ConstrainedSettings::tolerance).
  static constexpr float constrained_tolerance = 1e-5f;
  /// The interior-point method's relative tolerance before solve_constrained's Newton refinement.
  static constexpr float interior_tolerance = 1e-3f;
  /// The interior-point method's gap where Newton's refinement takes over (solve_constrained;
  /// the residuals to its square).
  static constexpr float interior_handover = 1e-3f;
  /// The interior-point method's boundary test (solve_constrained): an iterate that meets the
  /// residual tolerances with tau below this fraction of its largest value is the answer.
  static constexpr float interior_boundary = 1e-3f;
  /// The interior-point method's neighbourhood of the central path: a cone pair whose
  /// smallest scaled eigenvalue squared falls below this fraction of mu is centred toward it
  /// (Wright 1997, ch. 5, the wide neighbourhood N_-inf).
  static constexpr float interior_neighbourhood = 0.1f;
  /// The fraction of the largest step into the cones that the interior-point method takes: near
  /// the boundary float computes that step to a few of its last places only.
  static constexpr float interior_step = 0.95f;
  /// The relative slack of an infeasibility certificate (ConstrainedSettings::certificate_tolerance).
  static constexpr float certificate_tolerance = 1e-4f;
  /// The relative weight of F2 in the least-residual problem (ConstrainedSettings::least_residual_weight).
  static constexpr float least_residual_weight = 1e-4f;
  /// The contact search's certified depth tolerance (m; ContactSettings::refine_tolerance): a
  /// few units in the last place of coordinates of a few decimetres.
  static constexpr float contact_tolerance = 1e-7f;
  /// The scalar the offline conic analyses compute in (analysis/detail/conic_analysis.hpp):
  /// double. Their interior-point systems grow ill-conditioned as the iterates near the cones'
  /// boundaries, and in float the dual residual then stalls above the default tolerance.
  using Wide = double;
};

}  // namespace grip
