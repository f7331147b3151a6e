#pragma once
/// \file
/// The friction-constrained frame solver for the haptic pipeline: solve_constrained,
/// warm-started from the previous frame's multipliers.

#include "grip/core/types.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/solution.hpp"
#include "grip/solve/solve_constrained.hpp"

namespace grip {

/// Frame solver policy: the exact optimum of F2 with every force inside its exact cone
/// (solve_constrained). From the second frame on, each solve is warm-started from the
/// multipliers of the previous Ok or IterationLimit solve (contacts change little between
/// 1 kHz frames; the multipliers are a 6-vector, so they carry over whatever contacts come and
/// go). `settings` are solve_constrained's (tolerances, iteration bound).
template <class Scalar>
struct ConstrainedFrameSolver {
  static constexpr bool enforces_cones = true;  ///< forces come back inside their exact cones
  ConstrainedSettings<Scalar> settings{};      ///< tolerances and bounds of every solve
  Wrench<Scalar> warm{Wrench<Scalar>::Zero()};  ///< multipliers of the last usable solve
  bool has_warm{false};                         ///< whether `warm` holds any

  /// min F2 s.t. G x + w_ext = 0 and x_i in K_i for this frame's grasp (GraspT::ScalarType must be
  /// Scalar), warm-started when `has_warm`; keeps the multipliers of an Ok or IterationLimit solve
  /// with finite multipliers for the next frame, else clears `has_warm`. Returns the Solution part.
  template <class GraspT>
  Solution<GraspT> operator()(const GraspT& grasp, const Wrench<Scalar>& w_ext) {
    const ConstrainedSolution<GraspT> sol =
        has_warm ? solve_constrained(grasp, w_ext, settings, warm) : solve_constrained(grasp, w_ext, settings);
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
