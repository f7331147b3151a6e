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
/// - ConstrainedFrameSolver: the optimum with every force inside its exact cone,
///   warm-started from the previous frame, within a deadline of passes per solve.

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

/// The exact optimum of F2 with every force inside its exact cone (solve_constrained), within
/// a deadline. From the second frame on, each solve is warm-started from the multipliers of
/// the previous Ok or IterationLimit solve (contacts change little between 1 kHz frames; the
/// multipliers are a 6-vector, so they carry over whatever contacts come and go). `settings`
/// are solve_constrained's, with one difference: a real-time deadline of
/// `default_max_passes` passes per solve, so that a frame whose grasp slips costs a bounded
/// time (a solve cut short answers IterationLimit with forces in their cones, and the next
/// frame goes on from its multipliers). For the exact answer at any cost, set
/// settings.max_passes = std::numeric_limits<int>::max().
template <class Scalar>
struct ConstrainedFrameSolver {
  /// Forces come back inside their exact cones, a separating one at the apex (zero): one solve a frame.
  static constexpr bool enforces_cones = true;
  /// The default deadline of every solve (ConstrainedSettings::max_passes): 16 passes, which
  /// keeps the p99 of the haptic loop benchmark's slipping frames within two times the held
  /// frames' median (bench/RESULTS.md). A solve it cuts answers its best iterate, so the
  /// session it renders differs from one without a deadline (a few per cent of the frames
  /// change from held to slipping or back).
  static constexpr int default_max_passes = 16;
  /// Tolerances and bounds of every solve: solve_constrained's defaults, max_passes excepted.
  ConstrainedSettings<Scalar> settings{real_time_settings()};
  Wrench<Scalar> warm{Wrench<Scalar>::Zero()};  ///< multipliers of the last usable solve
  bool has_warm{false};                         ///< whether `warm` holds any
  int passes{0};  ///< passes over the contacts of the last solve (settings.max_passes bounds it)

  /// solve_constrained's default settings with max_passes = default_max_passes.
  static ConstrainedSettings<Scalar> real_time_settings() {
    ConstrainedSettings<Scalar> s;
    s.max_passes = default_max_passes;
    return s;
  }

  /// min F2 s.t. G x + w_ext = 0 and x_i in K_i for this frame's grasp (GraspT::ScalarType must be
  /// Scalar), warm-started when `has_warm`; keeps the multipliers of an Ok or IterationLimit solve
  /// with finite multipliers for the next frame, else clears `has_warm`. Returns the Solution part.
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<Scalar>& w_ext) {
    const ConstrainedSolution<GraspT> sol =
        has_warm ? solve_constrained(grasp, w_ext, settings, warm) : solve_constrained(grasp, w_ext, settings);
    passes = sol.passes;
    if ((sol.status == Status::Ok || sol.status == Status::IterationLimit) && sol.multipliers.allFinite()) {
      warm = sol.multipliers;
      has_warm = true;
    } else {
      has_warm = false;
    }
    return sol;
  }
};

}  // namespace grip
