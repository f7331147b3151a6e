#pragma once
// Tolerances derived from round-off, one formula for double and float:
//
//   tolerance = k * u * condition * scale
//
// - u: the unit round-off of the scalar type, 2^-53 for double and 2^-24 for float;
// - condition: the condition number of the problem the checked value comes from (1 for a value
//   computed straight from the data, grasp_condition() for the forces of a solve);
// - scale: the size of the data it is computed from, in the unit of the check (newtons for a
//   force, newton-metres for a moment);
// - k: a count of rounding errors, stated with its reason beside each check.
// A float tolerance is then the double one times 2^29, never a fudge factor of its own, and a
// check fails when its error grows with anything but round-off.
#include <Eigen/Dense>
#include <limits>

namespace grip_test {

/// u: the largest relative error of one correctly rounded operation in S.
template <class S>
constexpr double unit_roundoff() {
  return static_cast<double>(std::numeric_limits<S>::epsilon()) / 2.0;
}

/// k * u * condition * scale (see the top of this file).
template <class S>
double roundoff(double k, double condition, double scale) {
  return k * unit_roundoff<S>() * condition * scale;
}

/// The 2-norm condition number of G W^-1/2, the grasp matrix with each contact's columns divided
/// by the square root of its weight, computed in double from the grasp's own G and weights:
/// what the least-squares forces' error grows with (the range-space and KKT solves factor its
/// square, G W^-1 G^T, and keep the error of the forces near u times this number; the
/// constrained solve's steps are of the same kind). Infinite when G has rank below 6.
template <class GraspT>
double grasp_condition(const GraspT& g) {
  constexpr int dim = GraspT::dim;
  const Eigen::MatrixXd full = g.grasp_matrix().template cast<double>();
  Eigen::MatrixXd scaled = full;
  for (int i = 0; i < g.size(); ++i)
    scaled.middleCols(i * dim, dim) *= std::sqrt(static_cast<double>(g.inverse_weight(i)));
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled);
  const auto& s = svd.singularValues();
  if (s.size() < 6 || !(s(5) > 0.0)) return std::numeric_limits<double>::infinity();
  return s(0) / s(5);
}

}  // namespace grip_test
