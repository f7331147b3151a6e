#pragma once
/// \file
/// Solving the small symmetric positive semi-definite 6x6 systems M y = r that every
/// range-space method in grip reduces to (M = G W^-1 G^T).

#include <algorithm>
#include <cmath>
#include <utility>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

namespace detail {

/// LDL^T of a small symmetric N x N matrix `a` (full storage; the strict lower triangle is
/// overwritten by L, unit lower triangular) in the order given by `perm` (P^T A P = L D L^T,
/// perm[i] = the row of A that is row i of P^T A). With `pivot` true each step eliminates the largest
/// remaining diagonal entry, so |L| <= 1 and a pivot that is zero in exact arithmetic stays at
/// round-off size (rank revealing, like LAPACK's pstrf); `perm` is then filled in. With
/// `pivot` false `perm` must hold the identity and is kept. The diagonal of `a` keeps D and
/// `inv_d` receives 1 / D.
/// Returns false as soon as a pivot is not above `min_pivot` (or NaN). No square roots; one
/// division per pivot.
template <int N, class Scalar>
bool ldlt_factor(Scalar (&a)[N][N], Scalar (&inv_d)[N], int (&perm)[N], Scalar min_pivot, bool pivot) {
  for (int j = 0; j < N; ++j) {
    if (pivot) {
      int p = j;
      for (int i = j + 1; i < N; ++i)
        if (a[i][i] > a[p][p]) p = i;
      if (p != j) {  // symmetric swap of rows and columns j and p (L's finished rows move too)
        for (int k = 0; k < N; ++k) std::swap(a[j][k], a[p][k]);
        for (int k = 0; k < N; ++k) std::swap(a[k][j], a[k][p]);
        std::swap(perm[j], perm[p]);
      }
    }
    if (!(a[j][j] > min_pivot)) return false;
    const Scalar inv = Scalar(1) / a[j][j];
    inv_d[j] = inv;
    for (int i = j + 1; i < N; ++i) {  // trailing block -= w w^T / d_j, w = column j
      const Scalar lij = a[i][j] * inv;
      for (int k = j + 1; k <= i; ++k) {
        a[i][k] -= lij * a[k][j];
        if (pivot) a[k][i] = a[i][k];  // keep both triangles for later swaps
      }
    }
    for (int i = j + 1; i < N; ++i) a[i][j] *= inv;  // column j of L
  }
  return true;
}

/// Solves P L D L^T P^T x = b in place from ldlt_factor's output.
template <int N, class Scalar>
void ldlt_substitute(const Scalar (&a)[N][N], const Scalar (&inv_d)[N], const int (&perm)[N], Scalar (&x)[N]) {
  Scalar z[N];
  for (int i = 0; i < N; ++i) {  // L w = P^T b
    z[i] = x[perm[i]];
    for (int k = 0; k < i; ++k) z[i] -= a[i][k] * z[k];
  }
  for (int i = 0; i < N; ++i) z[i] *= inv_d[i];  // D v = w
  for (int i = N - 1; i >= 0; --i) {  // L^T u = v
    for (int k = i + 1; k < N; ++k) z[i] -= a[k][i] * z[k];
    x[perm[i]] = z[i];
  }
}

/// The LDL^T factorisation of a small symmetric positive semi-definite N x N matrix A whose
/// diagonal entries are at most `ref` > 0, kept for several solves (iterative refinement).
/// factor() succeeds when A is numerically of full rank: diagonally pivoted LDL^T
/// (ldlt_factor with pivoting) finds every pivot above tol * ref.
///
/// Fast path with the same verdict: the factorisation in natural order (no pivot search on the
/// critical path) is accepted when its pivots satisfy prod_j (d_j / ref) > tol. The pivots of
/// the pivoted factorisation multiply to the same det A and none exceeds ref (Schur complements
/// of a PSD matrix have smaller diagonals), so its smallest pivot is >= det A / ref^(N-1) >
/// tol * ref: it would accept too. Otherwise the pivoted factorisation decides.
template <int N, class Scalar>
struct SmallLdlt {
  Scalar f[N][N];  ///< L below the diagonal, D on it
  Scalar inv_d[N];  ///< 1 / D
  int perm[N];      ///< row i of P^T A is row perm[i] of A

