#pragma once
/// \file
/// Solving the small symmetric positive semi-definite 6x6 systems M y = r that every
/// range-space method in grip reduces to (M = G W^-1 G^T).

#include <algorithm>
#include <utility>
#include <cmath>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

namespace detail {

/// Eigen-decomposition of a symmetric 6x6 matrix by cyclic Jacobi rotations: a = v diag(ev) v^T.
/// Fixed size, no heap, no static state (Eigen's SelfAdjointEigenSolver pulls dynamic-size
/// Householder code and an allocator into a microcontroller build). At most `max_sweeps`
/// sweeps of 15 rotations; converges quadratically, typically in 6 to 8 sweeps.
template <class Scalar>
void symmetric_eigen_6x6(Matrix6<Scalar> a, Wrench<Scalar>& ev, Matrix6<Scalar>& v, int max_sweeps = 30) {
  v.setIdentity();
  const Scalar eps = Eigen::NumTraits<Scalar>::epsilon();
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    Scalar off(0), diag(0);
    for (int p = 0; p < 6; ++p) {
      diag += a(p, p) * a(p, p);
      for (int q = p + 1; q < 6; ++q) off += a(p, q) * a(p, q);
    }
    if (!(off > eps * eps * diag)) break;  // off-diagonal part negligible (or NaN)
    for (int p = 0; p < 5; ++p) {
      for (int q = p + 1; q < 6; ++q) {
        const Scalar apq = a(p, q);
        if (apq == Scalar(0)) continue;
        // The rotation that zeroes a(p, q): t = tan(phi) is the smaller root of
        // t^2 + 2 theta t - 1 = 0, theta = (a_qq - a_pp) / (2 a_pq).
        const Scalar theta = (a(q, q) - a(p, p)) / (Scalar(2) * apq);
        const Scalar at = std::abs(theta);
        Scalar t = at > Scalar(1) / eps ? Scalar(1) / (Scalar(2) * at) : Scalar(1) / (at + std::sqrt(at * at + Scalar(1)));
        if (theta < Scalar(0)) t = -t;
        const Scalar c = Scalar(1) / std::sqrt(t * t + Scalar(1)), sn = t * c;
        for (int k = 0; k < 6; ++k) {  // a <- a J (columns p, q)
          const Scalar akp = a(k, p), akq = a(k, q);
          a(k, p) = c * akp - sn * akq;
          a(k, q) = sn * akp + c * akq;
        }
        for (int k = 0; k < 6; ++k) {  // a <- J^T a (rows p, q)
          const Scalar apk = a(p, k), aqk = a(q, k);
          a(p, k) = c * apk - sn * aqk;
          a(q, k) = sn * apk + c * aqk;
        }
        for (int k = 0; k < 6; ++k) {  // v <- v J
          const Scalar vkp = v(k, p), vkq = v(k, q);
          v(k, p) = c * vkp - sn * vkq;
          v(k, q) = sn * vkp + c * vkq;
        }
      }
    }
  }
  ev = a.diagonal();
}

}  // namespace detail

/// Solves M y = r for a symmetric positive semi-definite 6x6 M = G W^-1 G^T by Cholesky on
/// the unit-free matrix A = D M D, D = diag(1, 1, 1, 1/L, 1/L, 1/L), where `length` L (m) is a
/// characteristic lever arm of the grasp (e.g. the weighted RMS of |r_i|): force and moment rows
/// of A then have comparable size, so the rank test does not depend on units, and round-off
/// in a row that is zero in exact arithmetic (moments of contacts whose normals all pass
/// through the centre) is not mistaken for information, as row-by-row scaling would.
///
/// Cholesky with diagonal pivoting (rank revealing, like LAPACK's pstrf) on A.
/// Ok: y solves the system. Singular: the largest remaining pivot fell below
/// ScalarTraits::rank_tolerance times the largest diagonal entry of A (or L is not positive); y = D u is then given by the
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
    // Cholesky with diagonal pivoting (rank revealing): P^T A P = L L^T, lower triangle of l.
    // Each step takes the largest remaining diagonal; when even that is below
    // rank_tolerance * max diag(A), the rest of A is numerically zero: rank < 6.
    Matrix6<Scalar> l = d.asDiagonal() * m * d.asDiagonal();
    const Scalar min_pivot = tol * ref;
    int perm[6] = {0, 1, 2, 3, 4, 5};
    for (int j = 0; j < 6 && ok; ++j) {
      int p = j;
      for (int i = j + 1; i < 6; ++i)
        if (l(i, i) > l(p, p)) p = i;
      if (!(l(p, p) > min_pivot)) {
        ok = false;
        break;
      }
      if (p != j) {  // symmetric swap of rows and columns j, p
        l.row(j).swap(l.row(p));
        l.col(j).swap(l.col(p));
        std::swap(perm[j], perm[p]);
      }
      const Scalar pivot = std::sqrt(l(j, j));
      l(j, j) = pivot;
      for (int i = j + 1; i < 6; ++i) l(i, j) /= pivot;
      for (int k = j + 1; k < 6; ++k)  // update the trailing block (both triangles, for the swaps)
        for (int i = k; i < 6; ++i) {
          l(i, k) -= l(i, j) * l(k, j);
          l(k, i) = l(i, k);
        }
    }
    if (ok) {
      Wrench<Scalar> z;
      for (int i = 0; i < 6; ++i) z(i) = d(perm[i]) * r(perm[i]);  // z = P^T D r
      for (int i = 0; i < 6; ++i) {  // forward: L w = z
        for (int k = 0; k < i; ++k) z(i) -= l(i, k) * z(k);
        z(i) /= l(i, i);
      }
      for (int i = 5; i >= 0; --i) {  // backward: L^T u = w
        for (int k = i + 1; k < 6; ++k) z(i) -= l(k, i) * z(k);
        z(i) /= l(i, i);
      }
      for (int i = 0; i < 6; ++i) y(perm[i]) = d(perm[i]) * z(i);  // y = D P u
      if (y.allFinite()) return Status::Ok;
    }
  }
  // Rank deficient: minimum-norm least squares on the scaled system A u = D r, y = D u, so that
  // D (M y - r) is as small as possible.
  y.setZero();
  if (!ok && !(length > Scalar(0) && std::isfinite(length))) d.setOnes();
  const Matrix6<Scalar> a = d.asDiagonal() * m * d.asDiagonal();
  if (!a.allFinite()) return Status::Singular;
  Wrench<Scalar> ev;
  Matrix6<Scalar> vecs;
  detail::symmetric_eigen_6x6(a, ev, vecs);
  const Scalar cut = tol * ev.cwiseAbs().maxCoeff();
  const Wrench<Scalar> q = vecs.transpose() * d.cwiseProduct(r);
  Wrench<Scalar> u = Wrench<Scalar>::Zero();
  for (int k = 0; k < 6; ++k)
    if (ev(k) > cut && ev(k) > Scalar(0)) u(k) = q(k) / ev(k);
  y = d.cwiseProduct(vecs * u);
  if (!y.allFinite()) y.setZero();
  return Status::Singular;
}

}  // namespace grip
