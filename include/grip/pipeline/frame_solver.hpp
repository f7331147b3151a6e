#pragma once
/// \file
/// Solver policies for the haptic pipeline: one object per pipeline, called once per frame
/// (or a few times when contacts are dropped), holding whatever it carries between frames.

#include "grip/core/types.hpp"
#include "grip/solve/solution.hpp"
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

}  // namespace grip
