#pragma once
/// \file
/// Solving the small symmetric positive semi-definite 6x6 systems M y = r that every
/// range-space method in grip reduces to (M = G W^-1 G^T).

#include <cmath>

#include <Eigen/Eigenvalues>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// Solves M y = r for a symmetric positive semi-definite 6x6 M by Cholesky with Jacobi
/// scaling (D M D has a unit diagonal, D = diag(M_jj^-1/2), so the rank test does not
/// depend on units: forces in N, moments in N m).
///
/// Ok: y solves the system. Singular: a scaled pivot fell below
/// ScalarTraits::rank_tolerance (or a diagonal entry is not positive); y is then the
/// minimum-norm least-squares solution M^+ r, with eigenvalues below rank_tolerance times
/// the largest treated as zero. y is finite in both cases.
template <class Scalar>
Status solve_symmetric_6x6(const Matrix6<Scalar>& m, const Wrench<Scalar>& r, Wrench<Scalar>& y) {
  const Scalar tol = ScalarTraits<Scalar>::rank_tolerance;
  Wrench<Scalar> d;
  bool ok = true;
  for (int j = 0; j < 6; ++j) {
    const Scalar mjj = m(j, j);
    if (!(mjj > Scalar(0)) || !std::isfinite(mjj)) {
      ok = false;
      break;
    }
    d(j) = Scalar(1) / std::sqrt(mjj);
  }
  if (ok) {
    // Cholesky of the scaled matrix, lower triangle in place.
    Matrix6<Scalar> l = d.asDiagonal() * m * d.asDiagonal();
    for (int j = 0; j < 6 && ok; ++j) {
      Scalar p = l(j, j);
      for (int k = 0; k < j; ++k) p -= l(j, k) * l(j, k);
      if (!(p > tol)) {
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
  // Rank deficient: minimum-norm least squares through the eigen-decomposition.
  y.setZero();
  if (!m.allFinite()) return Status::Singular;
  Eigen::SelfAdjointEigenSolver<Matrix6<Scalar>> eig(m);
  const auto& ev = eig.eigenvalues();
  const Scalar cut = tol * ev.cwiseAbs().maxCoeff();
  const Wrench<Scalar> q = eig.eigenvectors().transpose() * r;
  Wrench<Scalar> u = Wrench<Scalar>::Zero();
  for (int k = 0; k < 6; ++k)
    if (ev(k) > cut && ev(k) > Scalar(0)) u(k) = q(k) / ev(k);
  y = eig.eigenvectors() * u;
  if (!y.allFinite()) y.setZero();
  return Status::Singular;
}

}  // namespace grip
