#pragma once
/// \file
/// The per-contact work of conic_dual.hpp's interior-point iteration, on the contacts in SIMD
/// lanes (core/simd.hpp): every second-order cone of dimension D (1, 3 or 4) is one lane, and
/// each of its quantities is stored component by component across the contacts (structure of
/// arrays), so one pack of instructions serves 8 (AVX-512), 4 (AVX2) or 1 contacts. Internal to
/// conic_dual.hpp.
///
/// The second-order cone Q = {u in R^m : u_0 >= |(u_1, ..., u_{m-1})|} (m = 1: the half-line
/// u_0 >= 0) and its Jordan algebra (e = (1, 0, ..., 0), J = diag(1, -1, ..., -1)):
///   u o v = (u . v, u_0 v_1 + v_0 u_1),   u o e = u,   u in int Q iff u_0 > |u_1|.
/// Nesterov-Todd scaling of a pair s, z in int Q: the symmetric W with W z = W^-1 s = lambda,
/// W = beta (2 v v^T - J), W^-1 = (2 J v v^T J - J) / beta, where with s' = s / sqrt(s^T J s)
/// and z' = z / sqrt(z^T J z), gamma = sqrt((1 + z'^T s') / 2), w = (s' + J z') / (2 gamma),
/// v = (w + e) / sqrt(2 (w_0 + 1)) (so v^T J v = 1, and 2 v v^T - J is its own J-inverse) and
/// beta = (s^T J s / z^T J z)^(1/4). Then s^T z = lambda^T lambda. The step to the boundary
/// of u + a d is the least positive root of det(u + a d) = A a^2 + 2 B a + C (det u = u^T J u,
/// computed as (u_0 - |u_1|)(u_0 + |u_1|)), and at most -u_0 / d_0 when d_0 < 0, which also
/// decides the rays along which det has a double root that rounding can hide.
/// References: L. Vandenberghe, "The CVXOPT linear and quadratic cone program solvers" (2010),
/// section 4; Alizadeh & Goldfarb, "Second-order cone programming", Math. Program. 95 (2003),
/// section 4. The tests check each lane against a one-cone-at-a-time version of these
/// definitions.
///
/// Lanes past the last contact of the last block hold s = z = e and F = 0: their scaling is
/// the identity, they add nothing to the sums over contacts (each is a product with F), and
/// every step, gap and residual leaves them out, so their directions are kept at zero.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "grip/core/index.hpp"
#include "grip/core/simd.hpp"

namespace grip {
namespace detail {

/// The cones of up to Cap contacts, each of dimension D, with their maps F_i (D x 7), their
/// slacks s_i, multipliers z_i, Nesterov-Todd scalings and Newton directions, in lanes.
template <class S, int D, int Cap>
struct ConeLanes {
  using P = SimdPack<S>;
  using V7 = Eigen::Matrix<S, 7, 1>;
  static constexpr int width = P::width;
  static constexpr int stride = (Cap + 7) / 8 * 8;  ///< lanes per component (a multiple of every width)
  using Field = std::array<S, D * stride>;          ///< one D-vector per contact, component-major

  int n{0};       ///< contacts
  int blocks{0};  ///< packs of `width` contacts
  std::array<S, D * 7 * stride> F{}, WF{};  ///< F_i and W_i^-1 F_i, entry (r, c) at (7 r + c) stride + i
  Field s{}, z{}, rc{}, ds{}, dz{}, lambda{}, d{}, el{}, g{}, v{};
  std::array<S, stride> beta{}, inv_beta{};

  /// n contacts, every lane at s = z = e, F = 0 (fill F with set_map, then start()).
  explicit ConeLanes(int contacts) : n(contacts), blocks((contacts + width - 1) / width) {
    for (std::size_t i = 0; i < std::size_t{stride}; ++i) {
      s[i] = z[i] = lambda[i] = v[i] = S(1);
      beta[i] = inv_beta[i] = S(1);
    }
  }
  /// Row r of F_i (7 entries).
  template <class Row>
  void set_map(int i, int r, const Row& row) {
    for (int c = 0; c < 7; ++c) F[static_cast<std::size_t>((7 * r + c) * stride + i)] = row(c);
  }
  /// Component r of contact i's vector in `f`.
  static S& at(Field& f, int r, int i) { return f[static_cast<std::size_t>(r * stride + i)]; }
  static S at(const Field& f, int r, int i) { return f[static_cast<std::size_t>(r * stride + i)]; }

