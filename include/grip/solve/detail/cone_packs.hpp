#pragma once
/// \file
/// The algebra of the second-order cone on SIMD packs (namespace grip::detail): every function
/// takes cone vectors as arrays of D packs, component by component, so that one call serves as
/// many cones as the pack has lanes (core/simd.hpp). Internal to the interior-point method
/// (conic_lanes.hpp).
///
/// The cone of dimension D is Q = {u in R^D : u_0 >= |(u_1, ..., u_{D-1})|} (for D = 1 the
/// half-line u_0 >= 0). Its Jordan algebra, with e = (1, 0, ..., 0) and J = diag(1, -1, ..., -1):
///   u o v = (u . v, u_0 v_1 + v_0 u_1),    det u = u^T J u,    u in int Q iff u_0 > |u_1|.
/// Nesterov-Todd scaling of a pair u, z in int Q: the symmetric W with W z = W^-1 u = lambda,
///   W = beta (2 v v^T - J),    W^-1 = (2 J v v^T J - J) / beta,
/// where, with u' = u / sqrt(det u) and z' = z / sqrt(det z), gamma = sqrt((1 + z'^T u') / 2),
/// w = (u' + J z') / (2 gamma), v = (w + e) / sqrt(2 (w_0 + 1)) (so v^T J v = 1) and
/// beta = (det u / det z)^(1/4). Then u^T z = lambda^T lambda.
/// References: L. Vandenberghe, "The CVXOPT linear and quadratic cone program solvers" (2010),
/// section 4; F. Alizadeh and D. Goldfarb, "Second-order cone programming", Math. Program. 95
/// (2003), section 4.

#include <array>
#include <cstddef>
#include <limits>

#include "grip/core/simd.hpp"

