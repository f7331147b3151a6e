#pragma once
/// \file
/// Basic vocabulary types of grip: sizes, vectors, wrenches.

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace grip {

/// Marks a size that is known only at run time (bounded by a compile-time maximum).
/// Equal to Eigen::Dynamic so the two can be mixed freely.
constexpr int Dynamic = Eigen::Dynamic;

/// A 3-vector in the common world-aligned frame (metres or newtons).
template <class Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;

/// A 3x3 matrix in the common frame.
template <class Scalar>
using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;

/// A 6x6 matrix acting on wrenches ([force; moment] rows).
template <class Scalar>
using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;

/// A wrench `[force (N); moment (N m)]`, moment about the object's reference point.
template <class Scalar>
using Wrench = Eigen::Matrix<Scalar, 6, 1>;

/// `count * per_item` at compile time, or Dynamic if count is Dynamic.
constexpr int times_or_dynamic(int count, int per_item) { return count == Dynamic ? Dynamic : count * per_item; }

/// `offset + count` at compile time, or Dynamic if count is Dynamic.
constexpr int plus_or_dynamic(int offset, int count) { return count == Dynamic ? Dynamic : offset + count; }

/// The skew-symmetric matrix `[r]x` with `[r]x v = r x v` (the paper's R_i, eq. 3).
template <class Scalar>
Matrix3<Scalar> skew(const Vector3<Scalar>& r) {
  Matrix3<Scalar> m;
  m << Scalar(0), -r.z(), r.y(),  //
      r.z(), Scalar(0), -r.x(),   //
      -r.y(), r.x(), Scalar(0);
  return m;
}

namespace detail {

/// The Euclidean norm of v without the underflow of a plain sum of squares (internal: the
/// solvers' residual; may change). Entries near the scalar's smallest normal value (valid
/// inputs, e.g. a denormal squeeze) square to zero, so
/// v.norm() can report 0 for a vector of length 1e-43. The sum of squares is used when it is
/// safely above the underflow range (each entry it loses weighs below eps of it) and finite;
/// otherwise the entries scaled by the largest magnitude (NaN stays NaN, infinity infinity).
/// No heap, and a frame of a few scalars (Eigen's stableNorm() copies a block expression into a
/// 4096-entry buffer on the stack). v is a vector.
template <class Derived>
typename Derived::RealScalar stable_norm(const Eigen::MatrixBase<Derived>& v) {
  using S = typename Derived::RealScalar;
  const S s2 = v.squaredNorm();
  constexpr S safe = S(64) * std::numeric_limits<S>::min() / std::numeric_limits<S>::epsilon();
  if (s2 >= safe && s2 <= std::numeric_limits<S>::max()) return std::sqrt(s2);
  if (std::isnan(s2)) return s2;
  S scale(0);
  for (Eigen::Index i = 0; i < v.size(); ++i) scale = std::max(scale, std::abs(v.derived().coeff(i)));
  if (scale == S(0) || !std::isfinite(scale)) return scale;
  S sum(0);
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const S t = v.derived().coeff(i) / scale;
    sum += t * t;
  }
  return scale * std::sqrt(sum);
}

/// a <- D a D with D = diag(d), in place (the same products, in the same order, as
/// d.asDiagonal() * a * d.asDiagonal(), without the second 6x6 matrix on the stack).
template <class Scalar>
void scale_symmetric(Matrix6<Scalar>& a, const Wrench<Scalar>& d) {
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) a(i, j) = d(i) * a(i, j) * d(j);
}

}  // namespace detail

}  // namespace grip