  /// s_i = F_i q; false unless every s_i is interior to Q.
  bool start(const V7& q) {
    bool ok = true;
    for_blocks([&](int o, typename P::Mask valid) {
      P u[D];
      map(F.data(), o, q, u);
      for (int r = 0; r < D; ++r) u[r].store(ptr(s, r, o));
      ok = ok && (and_not(valid, interior(u))).bits() == 0u;
    });
    return ok;
  }

  /// The pass that opens an iteration: s_i += a ds_i and z_i += a dz_i (skipped for a = 0);
  /// then at the new point rd -= sum F_i^T z_i, rc_i = F_i q - s_i, the largest
  /// |rc_i|_inf / (1 + |s_i|_inf) into `pres` (if larger), and scale()'s work (H and `ok`).
  /// Returns the gap sum s_i . z_i.
  template <class M7>
  S advance(S a, const V7& q, V7& rd, S& pres, M7& H, bool& ok) {
    P acc[8], hacc[32], gap = P::set1(S(0)), rel = gap;
    for (P& e : acc) e = gap;
    for (P& e : hacc) e = gap;
    const P pa = P::set1(a);
    for_blocks([&](int o, typename P::Mask valid) {
      P su[D], zu[D], fq[D], big_r = P::set1(S(0)), big_s = P::set1(S(0)), sz = P::set1(S(0));
      map(F.data(), o, q, fq);
      for (int r = 0; r < D; ++r) {
        su[r] = P::load(ptr(s, r, o));
        zu[r] = P::load(ptr(z, r, o));
        if (a != S(0)) {
          su[r] = mul_add(pa, P::load(ptr(ds, r, o)), su[r]);
          zu[r] = mul_add(pa, P::load(ptr(dz, r, o)), zu[r]);
          su[r].store(ptr(s, r, o));
          zu[r].store(ptr(z, r, o));
        }
        const P rr = select(valid, fq[r] - su[r], P::set1(S(0)));
        rr.store(ptr(rc, r, o));
        big_r = max(big_r, abs(rr));
        big_s = max(big_s, abs(su[r]));
        sz = mul_add(su[r], zu[r], sz);
      }
      transpose_map(F.data(), o, zu, acc);
      gap = gap + select(valid, sz, P::set1(S(0)));
      rel = max(rel, big_r / (P::set1(S(1)) + big_s));
      ok = scale_block(o, valid, su, zu, hacc) && ok;
    });
    rd -= sums(acc);
    pres = std::max(pres, -least(P::set1(S(0)) - rel));  // the largest lane of rel
    add_upper(hacc, H);
    return gap.sum();
  }

  /// The scalings W_i of (s_i, z_i), lambda_i = W_i z_i, WF_i = W_i^-1 F_i, and
  /// H += sum WF_i^T WF_i; false if some pair is not interior (or a scaling not finite).
  template <class M7>
  bool scale(M7& H) {
    P acc[32];
    for (int e = 0; e < 32; ++e) acc[e] = P::set1(S(0));
    bool ok = true;
    for_blocks([&](int o, typename P::Mask valid) {
      P su[D], zu[D];
      load(s, o, su);
      load(z, o, zu);
      ok = scale_block(o, valid, su, zu, acc) && ok;
    });
    add_upper(acc, H);
    return ok;
  }

  /// g_i = W_i^-1 (d_i - W_i^-1 rc_i); r1 += sum F_i^T g_i. For the predictor (`affine`)
  /// d_i = -lambda_i; for the corrector d_i = c_i + sm e'_i as prepared by affine_gap().
  void newton_rhs(V7& r1, bool affine, S sm) {
    P acc[8];  // sum_each takes multiples of 8: acc[7] stays 0
    for (int c = 0; c < 8; ++c) acc[c] = P::set1(S(0));
    const P psm = P::set1(sm);
    for_blocks([&](int o, typename P::Mask) {
      P vv[D], u[D], w[D];
      load(v, o, vv);
      const P ib = P::load(&inv_beta[static_cast<std::size_t>(o)]);
      load(rc, o, u);
      apply_inverse(vv, ib, u, w);
      for (int r = 0; r < D; ++r) {
        const P dr = affine ? P::set1(S(0)) - P::load(ptr(lambda, r, o))
                            : mul_add(psm, P::load(ptr(el, r, o)), P::load(ptr(d, r, o)));
        u[r] = dr - w[r];
      }
      apply_inverse(vv, ib, u, w);
      for (int r = 0; r < D; ++r) w[r].store(ptr(g, r, o));
      transpose_map(F.data(), o, w, acc);
    });
    r1 += sums(acc);
  }