  /// Factors A, written into `f` (full storage, both triangles) by `fill(f)`, which is called
  /// again if the pivoted factorisation is needed (no copy of A is kept: small stacks).
  /// False: rank deficient.
  template <class Fill>
  bool factor(const Fill& fill, Scalar ref, Scalar tol) {
    reset(fill);
    if (ldlt_factor<N>(f, inv_d, perm, Scalar(0), false)) {
      const Scalar inv_ref = Scalar(1) / ref;
      Scalar det_ratio(1);
      for (int j = 0; j < N; ++j) det_ratio *= f[j][j] * inv_ref;
      if (det_ratio > tol) return true;
    }
    reset(fill);
    return ldlt_factor<N>(f, inv_d, perm, tol * ref, true);
  }
  /// Factors the matrix `a` (full storage; not modified). False: rank deficient.
  bool factor(const Scalar (&a)[N][N], Scalar ref, Scalar tol) {
    return factor(
        [&a](Scalar (&out)[N][N]) {
          for (int i = 0; i < N; ++i)
            for (int k = 0; k < N; ++k) out[i][k] = a[i][k];
        },
        ref, tol);
  }
  /// Solves A x = b in place (x: b on entry), after a successful factor().
  void solve(Scalar (&x)[N]) const { ldlt_substitute<N>(f, inv_d, perm, x); }

