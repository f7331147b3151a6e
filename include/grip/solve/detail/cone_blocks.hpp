#pragma once
/// \file
/// The per-contact block of the interior-point method's Newton system, on SIMD packs
/// (namespace grip::detail). Eliminating the dual z_i and a bound's slack s_i and dual t_i from
/// the Newton system leaves, per contact,
///     B_i du_i + A_i^T dy + qt_i dtau = g_i,     B_i = P_i + W_i^-2 + e e^T t_i / s_i,
/// (W_i the Nesterov-Todd scaling of (u_i, z_i), cone_packs.hpp; qt_i = q_i - e c_i t_i / s_i,
/// e = (1, 0, ...)). B_i^-1 is formed in the scaling's eigenframe (NtFrame), where W_i^-2 is
/// diagonal: each eigen-direction keeps its own relative accuracy as W_i^-2 spreads over many
/// orders of magnitude near the optimum. ConeBlock<P, D> gathers, for D-dimensional cones in the
/// lanes of pack P, this algebra as ConicLanes (conic_lanes.hpp) applies it to each contact:
/// B^-1, symmetric D x D products, the right-hand sides of the constant system, the predictor
/// and the corrector (in parts linear in sigma and sigma mu), the dual direction from a primal
/// one, and the step to the cones' boundary. Lanes whose contact has no bound hold s = 1, t = 0,
/// c = 0 in its row, which then adds nothing.

#include <array>
#include <cstddef>
#include <limits>

#include "grip/core/simd.hpp"
#include "grip/solve/detail/cone_packs.hpp"