namespace grip {
namespace detail {

/// N values indexed by int or std::size_t: the lane algebra indexes by int loop counters, which
/// std::array would have converted to size_t one by one.
template <class T, int N>
struct IntArray {
  T v[N];
  GRIP_ALWAYS_INLINE T& operator[](int i) { return v[i]; }
  GRIP_ALWAYS_INLINE const T& operator[](int i) const { return v[i]; }
  GRIP_ALWAYS_INLINE T& operator[](std::size_t i) { return v[i]; }
  GRIP_ALWAYS_INLINE const T& operator[](std::size_t i) const { return v[i]; }
};

/// D packs: one cone vector per lane, component by component.
template <class P, int D>
using ConeVec = IntArray<P, D>;

/// a . b, lane by lane.
template <class P, int D>
GRIP_ALWAYS_INLINE P cone_dot(const ConeVec<P, D>& a, const ConeVec<P, D>& b) {
  P t = a[0] * b[0];
  for (int r = 1; r < D; ++r) t = mul_add(a[r], b[r], t);
  return t;
}

/// |u_1|, the norm of the components after the first (0 for D = 1).
template <class P, int D>
GRIP_ALWAYS_INLINE P cone_tail_norm(const ConeVec<P, D>& u) {
  if constexpr (D == 1) {
    return P::set1(typename P::Scalar(0));
  } else {
    P t2 = u[1] * u[1];
    for (int r = 2; r < D; ++r) t2 = mul_add(u[r], u[r], t2);
    return sqrt(t2);
  }
}

/// det u = u_0^2 - |u_1|^2, computed as (u_0 - |u_1|)(u_0 + |u_1|): no cancellation near the
/// boundary of the cone.
template <class P, int D>
GRIP_ALWAYS_INLINE P cone_det(const ConeVec<P, D>& u) {
  if constexpr (D == 1) {
    return u[0] * u[0];
  } else {
    const P t = cone_tail_norm<P, D>(u);
    return (u[0] - t) * (u[0] + t);
  }
}

/// u_0 - |u_1|: positive inside the cone, 0 on its boundary.
template <class P, int D>
GRIP_ALWAYS_INLINE P cone_margin(const ConeVec<P, D>& u) {
  return u[0] - cone_tail_norm<P, D>(u);
}

/// The Nesterov-Todd scaling of (u, z), both interior (see the file comment), in its eigenframe.
/// With w = v o v the scaling point (w^T J w = 1), W / beta has the eigenvalues d+ = w_0 + |w_1| and
/// d- = 1 / d+ along e+ = (1, f) / sqrt(2) and e- = (1, -f) / sqrt(2), f = w_1 / |w_1|, and 1 on the
/// rest of the tail (orthogonal to f). Applying W or W^-1 in this frame keeps every eigen-direction
/// to its own relative accuracy however far d+ grows as u or z nears the boundary (the explicit
/// beta (2 v v^T - J) has entries of d+ and recovers the d- direction by cancellation).
template <class P, int D>
struct NtFrame {
  P beta, inv_beta;      ///< (det u / det z)^(1/4) and its inverse
  P dp, dm;              ///< d+ >= 1 and d- = 1 / d+
  ConeVec<P, D> f;       ///< f in entries 1..D-1 (entry 0 unused): a unit vector (e_1 where |w_1| = 0)
  ConeVec<P, D> lambda;  ///< W z = W^-1 u
  P det_u, det_z;        ///< det u, det z
  P det_lambda;          ///< det lambda = sqrt(det u det z)
  typename P::Mask ok;   ///< lanes with a valid scaling (both interior, finite)
};

/// W x (inverse false) or W^-1 x (inverse true) in the frame of `k`: with s = f . x_1, P = x_0 + s,
/// M = x_0 - s, W x = beta ((d+ P + d- M) / 2, x_1 + ((d+ P - d- M) / 2 - s) f); W^-1 swaps d+ and
/// d- and takes 1 / beta.
template <bool Inverse, class P, int D>
GRIP_ALWAYS_INLINE ConeVec<P, D> nt_frame_apply(const NtFrame<P, D>& k, const ConeVec<P, D>& x) {
  using S = typename P::Scalar;
  const P half = P::set1(S(0.5));
  const P up = Inverse ? k.dm : k.dp, down = Inverse ? k.dp : k.dm, scale = Inverse ? k.inv_beta : k.beta;
  ConeVec<P, D> out;
  if constexpr (D == 1) {
    out[0] = scale * x[0];
  } else {
    P s = k.f[1] * x[1];
    for (int r = 2; r < D; ++r) s = mul_add(k.f[r], x[r], s);
    const P pp = x[0] + s, mm = x[0] - s;
    const P a = up * pp, b = down * mm;
    out[0] = scale * (half * (a + b));
    const P c = half * (a - b) - s;
    for (int r = 1; r < D; ++r) out[r] = scale * mul_add(c, k.f[r], x[r]);
  }
  return out;
}

/// The Nesterov-Todd scaling of the pairs (u, z), lane by lane, in its eigenframe (NtFrame). With
/// su = sqrt(det u), sz = sqrt(det z), m = su sz: w = (sz u + su J z) / sqrt(2 m (m + u . z)),
/// beta^2 = su / sz.
template <class P, int D>
GRIP_ALWAYS_INLINE NtFrame<P, D> nt_frame(const ConeVec<P, D>& u, const ConeVec<P, D>& z) {
  using S = typename P::Scalar;
  const P one = P::set1(S(1)), zero = P::set1(S(0));
  NtFrame<P, D> k;
  k.det_u = cone_det<P, D>(u);
  k.det_z = cone_det<P, D>(z);
  const auto good = (k.det_u > zero) & (k.det_z > zero) & (u[0] > zero) & (z[0] > zero);
  const P du = select(good, k.det_u, one), dz = select(good, k.det_z, one);
  const P su = sqrt(du), sz = sqrt(dz);
  const P m = su * sz;
  k.det_lambda = m;
  const P uz = cone_dot<P, D>(u, z);
  const P t = P::set1(S(2)) * m * (m + uz);
  const P rsq = one / sqrt(select(good & (t > zero), t, one));
  // 1 / m = 2 (m + u . z) rsq^2, so beta^2 = su^2 / m and 1 / beta^2 = sz^2 / m.
  const P inv_m = P::set1(S(2)) * (m + uz) * rsq * rsq;
  k.beta = sqrt(du * inv_m);
  k.inv_beta = k.beta * dz * inv_m;
  if constexpr (D == 1) {
    k.dp = k.dm = one;
    k.f[0] = zero;
  } else {
    ConeVec<P, D> w;
    w[0] = (u[0] * sz + z[0] * su) * rsq;
    for (int r = 1; r < D; ++r) w[r] = (u[r] * sz - z[r] * su) * rsq;
    const P tw = cone_tail_norm<P, D>(w);
    k.dp = w[0] + tw;
    const auto turn = tw > P::set1(std::numeric_limits<S>::min());
    const P r = one / (k.dp * select(turn, tw, one));  // 1 / (d+ |w_1|), or 1 / d+ where |w_1| = 0
    k.dm = select(turn, tw * r, r);
    const P itw = k.dp * r;
    k.f[0] = zero;
    for (int c = 1; c < D; ++c) k.f[c] = select(turn, w[c] * itw, c == 1 ? one : zero);
  }
  P fin = k.beta + k.inv_beta + k.dp;
  k.ok = good & (abs(fin) < P::set1(std::numeric_limits<S>::infinity()));
  k.lambda = nt_frame_apply<false, P, D>(k, z);
  return k;
}

/// a o b = (a . b, a_0 b_1 + b_0 a_1).
template <class P, int D>
GRIP_ALWAYS_INLINE ConeVec<P, D> jordan_product(const ConeVec<P, D>& a, const ConeVec<P, D>& b) {
  ConeVec<P, D> out;
  out[0] = cone_dot<P, D>(a, b);
  for (int r = 1; r < D; ++r) out[r] = mul_add(a[0], b[r], b[0] * a[r]);
  return out;
}

/// x with l o x = d, for l in int Q with det l = `det_l` (> 0): x_0 = (l_0 d_0 - l_1 . d_1) / det l,
/// x_1 = (d_1 - x_0 l_1) / l_0.
template <class P, int D>
GRIP_ALWAYS_INLINE ConeVec<P, D> jordan_divide(const ConeVec<P, D>& l, P det_l, const ConeVec<P, D>& d) {
  using S = typename P::Scalar;
  ConeVec<P, D> out;
  P ld = l[0] * d[0];
  for (int r = 1; r < D; ++r) ld = neg_mul_add(l[r], d[r], ld);
  // One division for 1 / det_l and 1 / l_0.
  const P inv = P::set1(S(1)) / (det_l * l[0]);
  out[0] = ld * (l[0] * inv);
  const P il0 = det_l * inv;
  for (int r = 1; r < D; ++r) out[r] = neg_mul_add(out[0], l[r], d[r]) * il0;
  return out;
}

/// The largest a >= 0 with u + a du in Q (infinity if the whole ray stays inside), lane by lane,
/// for u in Q with det u = `det_u` (cone_det's accurate value): the least positive root of
/// det(u + a du) = A a^2 + 2 B a + C, and at most -u_0 / du_0 when du_0 < 0 (which also covers the
/// rays along which det has a double root that rounding can hide). Roots as q / A and C / q with
/// q = -(B + sign(B) sqrt(B^2 - A C)), the form without cancellation.
template <class P, int D>
GRIP_ALWAYS_INLINE P cone_ray_step(const ConeVec<P, D>& u, P det_u, const ConeVec<P, D>& du) {
  using S = typename P::Scalar;
  const P inf = P::set1(std::numeric_limits<S>::infinity()), zero = P::set1(S(0)), one = P::set1(S(1));
  P best = select(du[0] < zero, zero - u[0] / select(du[0] < zero, du[0], one), inf);
  if constexpr (D > 1) {
    P a = du[0] * du[0], b = u[0] * du[0];
    for (int r = 1; r < D; ++r) {
      a = neg_mul_add(du[r], du[r], a);
      b = neg_mul_add(u[r], du[r], b);
    }
    const P c = det_u;
    const P disc = b * b - a * c;
    const auto a_zero = (a <= zero) & (!(a < zero));
    // A == 0 (disc = B^2): q = -2 B and the one root C / q = -C / (2 B), positive when B < 0.
    const auto real = zero <= disc;
    const P sq = sqrt(select(real, disc, zero));
    const P q = zero - (b + select(b < zero, zero - sq, sq));
    const auto use = real & ((q < zero) | (q > zero));
    const auto quadratic = use & !a_zero;
    const P r1 = q / select(quadratic, a, one), r2 = c / select(use, q, one);
    best = select(quadratic & (r1 > zero) & (r1 < best), r1, best);
    best = select(use & (r2 > zero) & (r2 < best), r2, best);
  }
  return best;
}

}  // namespace detail
}  // namespace grip
