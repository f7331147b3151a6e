#pragma once
/// \file
/// Solving the small symmetric positive semi-definite 6x6 systems M y = r that every
/// range-space method in grip reduces to (M = G W^-1 G^T).

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// Solves M y = r for a symmetric positive semi-definite 6x6 M = G W^-1 G^T by Cholesky on
/// the unit-free matrix A = D M D, D = diag(1, 1, 1, 1/L, 1/L, 1/L), where `length` L (m) is a
/// characteristic lever arm of the grasp (e.g. the weighted RMS of |r_i|): force and moment rows
/// of A then have comparable size, so the rank test does not depend on units, and round-off
/// in a row that is zero in exact arithmetic (moments of contacts whose normals all pass
/// through the centre) is not mistaken for information, as row-by-row scaling would.
///
/// Ok: y solves the system. Singular: a pivot fell below ScalarTraits::rank_tolerance times
/// the largest diagonal entry of A (or L is not positive); y = D u is then given by the
/// minimum-norm least-squares solution u = A^+ D r, so |D (M y - r)| is smallest, with
/// eigenvalues of A below rank_tolerance times the largest treated as zero. y is finite.
template <class Scalar>
Status solve_symmetric_6x6(const Matrix6<Scalar>& m, const Wrench<Scalar>& r, Wrench<Scalar>& y,
                           Scalar length = Scalar(1)) {
  const Scalar tol = ScalarTraits<Scalar>::rank_tolerance;
  Wrench<Scalar> d;
  d << Scalar(1), Scalar(1), Scalar(1), Scalar(1) / length, Scalar(1) / length, Scalar(1) / length;
  bool ok = length > Scalar(0) && std::isfinite(length) && d.allFinite();
  Scalar ref(0);
  if (ok) {
    for (int j = 0; j < 6; ++j) ref = std::max(ref, m(j, j) * d(j) * d(j));
    ok = ref > Scalar(0) && std::isfinite(ref);
  }
  if (ok) {
    // Cholesky of the scaled matrix, lower triangle in place.
    Matrix6<Scalar> l = d.asDiagonal() * m * d.asDiagonal();
    const Scalar min_pivot = tol * ref;
    for (int j = 0; j < 6 && ok; ++j) {
      Scalar p = l(j, j);
      for (int k = 0; k < j; ++k) p -= l(j, k) * l(j, k);
      if (!(p > min_pivot)) {
        ok = false;
        break;
      }
      p = std::sqrt(p);
      l(j, j) = p;
      for (int i = j + 1; i < 6; ++i) {
        Scalar s = l(i, j);
        for (int k = 0; k < j; ++k) s -= l(i, k) * l(j, k);
        l(i, j) = s / p;
      }
    }
    if (ok) {
      Wrench<Scalar> z = d.cwiseProduct(r);
      for (int i = 0; i < 6; ++i) {  // forward: L z = D r
        for (int k = 0; k < i; ++k) z(i) -= l(i, k) * z(k);
        z(i) /= l(i, i);
      }
      for (int i = 5; i >= 0; --i) {  // backward: L^T u = z
        for (int k = i + 1; k < 6; ++k) z(i) -= l(k, i) * z(k);
        z(i) /= l(i, i);
      }
      y = d.cwiseProduct(z);
      if (y.allFinite()) return Status::Ok;
    }
  }
  // Rank deficient: minimum-norm least squares on the scaled system A u = D r, y = D u, so that
  // D (M y - r) is as small as possible.
  y.setZero();
  if (!ok && !(length > Scalar(0) && std::isfinite(length))) d.setOnes();
  const Matrix6<Scalar> a = d.asDiagonal() * m * d.asDiagonal();
  if (!a.allFinite()) return Status::Singular;
  Eigen::SelfAdjointEigenSolver<Matrix6<Scalar>> eig(a);
  const auto& ev = eig.eigenvalues();
  const Scalar cut = tol * ev.cwiseAbs().maxCoeff();
  const Wrench<Scalar> q = eig.eigenvectors().transpose() * d.cwiseProduct(r);
  Wrench<Scalar> u = Wrench<Scalar>::Zero();
  for (int k = 0; k < 6; ++k)
    if (ev(k) > cut && ev(k) > Scalar(0)) u(k) = q(k) / ev(k);
  y = d.cwiseProduct(eig.eigenvectors() * u);
  if (!y.allFinite()) y.setZero();
  return Status::Singular;
}

}  // namespace grip