namespace grip {
namespace detail {

/// The per-contact algebra of the Newton system for D-dimensional cones in the lanes of P (see
/// the file comment); static members only.
template <class P, int D>
struct ConeBlock {
  using S = typename P::Scalar;
  using Mask = typename P::Mask;
  using Vec = ConeVec<P, D>;
  static constexpr int tri = D * (D + 1) / 2;  ///< entries of a symmetric D x D matrix
  using Sym = IntArray<P, tri>;
  /// A contact's bound row in lanes: lanes without one hold s = 1, t = 0, c = 0.
  struct Bound {
    Mask has{P::first(0)};
    P s{P::set1(S(1))}, t{P::set1(S(0))}, c{P::set1(S(0))}, hb{P::set1(S(0))}, rb{P::set1(S(0))};
    P it{P::set1(S(1))}, is{P::set1(S(1))};  ///< 1 / t (1 without a bound), 1 / s
  };
  /// The entry (r, c) of a symmetric D x D matrix stored as its upper triangle, row by row.
  static constexpr std::size_t sym(int r, int c) {
    return r <= c ? static_cast<std::size_t>(r * D - r * (r - 1) / 2 + (c - r))
                  : static_cast<std::size_t>(c * D - c * (c - 1) / 2 + (r - c));
  }
  static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
  static P min(P x, P y) { return select(x < y, x, y); }
  /// g - A^T y.
  static Vec minus_transpose(const Vec& g, const IntArray<Vec, 6>& a, const P (&y)[6]) {
    Vec out;
    for (int k = 0; k < D; ++k) {
      P v = g[idx(k)];
      for (int r = 0; r < 6; ++r) v = neg_mul_add(a[idx(r)][idx(k)], y[r], v);
      out[idx(k)] = v;
    }
    return out;
  }
  /// dz = P du + A^T dy + q dtau + d_x + e dt (the dual residual's row of the Newton system).
  template <bool Bounded>
  static Vec dual_direction(const IntArray<Vec, 6>& a, const Vec& p, const Vec& q, const Vec& du, const P (&dy)[6],
                            P dtau, const Vec& dx, P dt) {
    Vec dz;
    for (int k = 0; k < D; ++k) {
      P v = a[0][idx(k)] * dy[0];
      for (int r = 1; r < 6; ++r) v = mul_add(a[idx(r)][idx(k)], dy[r], v);
      dz[idx(k)] = mul_add(q[idx(k)], dtau, mul_add(p[idx(k)], du[idx(k)], v) + dx[idx(k)]);
    }
    if constexpr (Bounded) dz[0] = dz[0] + dt;
    return dz;
  }
  /// The embedding's gradient row c = q + 2 P u / tau + e c t / s.
  template <bool Bounded>
  static Vec gradient_row(const Vec& p, const Vec& q, const Vec& u, P itau2, P cb, P hb) {
    Vec cg;
    for (int k = 0; k < D; ++k) cg[idx(k)] = mul_add(itau2, p[idx(k)] * u[idx(k)], q[idx(k)]);
    if constexpr (Bounded) cg[0] = mul_add(cb, hb, cg[0]);
    return cg;
  }
  /// The largest step keeping u + a du, z + a dz in Q and s + a ds, t + a dt >= 0 (bounded
  /// lanes), masked to the contacts.
  template <bool Bounded>
  static P step_length(const Vec& u, P det_u, const Vec& du, const Vec& z, P det_z, const Vec& dz, const Bound& b, P ds,
                       P dt, Mask valid) {
    const P inf = P::set1(std::numeric_limits<S>::infinity());
    P st = min(cone_ray_step<P, D>(u, det_u, du), cone_ray_step<P, D>(z, det_z, dz));
    if constexpr (Bounded) {
      const P zero = P::set1(S(0)), one = P::set1(S(1));
      st = select(b.has & (ds < zero), min(st, zero - b.s / select(ds < zero, ds, zero - one)), st);
      st = select(b.has & (dt < zero), min(st, zero - b.t / select(dt < zero, dt, zero - one)), st);
    }
    return select(valid, st, inf);
  }
  /// The constant system's right-hand side: -q + e c t/s.
  template <bool Bounded>
  static Vec constant_rhs(const Vec& q, P hb, P cb) {
    Vec g;
    for (int k = 0; k < D; ++k) g[idx(k)] = P::set1(S(0)) - q[idx(k)];
    if constexpr (Bounded) g[0] = mul_add(cb, hb, g[0]);
    return g;
  }
  /// The predictor's right-hand side: -rx - z + e (t/s)(s - rb) (W^-1 (lambda \ lambda o lambda) = z).
  template <bool Bounded>
  static Vec predictor_rhs(const Vec& rx, const Vec& z, P hb, P s, P rb) {
    Vec g;
    for (int k = 0; k < D; ++k) g[idx(k)] = P::set1(S(0)) - rx[idx(k)] - z[idx(k)];
    if constexpr (Bounded) g[0] = mul_add(hb, s - rb, g[0]);
    return g;
  }
  /// The corrector's right-hand side in parts, g = g0 + sigma g1 + sigma mu g2:
  /// -(1 - sigma) rx - (cc - sigma mu ce) - e (t/s)((1 - sigma) rb - s - ds dt / t + sigma mu / t).
  template <bool Bounded>
  static void corrector_parts(const Vec& rx, const Vec& cc, const Vec& ce, const Bound& b, P dsdt, Vec* g) {
    const P zero = P::set1(S(0));
    for (int k = 0; k < D; ++k) {
      g[0][idx(k)] = zero - rx[idx(k)] - cc[idx(k)];
      g[1][idx(k)] = rx[idx(k)];
      g[2][idx(k)] = ce[idx(k)];
    }
    if constexpr (Bounded) {
      g[0][0] = g[0][0] + select(b.has, b.hb * (b.s - b.rb + dsdt * b.it), zero);
      g[1][0] = g[1][0] + select(b.has, b.hb * b.rb, zero);
      g[2][0] = g[2][0] - b.is;
    }
  }
  /// The wide neighbourhood's fourth part of the corrector's right-hand side (beside the three of
  /// corrector_parts): ce on the lanes whose cone pair has its scaled point lambda = W z with
  /// smallest eigenvalue lambda_0 - |lambda_1| below `root_gamma_mu` = sqrt(gamma mu), else 0. The
  /// driver adds it times max(gamma - sigma, 0) mu, so that those pairs are centred toward at least
  /// gamma mu and none is driven to its cone's boundary ahead of the others (Wright,
  /// "Primal-Dual Interior-Point Methods", SIAM 1997, ch. 5). A bound's terms take no part.
  /// Without a square root per lane: lambda_0 < sqrt(gamma mu) or (lambda_0 - sqrt(gamma mu))^2 <
  /// |lambda_1|^2.
  static Vec recentre_part(const Vec& lambda, const Vec& ce, P root_gamma_mu) {
    const P zero = P::set1(S(0));
    const P d = lambda[0] - root_gamma_mu;
    P tail = zero;
    for (int k = 1; k < D; ++k) tail = mul_add(lambda[idx(k)], lambda[idx(k)], tail);
    const Mask near = (d < zero) | (d * d < tail);
    Vec g;
    for (int k = 0; k < D; ++k) g[idx(k)] = select(near, ce[idx(k)], zero);
    return g;
  }
  /// B^-1 for B = P + e e^T hb + W^-2, in the scaling's frame (NtFrame): W^-2 = diag(a, b, g, ...)
  /// along (e+, e-, the rest), a = d-^2 / beta^2, b = d+^2 / beta^2, g = 1 / beta^2.
  /// D = 1: 1 / (p + hb + g). D = 3 (P = diag(p0, p1, p1)): in the frame B is a 2 x 2 block on
  /// (e+, e-) plus p1 + g on the rest, with determinant p0 p1 + (p0 + p1)(a + b)/2 + a b (a sum of
  /// positive terms), so B^-1 = [[c0, c1 f^T], [c1 f, c2 f f^T + (I - f f^T) / (p1 + g)]] with
  /// c0 = (2 p1 + a + b) / 2 det, c1 = (b - a) / 2 det, c2 = (2 p0 + a + b) / 2 det. Otherwise
  /// (D = 2, 4): B0 = P + e e^T hb + g I + (a - g) e+ e+^T inverted by LDL^T, then the large
  /// b - g along e- by Sherman and Morrison.
  static Sym inverse_from_frame(const NtFrame<P, D>& k, const Vec& p, P hb) {
    const P one = P::set1(S(1)), half = P::set1(S(0.5)), zero = P::set1(S(0));
    const P g = k.inv_beta * k.inv_beta;
    Sym out;
    if constexpr (D == 1) {
      out[0] = one / (p[0] + hb + g);
    } else if constexpr (D == 3) {
      const P a = k.dm * k.dm * g, b = k.dp * k.dp * g;
      const P p0 = p[0] + hb, p1 = p[1];
      const P ab = a + b;
      const P det = mul_add(p0, p1, mul_add(half * (p0 + p1), ab, a * b));
      const P pg = p1 + g;
      const P r = one / (det * pg);
      const P idet = r * pg, ag = r * det;
      const P c0 = half * (P::set1(S(2)) * p1 + ab) * idet;
      const P c1 = half * (b - a) * idet;
      const P c2 = half * (P::set1(S(2)) * p0 + ab) * idet;
      const P cf = c2 - ag;
      out[sym(0, 0)] = c0;
      out[sym(0, 1)] = c1 * k.f[1];
      out[sym(0, 2)] = c1 * k.f[2];
      out[sym(1, 1)] = mul_add(cf * k.f[1], k.f[1], ag);
      out[sym(1, 2)] = cf * k.f[1] * k.f[2];
      out[sym(2, 2)] = mul_add(cf * k.f[2], k.f[2], ag);
    } else {
      // e+ and e- (unit): (1, +-f) / sqrt(2).
      const P r2 = P::set1(S(0.70710678118654752440));
      Vec ep, em;
      ep[0] = em[0] = r2;
      for (int j = 1; j < D; ++j) {
        ep[idx(j)] = r2 * k.f[idx(j)];
        em[idx(j)] = zero - ep[idx(j)];
      }
      const P a = k.dm * k.dm * g;
      Sym b0;
      for (int r = 0; r < D; ++r)
        for (int c = r; c < D; ++c) {
          P v = (a - g) * ep[idx(r)] * ep[idx(c)];
          if (r == c) v = v + g + p[idx(r)];
          b0[sym(r, c)] = v;
        }
      b0[0] = b0[0] + hb;
      out = sym_inverse(b0);
      // b - g = (d+^2 - 1) g = (d+ - 1)(d+ + 1) g along e-.
      const P kappa = (k.dp - one) * (k.dp + one) * g;
      const Vec h = sym_apply(out, em);
      const P sigma = cone_dot<P, D>(em, h);
      const P w = select(kappa > zero, kappa / mul_add(kappa, sigma, one), zero);
      for (int r = 0; r < D; ++r)
        for (int c = r; c < D; ++c) out[sym(r, c)] = neg_mul_add(w * h[idx(r)], h[idx(c)], out[sym(r, c)]);
    }
    return out;
  }
  /// The inverse of a symmetric positive definite D x D matrix (upper triangles) by LDL^T, lane
  /// by lane.
  static Sym sym_inverse(const Sym& m) {
    Sym out;
    P l[D][D], d[D];
    for (int j = 0; j < D; ++j) {
      P v = m[sym(j, j)];
      for (int k = 0; k < j; ++k) v = neg_mul_add(l[j][k] * d[k], l[j][k], v);
      d[j] = v;
      const P inv = P::set1(S(1)) / v;
      for (int i = j + 1; i < D; ++i) {
        P w = m[sym(j, i)];
        for (int k = 0; k < j; ++k) w = neg_mul_add(l[i][k] * d[k], l[j][k], w);
        l[i][j] = w * inv;
      }
    }
    for (int c = 0; c < D; ++c) {
      P x[D];
      for (int i = 0; i < D; ++i) {
        P v = P::set1(i == c ? S(1) : S(0));
        for (int k = 0; k < i; ++k) v = neg_mul_add(l[i][k], x[k], v);
        x[i] = v;
      }
      for (int i = 0; i < D; ++i) x[i] = x[i] / d[i];
      for (int i = D - 1; i >= 0; --i)
        for (int k = i + 1; k < D; ++k) x[i] = neg_mul_add(l[k][i], x[k], x[i]);
      for (int r = 0; r <= c; ++r) out[sym(r, c)] = x[r];
    }
    return out;
  }
  /// m x for a symmetric m (upper triangle).
  static Vec sym_apply(const Sym& m, const Vec& x) {
    Vec out;
    for (int r = 0; r < D; ++r) {
      P v = m[sym(r, 0)] * x[0];
      for (int k = 1; k < D; ++k) v = mul_add(m[sym(r, k)], x[idx(k)], v);
      out[idx(r)] = v;
    }
    return out;
  }
};

}  // namespace detail
}  // namespace grip
