#pragma once
/// \file
/// How a frame's forces are solved: the frame solver policies of the haptic pipeline. One
/// object per pipeline, called once per solve, holding whatever it carries between frames. A
/// policy provides
///
///     static constexpr bool enforces_cones;
///     template <class GraspT>
///     Solution<GraspT> operator()(const GraspT& grasp, const Wrench<Scalar>& w_ext);
///
/// enforces_cones true promises forces inside the cones, a separating contact's force exactly
/// zero and the others the answer for the grasp without it: the pipeline then solves each
/// frame once. False: the pipeline drops separating contacts and solves again (a few solves
/// in a frame).
///
/// - RangeSpaceFrameSolver: the equality-constrained optimum of F2, O(n) (the default);
/// - KktFrameSolver: the same optimum by the paper's section 5 method, O(n^3) (a baseline);
/// - ConstrainedFrameSolver: the optimum with every force inside its exact cone (and below its
///   contact's max_normal_force), warm-started from the previous frame.

#include "grip/contact/contact.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_constrained.hpp"
#include "grip/solve/solve_kkt.hpp"
#include "grip/solve/solve_range_space.hpp"

namespace grip {

/// The equality-constrained optimum of F2 (no friction constraints): solve_range_space, O(n).
/// The pipeline's monitor then checks the cones and drops separating contacts.
struct RangeSpaceFrameSolver {
  /// Whether the solver keeps forces inside the friction cones itself.
  static constexpr bool enforces_cones = false;
  /// min F2 s.t. G x + w_ext = 0 for this frame's grasp.
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext) {
    return solve_range_space(grasp, w_ext);
  }
};

/// The paper's section 5 method (Gaussian elimination on H): same optimum as
/// RangeSpaceFrameSolver, O(n^3); a baseline for benchmarks.
struct KktFrameSolver {
  /// Whether the solver keeps forces inside the friction cones itself.
  static constexpr bool enforces_cones = false;
  /// min F2 s.t. G x + w_ext = 0 for this frame's grasp, by solve_kkt.
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext) {
    return solve_kkt(grasp, w_ext);
  }
};

/// The exact optimum of F2 with every force inside its exact cone and below its contact's
/// max_normal_force (solve_constrained). From the second frame on, each solve is warm-started
/// from the previous solve: the multipliers of an Ok or IterationLimit one, the certificate of an
/// Infeasible one (contacts change little between 1 kHz frames, and a slip lasts many; both are
/// 6-vectors, so they carry over whatever contacts come and go). Every solve is bounded by its settings (docs/solve.md:
/// at most settings.max_iterations interior-point iterations and 2 settings.newton_passes Newton passes), a grasp that
/// slips included: no deadline of its own is needed.
template <class Scalar>
struct ConstrainedFrameSolver {
  /// Forces come back inside their exact cones, a separating one at the apex (zero): one solve a frame.
  static constexpr bool enforces_cones = true;
  /// Tolerances and bounds of every solve: solve_constrained's defaults.
  ConstrainedSettings<Scalar> settings{};
  /// The next solve's warm start: the last solve's multipliers (Ok or IterationLimit) or
  /// certificate (Infeasible), each when within ScalarTraits::max_magnitude (what
  /// solve_constrained accepts); nothing before the first frame.
  ConstrainedWarmStart<Scalar> warm{};
  int passes{0};      ///< passes over the contacts of the last solve (ConstrainedSolution::passes)
  int iterations{0};  ///< interior-point iterations of the last solve (0: the fast path or Newton answered)

  /// min F2 s.t. G x + w_ext = 0 and x_i in K_i for this frame's grasp (GraspT::ScalarType must be
  /// Scalar), warm-started from `warm`. Keeps in `warm` for the next frame the multipliers of an
  /// Ok or IterationLimit solve and the certificate of an Infeasible one, each when within
  /// range (a warm start out of range would make the next solve InvalidInput), and clears the
  /// other. Returns the Solution part.
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<Scalar>& w_ext) {
    const ConstrainedSolution<GraspT> sol = solve_constrained(grasp, w_ext, settings, warm);
    passes = sol.passes;
    iterations = sol.iterations;
    warm.has_multipliers =
        (sol.status == Status::Ok || sol.status == Status::IterationLimit) && detail::all_in_range(sol.multipliers);
    if (warm.has_multipliers) warm.multipliers = sol.multipliers;
    warm.has_certificate = sol.status == Status::Infeasible && detail::all_in_range(sol.certificate);
    if (warm.has_certificate) warm.certificate = sol.certificate;
    return sol;
  }
};

}  // namespace grip
