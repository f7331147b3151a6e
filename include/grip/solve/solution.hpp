#pragma once
/// \file
/// The result type shared by every grip solver.

#include <limits>

#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// What a solver returns for a grasp of type GraspT.
///
/// Invariant: every number is finite whatever the status. On InvalidInput `forces` and
/// `multipliers` are zero and `residual` is the largest finite Scalar.
template <class GraspT>
struct Solution {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;
  /// Contact unknowns x = (x_1, ..., x_n), grasp.unknowns() values, in grip's order (docs/conventions.md)
  /// (hard finger: f_i in N, the force ON the object; the hand feels -f_i).
  typename GraspT::ForceVector forces;
  /// Lagrange multipliers lambda (6) of the equilibrium rows: W (x - t) = G^T lambda.
  Wrench<Scalar> multipliers{Wrench<Scalar>::Zero()};
  /// Outcome; see each solver for what the numbers mean under each status.
  Status status{Status::InvalidInput};
  /// Equilibrium residual |G x + w_ext|_2 (N and N m mixed, as the paper's eq. 3).
  Scalar residual{std::numeric_limits<Scalar>::max()};
  /// Iterations used: 0 for the direct solvers.
  int iterations{0};

  /// True when status == Status::Ok.
  bool ok() const { return status == Status::Ok; }
};

}  // namespace grip