  /// ds_i = F_i dq + rc_i, dz_i = g_i - W_i^-1 (WF_i dq); res -= sum F_i^T dz_i. Returns the
  /// largest a >= 0 keeping every s_i + a ds_i and z_i + a dz_i in Q, as max_step() would.
  S recover(const V7& dq, V7& res) {
    P acc[8];  // sum_each takes multiples of 8: acc[7] stays 0
    for (int c = 0; c < 8; ++c) acc[c] = P::set1(S(0));
    P t = P::set1(std::numeric_limits<S>::infinity());
    for_blocks([&](int o, typename P::Mask valid) {
      P u[D], w[D], vv[D], dsu[D], base[D];
      map(F.data(), o, dq, u);
      for (int r = 0; r < D; ++r) {
        dsu[r] = select(valid, u[r] + P::load(ptr(rc, r, o)), P::set1(S(0)));
        dsu[r].store(ptr(ds, r, o));
      }
      map(WF.data(), o, dq, u);
      load(v, o, vv);
      apply_inverse(vv, P::load(&inv_beta[static_cast<std::size_t>(o)]), u, w);
      for (int r = 0; r < D; ++r) {
        w[r] = select(valid, P::load(ptr(g, r, o)) - w[r], P::set1(S(0)));
        w[r].store(ptr(dz, r, o));
      }
      transpose_map(F.data(), o, w, acc);
      load(s, o, base);
      t = min(t, select(valid, ray_step(base, dsu), t));
      load(z, o, base);
      t = min(t, select(valid, ray_step(base, w), t));
    });
    res -= sums(acc);
    return least(t);
  }

  /// The largest a >= 0 keeping every s_i + a ds_i and z_i + a dz_i in Q (infinity if no bound).
  S max_step() const {
    P t = P::set1(std::numeric_limits<S>::infinity());
    for_blocks([&](int o, typename P::Mask valid) {
      P u[D], du[D];
      load(s, o, u);
      load(ds, o, du);
      t = min(t, select(valid, ray_step(u, du), t));
      load(z, o, u);
      load(dz, o, du);
      t = min(t, select(valid, ray_step(u, du), t));
    });
    return least(t);
  }

  /// sum (s_i + a ds_i) . (z_i + a dz_i), the predictor's gap; also prepares the corrector
  /// (Mehrotra) from the predictor's directions ds, dz: the d_i with lambda_i o d_i = sm e -
  /// lambda_i o lambda_i - (W^-1 ds_i) o (W dz_i) is linear in sm, d_i = c_i + sm e'_i with
  /// e'_i = lambda_i \ e; c_i goes to d and e'_i to el, for newton_rhs(r1, false, sm).
  S affine_gap(S a) {
    P gap = P::set1(S(0));
    const P pa = P::set1(a);
    for_blocks([&](int o, typename P::Mask valid) {
      P acc = P::set1(S(0)), dsr[D], dzr[D];
      for (int r = 0; r < D; ++r) {
        dsr[r] = P::load(ptr(ds, r, o));
        dzr[r] = P::load(ptr(dz, r, o));
        acc = mul_add(mul_add(pa, dsr[r], P::load(ptr(s, r, o))), mul_add(pa, dzr[r], P::load(ptr(z, r, o))), acc);
      }
      gap = gap + select(valid, acc, P::set1(S(0)));
      P vv[D], l[D], x[D], y[D];
      load(v, o, vv);
      load(lambda, o, l);
      apply_inverse(vv, P::load(&inv_beta[static_cast<std::size_t>(o)]), dsr, x);
      apply(vv, P::load(&beta[static_cast<std::size_t>(o)]), dzr, y);
      P r[D];
      r[0] = P::set1(S(0)) - dot(l, l) - dot(x, y);
      for (int k = 1; k < D; ++k) r[k] = P::set1(S(0)) - P::set1(S(2)) * l[0] * l[k] - (x[0] * y[k] + y[0] * x[k]);
      // lambda \ r: d_0 = (lambda_0 r_0 - lambda_1 . r_1) / det(lambda), d_1 = (r_1 - d_0 lambda_1) / lambda_0;
      // for r = e: d_0 = lambda_0 / det(lambda), d_1 = -d_0 lambda_1 / lambda_0.
      P l1r1 = P::set1(S(0));
      for (int k = 1; k < D; ++k) l1r1 = mul_add(l[k], r[k], l1r1);
      const P idet = P::set1(S(1)) / det(l), il0 = P::set1(S(1)) / l[0];
      const P d0 = (l[0] * r[0] - l1r1) * idet, e0 = l[0] * idet;
      d0.store(ptr(d, 0, o));
      e0.store(ptr(el, 0, o));
      for (int k = 1; k < D; ++k) {
        ((r[k] - d0 * l[k]) * il0).store(ptr(d, k, o));
        (P::set1(S(0)) - e0 * l[k] * il0).store(ptr(el, k, o));
      }
    });
    return gap.sum();
  }