 private:
  template <class Fill>
  void reset(const Fill& fill) {
    for (int i = 0; i < N; ++i) perm[i] = i;
    fill(f);
  }
};

/// Eigen-decomposition of a symmetric 6x6 matrix by cyclic Jacobi rotations: a = v diag(ev) v^T
/// (`a` is overwritten, its diagonal ends as ev: no copy, for small stacks).
/// Fixed size, no heap, no static state (Eigen's SelfAdjointEigenSolver pulls dynamic-size
/// Householder code and an allocator into a microcontroller build). At most `max_sweeps`
/// sweeps of 15 rotations; converges quadratically, typically in 6 to 8 sweeps.
template <class Scalar>
void symmetric_eigen_6x6(Matrix6<Scalar>& a, Wrench<Scalar>& ev, Matrix6<Scalar>& v, int max_sweeps = 30) {
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

/// symmetric_eigen_6x6 of a copy of `m`, with the eigenvalues in ascending order and the
/// eigenvectors (columns of v, orthonormal) in the same order, as Eigen's
/// SelfAdjointEigenSolver reports them.
template <class Scalar>
void symmetric_eigen_6x6_sorted(const Matrix6<Scalar>& m, Wrench<Scalar>& ev, Matrix6<Scalar>& v) {
  Matrix6<Scalar> a = m;
  symmetric_eigen_6x6(a, ev, v);
  for (int i = 0; i < 5; ++i) {  // selection sort: 6 entries
    int k = i;
    for (int j = i + 1; j < 6; ++j)
      if (ev(j) < ev(k)) k = j;
    if (k != i) {
      std::swap(ev(i), ev(k));
      v.col(i).swap(v.col(k));
    }
  }
}

/// True when a lever arm `length` L (m) can balance units: L > 0 and L, 1/L finite.
template <class Scalar>
bool lever_usable(Scalar length) {
  return length > Scalar(0) && std::isfinite(length) && std::isfinite(Scalar(1) / length);
}

/// The unit balance D = diag(1, 1, 1, 1/L, 1/L, 1/L) of a lever arm `length` L (m); the identity
/// when L is not usable (lever_usable).
template <class Scalar>
Wrench<Scalar> unit_balance(Scalar length) {
  Wrench<Scalar> d = Wrench<Scalar>::Ones();
  if (lever_usable(length)) d.template tail<3>().setConstant(Scalar(1) / length);
  return d;
}

/// The minimum-norm least-squares solver of A u = b for a symmetric positive semi-definite 6x6
/// A: A^+ from the eigen-decomposition, eigenvalues below ScalarTraits::rank_tolerance times the
/// largest counted as zero. Decomposed once, applied to any number of right-hand sides. A not
/// finite: every answer is zero.
template <class Scalar>
struct PseudoInverse6 {
  Wrench<Scalar> inv_ev{Wrench<Scalar>::Zero()};  ///< 1 / eigenvalue, 0 for those cut
  Matrix6<Scalar> vecs{Matrix6<Scalar>::Identity()};  ///< orthonormal eigenvectors (columns)

  explicit PseudoInverse6(Matrix6<Scalar> a) {
    if (!a.allFinite()) return;
    Wrench<Scalar> ev;
    symmetric_eigen_6x6(a, ev, vecs);
    const Scalar cut = ScalarTraits<Scalar>::rank_tolerance * ev.cwiseAbs().maxCoeff();
    for (int k = 0; k < 6; ++k)
      if (ev(k) > cut && ev(k) > Scalar(0)) inv_ev(k) = Scalar(1) / ev(k);
  }
  /// u = A^+ b; zero when not finite.
  Wrench<Scalar> apply(const Wrench<Scalar>& b) const {
    const Wrench<Scalar> u = vecs * inv_ev.cwiseProduct(vecs.transpose() * b);
    return u.allFinite() ? u : Wrench<Scalar>::Zero();
  }
};

/// The minimum-norm least-squares solution of M y = r on the unit-balanced scale: y = D u with
/// u = A^+ D r, A = D M D, D = diag(`d`) (PseudoInverse6). So |D (M y - r)| is smallest.
template <class Scalar>
void least_squares_6x6(const Matrix6<Scalar>& m, const Wrench<Scalar>& r, const Wrench<Scalar>& d, Wrench<Scalar>& y) {
  const PseudoInverse6<Scalar> pinv(d.asDiagonal() * m * d.asDiagonal());
  y = d.cwiseProduct(pinv.apply(d.cwiseProduct(r)));
  if (!y.allFinite()) y.setZero();
}

}  // namespace detail

/// Solves M y = r for a symmetric positive semi-definite 6x6 M = G W^-1 G^T by an LDL^T
/// factorisation on the unit-free matrix A = D M D, D = diag(1, 1, 1, 1/L, 1/L, 1/L), where `length` L (m) is a
/// characteristic lever arm of the grasp (e.g. the weighted RMS of |r_i|): force and moment rows
/// of A then have comparable size, so the rank test does not depend on units, and round-off
/// in a row that is zero in exact arithmetic (moments of contacts whose normals all pass
/// through the centre) is not mistaken for information, as row-by-row scaling would.
///
/// The factorisation pivots on the diagonal (rank revealing, like LAPACK's pstrf; see
/// detail::SmallLdlt). Ok: y solves the system. Singular: the largest remaining pivot fell below
/// ScalarTraits::rank_tolerance times the largest diagonal entry of A (or L is not positive); y = D u is then given by the
/// minimum-norm least-squares solution u = A^+ D r, so |D (M y - r)| is smallest, with
/// eigenvalues of A below rank_tolerance times the largest treated as zero. y is finite.
template <class Scalar>
Status solve_symmetric_6x6(const Matrix6<Scalar>& m, const Wrench<Scalar>& r, Wrench<Scalar>& y,
                           Scalar length = Scalar(1)) {
  const Scalar tol = ScalarTraits<Scalar>::rank_tolerance;
  const Wrench<Scalar> d = detail::unit_balance(length);
  if (detail::lever_usable(length)) {
    Scalar ref(0);
    for (int k = 0; k < 6; ++k) ref = std::max(ref, d(k) * m(k, k) * d(k));
    detail::SmallLdlt<6, Scalar> ldlt;
    const auto scaled = [&](Scalar (&a)[6][6]) {  // A = D M D
      for (int k = 0; k < 6; ++k)
        for (int i = 0; i < 6; ++i) a[i][k] = d(i) * m(i, k) * d(k);
    };
    if (ref > Scalar(0) && std::isfinite(ref) && ldlt.factor(scaled, ref, tol)) {
      Scalar x[6];
      for (int k = 0; k < 6; ++k) x[k] = d(k) * r(k);
      ldlt.solve(x);
      for (int i = 0; i < 6; ++i) y(i) = d(i) * x[i];
      if (y.allFinite()) return Status::Ok;
    }
  }
  // Rank deficient: minimum-norm least squares on the scaled system A u = D r, y = D u, so that
  // D (M y - r) is as small as possible.
  detail::least_squares_6x6(m, r, d, y);
  return Status::Singular;
}

}  // namespace grip
