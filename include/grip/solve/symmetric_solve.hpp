#pragma once
/// \file
/// Solving the small symmetric positive semi-definite 6x6 systems M y = r that every
/// range-space method in grip reduces to (M = G W^-1 G^T), and the regularised 6x6 Newton
/// systems of solve_constrained (detail::solve_newton_6x6, detail::solve_floored_6x6).

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
/// perm[i] = the row of A that is row i of P^T A). With `Pivot` true each step eliminates the largest
/// remaining diagonal entry, so |L| <= 1 and a pivot that is zero in exact arithmetic stays at
/// round-off size (rank revealing, like LAPACK's pstrf); `perm` is then filled in. With
/// `Pivot` false `perm` must hold the identity and is kept. The diagonal of `a` keeps D and
/// `inv_d` receives 1 / D.
/// Returns false as soon as a pivot is not above `min_pivot` (or NaN). No square roots; one
/// division per pivot.
template <bool Pivot, int N, class Scalar>
bool ldlt_factor(Scalar (&a)[N][N], Scalar (&inv_d)[N], int (&perm)[N], Scalar min_pivot) {
  for (int j = 0; j < N; ++j) {
    if constexpr (Pivot) {
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
        if constexpr (Pivot) a[k][i] = a[i][k];  // keep both triangles for later swaps
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
  for (int i = N - 1; i >= 0; --i) {             // L^T u = v
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
  Scalar f[N][N];   ///< L below the diagonal, D on it
  Scalar inv_d[N];  ///< 1 / D
  int perm[N];      ///< row i of P^T A is row perm[i] of A

  /// Factors A, written into `f` (full storage, both triangles) by `fill(f)`, which is called
  /// again if the pivoted factorisation is needed (no copy of A is kept: small stacks).
  /// False: rank deficient.
  template <class Fill>
  bool factor(const Fill& fill, Scalar ref, Scalar tol) {
    reset(fill);
    if (ldlt_factor<false, N>(f, inv_d, perm, Scalar(0))) {
      const Scalar inv_ref = Scalar(1) / ref;
      Scalar det_ratio(1);
      for (int j = 0; j < N; ++j) det_ratio *= f[j][j] * inv_ref;
      if (det_ratio > tol) return true;
    }
    reset(fill);
    return ldlt_factor<true, N>(f, inv_d, perm, tol * ref);
  }
  /// The diagonally pivoted factorisation alone (no fast path) of the matrix `fill(f)` writes:
  /// false as soon as a pivot is not above `min_pivot` (ldlt_factor).
  template <class Fill>
  bool factor_pivoted(const Fill& fill, Scalar min_pivot) {
    reset(fill);
    return ldlt_factor<true, N>(f, inv_d, perm, min_pivot);
  }
  /// Factors the matrix `a` (full storage; not modified). False: rank deficient.
  bool factor(const Scalar (&a)[N][N], Scalar ref, Scalar tol) {
    return factor(
        [&a](Scalar(&out)[N][N]) {
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

/// The adjugate and determinant of a symmetric 3x3 matrix (adjugate3).
template <class Scalar>
struct Adjugate3 {
  Scalar c00, c01, c02, c11, c12, c22;  ///< the adjugate's upper triangle (it is symmetric)
  Scalar det;                           ///< the determinant, a00 c00 + a01 c01 + a02 c02
};

/// The adjugate (the transposed cofactor matrix, so A^-1 = adj(A) / det A) and determinant of
/// the symmetric 3x3 matrix A = [[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]]: six
/// products of differences and a first-row expansion, no division. Each entry is one
/// expression of fixed operation order, so its rounding does not depend on the caller.
template <class Scalar>
EIGEN_ALWAYS_INLINE Adjugate3<Scalar> adjugate3(Scalar a00, Scalar a01, Scalar a02, Scalar a11, Scalar a12,
                                                Scalar a22) {
  Adjugate3<Scalar> r;
  r.c00 = a11 * a22 - a12 * a12;
  r.c01 = a02 * a12 - a01 * a22;
  r.c02 = a01 * a12 - a02 * a11;
  r.c11 = a00 * a22 - a02 * a02;
  r.c12 = a01 * a02 - a00 * a12;
  r.c22 = a00 * a11 - a01 * a01;
  r.det = a00 * r.c00 + a01 * r.c01 + a02 * r.c02;
  return r;
}

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
        Scalar t =
            at > Scalar(1) / eps ? Scalar(1) / (Scalar(2) * at) : Scalar(1) / (at + std::sqrt(at * at + Scalar(1)));
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
  Wrench<Scalar> inv_ev{Wrench<Scalar>::Zero()};      ///< 1 / eigenvalue, 0 for those cut
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

/// Solves A y = b for a symmetric 6x6 A known to satisfy A >= floor I (here: a Jacobi-scaled
/// M + el I) by Cholesky with every pivot raised to at least `floor`, so that round-off can
/// neither break the factorisation nor hide the directions that only the floor keeps.
template <class Scalar>
Wrench<Scalar> solve_floored_6x6(const Matrix6<Scalar>& a, const Wrench<Scalar>& b, Scalar floor) {
  Matrix6<Scalar> l = a;
  Wrench<Scalar> inv;  // 1 / l(j, j): one division per pivot
  for (int j = 0; j < 6; ++j) {
    Scalar p = l(j, j);
    for (int k = 0; k < j; ++k) p -= l(j, k) * l(j, k);
    if (!(p > floor)) p = floor;
    p = std::sqrt(p);
    l(j, j) = p;
    inv(j) = Scalar(1) / p;
    for (int i = j + 1; i < 6; ++i) {
      Scalar t = l(i, j);
      for (int k = 0; k < j; ++k) t -= l(i, k) * l(j, k);
      l(i, j) = t * inv(j);
    }
  }
  Wrench<Scalar> z = b;
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < i; ++k) z(i) -= l(i, k) * z(k);
    z(i) *= inv(i);
  }
  for (int i = 5; i >= 0; --i) {
    for (int k = i + 1; k < 6; ++k) z(i) -= l(k, i) * z(k);
    z(i) *= inv(i);
  }
  return z;
}

/// Solves A y = b for the symmetric positive definite Newton matrix A (6x6, Jacobi-scaled) by
/// 3x3 blocks: A = [[P, Q], [Q^T, R]], P^-1 and the Schur complement T = R - Q^T P^-1 Q inverted
/// by their adjugates (adjugate3: two divisions, no square root: the floored Cholesky's six
/// square roots and divisions form one chain of latencies). Taken in double precision only
/// (ScalarTraits::is_single_precision false), and only when both 3x3 determinants exceed 1e-4
/// times the product of their diagonals and T's diagonal keeps 1e-4 of A's (no cancellation),
/// so that the answer loses at most about 1e8 eps (backward error); otherwise (and always in
/// float, and for any non-finite input) solve_floored_6x6(a, b, floor).
template <class S>
Wrench<S> solve_newton_6x6(const Matrix6<S>& a, const Wrench<S>& b, S floor) {
  if constexpr (ScalarTraits<S>::is_single_precision) return solve_floored_6x6(a, b, floor);
  const S hadamard = S(1e-4);
  const S p00 = a(0, 0), p01 = a(0, 1), p02 = a(0, 2), p11 = a(1, 1), p12 = a(1, 2), p22 = a(2, 2);
  const Adjugate3<S> pa = adjugate3(p00, p01, p02, p11, p12, p22);  // adj(P) and det(P)
  const S c00 = pa.c00, c01 = pa.c01, c02 = pa.c02, c11 = pa.c11, c12 = pa.c12, c22 = pa.c22;
  const S dp = pa.det;
  if (!(dp > hadamard * p00 * p11 * p22) || !(p00 > S(0) && p11 > S(0) && p22 > S(0)))
    return solve_floored_6x6(a, b, floor);
  const S ip = S(1) / dp;
  // X = P^-1 Q (Q = rows 0-2, columns 3-5), then the Schur complement T = R - Q^T X.
  S x[3][3];
  for (int j = 0; j < 3; ++j) {
    const S q0 = a(0, 3 + j), q1 = a(1, 3 + j), q2 = a(2, 3 + j);
    x[0][j] = (c00 * q0 + c01 * q1 + c02 * q2) * ip;
    x[1][j] = (c01 * q0 + c11 * q1 + c12 * q2) * ip;
    x[2][j] = (c02 * q0 + c12 * q1 + c22 * q2) * ip;
  }
  const auto t = [&](int i, int j) {
    return a(3 + i, 3 + j) - (a(0, 3 + i) * x[0][j] + a(1, 3 + i) * x[1][j] + a(2, 3 + i) * x[2][j]);
  };
  const S t00 = t(0, 0), t01 = t(0, 1), t02 = t(0, 2), t11 = t(1, 1), t12 = t(1, 2), t22 = t(2, 2);
  const Adjugate3<S> ta = adjugate3(t00, t01, t02, t11, t12, t22);  // adj(T) and det(T)
  const S d00 = ta.c00, d01 = ta.c01, d02 = ta.c02, d11 = ta.c11, d12 = ta.c12, d22 = ta.c22;
  const S dt = ta.det;
  // T's diagonal must not have cancelled (t_ii against a_ii), nor its determinant against its
  // diagonal.
  if (!(dt > hadamard * t00 * t11 * t22) ||
      !(t00 > hadamard * a(3, 3) && t11 > hadamard * a(4, 4) && t22 > hadamard * a(5, 5)))
    return solve_floored_6x6(a, b, floor);
  const S it = S(1) / dt;
  // u = P^-1 b_1; y_2 = T^-1 (b_2 - Q^T u); y_1 = u - X y_2.
  const S u0 = (c00 * b(0) + c01 * b(1) + c02 * b(2)) * ip, u1 = (c01 * b(0) + c11 * b(1) + c12 * b(2)) * ip,
          u2 = (c02 * b(0) + c12 * b(1) + c22 * b(2)) * ip;
  const S r0 = b(3) - (a(0, 3) * u0 + a(1, 3) * u1 + a(2, 3) * u2);
  const S r1 = b(4) - (a(0, 4) * u0 + a(1, 4) * u1 + a(2, 4) * u2);
  const S r2 = b(5) - (a(0, 5) * u0 + a(1, 5) * u1 + a(2, 5) * u2);
  Wrench<S> y;
  y(3) = (d00 * r0 + d01 * r1 + d02 * r2) * it;
  y(4) = (d01 * r0 + d11 * r1 + d12 * r2) * it;
  y(5) = (d02 * r0 + d12 * r1 + d22 * r2) * it;
  y(0) = u0 - (x[0][0] * y(3) + x[0][1] * y(4) + x[0][2] * y(5));
  y(1) = u1 - (x[1][0] * y(3) + x[1][1] * y(4) + x[1][2] * y(5));
  y(2) = u2 - (x[2][0] * y(3) + x[2][1] * y(4) + x[2][2] * y(5));
  return y;
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
/// ScalarTraits::rank_tolerance times the largest diagonal entry of A (or L is not positive); y = D u is then given by
/// the minimum-norm least-squares solution u = A^+ D r, so |D (M y - r)| is smallest, with eigenvalues of A below
/// rank_tolerance times the largest treated as zero. y is finite.
template <class Scalar>
Status solve_symmetric_6x6(const Matrix6<Scalar>& m, const Wrench<Scalar>& r, Wrench<Scalar>& y,
                           Scalar length = Scalar(1)) {
  const Scalar tol = ScalarTraits<Scalar>::rank_tolerance;
  const Wrench<Scalar> d = detail::unit_balance(length);
  if (detail::lever_usable(length)) {
    Scalar ref(0);
    for (int k = 0; k < 6; ++k) ref = std::max(ref, d(k) * m(k, k) * d(k));
    detail::SmallLdlt<6, Scalar> ldlt;
    const auto scaled = [&](Scalar(&a)[6][6]) {  // A = D M D
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