 private:
  /// scale()'s work on the block at lane o, s and z given: false if a valid lane fails.
  bool scale_block(int o, typename P::Mask valid, const P (&su)[D], const P (&zu)[D], P (&acc)[32]) {
    P vv[D];
    const P dsn = det(su), dzn = det(zu), zero = P::set1(S(0));
    const typename P::Mask good = (dsn > zero) & (dzn > zero) & (su[0] > zero) & (zu[0] > zero);
    const P rs = P::set1(S(1)) / sqrt(select(good, dsn, P::set1(S(1))));
    const P rz = P::set1(S(1)) / sqrt(select(good, dzn, P::set1(S(1))));
    P dot = su[0] * zu[0] * rs * rz;  // zn . sn
    for (int r = 1; r < D; ++r) dot = mul_add(su[r] * rs, zu[r] * rz, dot);
    const P gamma = sqrt((P::set1(S(1)) + dot) * P::set1(S(0.5)));
    const P inv2g = P::set1(S(1)) / (P::set1(S(2)) * gamma);
    const P w0 = (su[0] * rs + zu[0] * rz) * inv2g;
    const P nv = P::set1(S(1)) / sqrt(P::set1(S(2)) * (w0 + P::set1(S(1))));
    vv[0] = (w0 + P::set1(S(1))) * nv;
    for (int r = 1; r < D; ++r) vv[r] = (su[r] * rs - zu[r] * rz) * inv2g * nv;
    const P b = sqrt(sqrt(select(good, dsn / dzn, P::set1(S(1)))));
    const P ib = P::set1(S(1)) / b;
    P fin = b + ib;
    for (int r = 0; r < D; ++r) fin = fin + vv[r];
    const bool ok = and_not(valid, good & (abs(fin) < P::set1(std::numeric_limits<S>::infinity()))).bits() == 0u;
    for (int r = 0; r < D; ++r) vv[r].store(ptr(v, r, o));
    b.store(&beta[static_cast<std::size_t>(o)]);
    ib.store(&inv_beta[static_cast<std::size_t>(o)]);
    P lz[D];
    apply(vv, b, zu, lz);
    for (int r = 0; r < D; ++r) lz[r].store(ptr(lambda, r, o));
    P col[D][7];
    for (int c = 0; c < 7; ++c) {
      P fc[D], wc[D];
      for (int r = 0; r < D; ++r) fc[r] = P::load(&F[static_cast<std::size_t>((7 * r + c) * stride + o)]);
      apply_inverse(vv, ib, fc, wc);
      for (int r = 0; r < D; ++r) {
        wc[r].store(&WF[static_cast<std::size_t>((7 * r + c) * stride + o)]);
        col[r][c] = wc[r];
      }
    }
    int e = 0;
    for (int a = 0; a < 7; ++a)
      for (int c = a; c < 7; ++c, ++e)
        for (int r = 0; r < D; ++r) acc[e] = mul_add(col[r][a], col[r][c], acc[e]);
    return ok;
  }
  template <class M7>
  static void add_upper(const P (&acc)[32], M7& H) {
    S h[32];
    P::sum_each(acc, 32, h);
    int e = 0;
    for (int a = 0; a < 7; ++a)
      for (int c = a; c < 7; ++c, ++e) {
        H(a, c) += h[e];
        if (c != a) H(c, a) += h[e];
      }
  }
  static S least(P t) {  // the least lane
    alignas(64) S lanes[8];
    t.store(lanes);
    return *std::min_element(lanes, lanes + width);
  }
  template <class Fn>
  void for_blocks(Fn&& fn) const {
    for (int b = 0; b < blocks; ++b) fn(b * width, P::first(n - b * width));
  }
  static S* ptr(Field& f, int r, int o) { return &f[static_cast<std::size_t>(r * stride + o)]; }
  static const S* ptr(const Field& f, int r, int o) { return &f[static_cast<std::size_t>(r * stride + o)]; }
  static void load(const Field& f, int o, P (&u)[D]) {
    for (int r = 0; r < D; ++r) u[r] = P::load(ptr(f, r, o));
  }
  static P max(P a, P b) { return select(a > b, a, b); }
  static P min(P a, P b) { return select(a < b, a, b); }
  static P dot(const P (&a)[D], const P (&b)[D]) {
    P t = a[0] * b[0];
    for (int r = 1; r < D; ++r) t = mul_add(a[r], b[r], t);
    return t;
  }
  /// u_0^2 - |u_1|^2 as (u_0 - |u_1|)(u_0 + |u_1|).
  static P det(const P (&u)[D]) {
    if constexpr (D == 1) {
      return u[0] * u[0];
    } else {
      P t2 = u[1] * u[1];
      for (int r = 2; r < D; ++r) t2 = mul_add(u[r], u[r], t2);
      const P t = sqrt(t2);
      return (u[0] - t) * (u[0] + t);
    }
  }
  static typename P::Mask interior(const P (&u)[D]) {
    P t2 = P::set1(S(0));
    for (int r = 1; r < D; ++r) t2 = mul_add(u[r], u[r], t2);
    return (u[0] > sqrt(t2)) & (abs(u[0]) < P::set1(std::numeric_limits<S>::infinity()));
  }
  /// out = M_i x over the 7 columns of a D x 7 map M in lanes (x broadcast).
  static void map(const S* m, int o, const V7& x, P (&out)[D]) {
    for (int r = 0; r < D; ++r) {
      P t = P::load(m + (7 * r) * stride + o) * P::set1(x(0));
      for (int c = 1; c < 7; ++c) t = mul_add(P::load(m + (7 * r + c) * stride + o), P::set1(x(c)), t);
      out[r] = t;
    }
  }
  /// acc_c += sum_r M_rc u_r (lane-wise partial sums of M^T u).
  static void transpose_map(const S* m, int o, const P (&u)[D], P (&acc)[8]) {
    for (int c = 0; c < 7; ++c)
      for (int r = 0; r < D; ++r) acc[c] = mul_add(P::load(m + (7 * r + c) * stride + o), u[r], acc[c]);
  }
  static V7 sums(const P (&acc)[8]) {
    S out[8];
    P::sum_each(acc, 8, out);
    return V7(out[0], out[1], out[2], out[3], out[4], out[5], out[6]);
  }
  /// W u = beta (2 (v . u) v - J u).
  static void apply(const P (&vv)[D], P b, const P (&u)[D], P (&out)[D]) {
    const P t = P::set1(S(2)) * dot(vv, u);
    out[0] = b * (t * vv[0] - u[0]);
    for (int r = 1; r < D; ++r) out[r] = b * mul_add(t, vv[r], u[r]);
  }
  /// W^-1 u = (2 (Jv . u) Jv - J u) / beta.
  static void apply_inverse(const P (&vv)[D], P ib, const P (&u)[D], P (&out)[D]) {
    P jvu = vv[0] * u[0];
    for (int r = 1; r < D; ++r) jvu = neg_mul_add(vv[r], u[r], jvu);
    const P t = P::set1(S(2)) * jvu;
    out[0] = ib * (t * vv[0] - u[0]);
    for (int r = 1; r < D; ++r) out[r] = ib * neg_mul_add(t, vv[r], u[r]);
  }
  /// The largest a >= 0 with u + a du in Q (infinity if none), per lane: see the file comment.
  static P ray_step(const P (&u)[D], const P (&du)[D]) {
    const P inf = P::set1(std::numeric_limits<S>::infinity()), zero = P::set1(S(0));
    P best = select(du[0] < zero, zero - u[0] / du[0], inf);
    if constexpr (D > 1) {
      const P A = det(du), C = det(u);
      P B = u[0] * du[0];
      for (int r = 1; r < D; ++r) B = neg_mul_add(u[r], du[r], B);
      const P disc = B * B - A * C;
      const typename P::Mask a_zero = (A <= zero) & (!(A < zero));
      // A == 0: the root -C / (2B) when B < 0.
      const P lin = zero - C / (P::set1(S(2)) * B);
      best = select(a_zero & (B < zero), min(best, lin), best);
      // Roots (-B -+ sqrt(disc)) / A as q / A and C / q, q = -(B + sign(B) sqrt(disc)).
      const typename P::Mask real = (!a_zero) & (zero <= disc);
      const P sq = sqrt(select(real, disc, zero));
      const P q = zero - (B + select(B < zero, zero - sq, sq));
      const typename P::Mask use = real & ((q < zero) | (q > zero));
      const P r1 = q / select(use, A, P::set1(S(1))), r2 = C / select(use, q, P::set1(S(1)));
      best = select(use & (r1 > zero), min(best, r1), best);
      best = select(use & (r2 > zero), min(best, r2), best);
    }
    return best;
  }
};

}  // namespace detail
}  // namespace grip
