#pragma once
/// \file
/// The per-contact work of the interior-point method (interior_point.hpp), on the contacts in
/// SIMD lanes (namespace grip::detail). Every contact i owns one second-order cone Q of
/// dimension D (cone_packs.hpp) and the data of
///
///     minimise   sum_i 1/2 u_i^T P_i u_i + q_i^T u_i  (+ 1/2 |sum_i A_i u_i - b|^2: the soft form)
///     subject to sum_i A_i u_i = b  (six rows; none in the soft form),
///                u_i in Q,   u_i0 <= c_i  (an optional bound on the first component),
///
/// with P_i diagonal (D entries >= 0, the last D - 1 equal when D = 3), q_i (D) and A_i (6 x D).
/// The homogeneous embedding (interior_point.hpp) keeps in these lanes the cone variable u_i (its
/// own slack), its dual z_i, and for a bound the slack s_i = c_i tau - u_i0 >= 0 and its dual
/// t_i >= 0; the multipliers y, tau, kappa and, in the soft form, r = A u - b live in the driver.
///
/// Eliminating z_i, s_i and t_i from the Newton system leaves, per contact,
///     B_i du_i + A_i^T dy + qt_i dtau = g_i,     B_i = P_i + W_i^-2 + e e^T t_i / s_i,
/// (W_i the Nesterov-Todd scaling of (u_i, z_i), qt_i = q_i - e c_i t_i / s_i, e = (1, 0, ...)),
/// and the driver's 6 x 6 Schur complement S = sum_i A_i B_i^-1 A_i^T. B_i^-1 is formed in the
/// scaling's eigenframe (NtFrame), where W_i^-2 is diagonal: each eigen-direction keeps its own
/// relative accuracy as W_i^-2 spreads over many orders of magnitude near the optimum.
///
/// Each iteration makes five passes: assemble (the step just taken, the residuals, the scalings,
/// B_i^-1, S and the right-hand sides' forward sums), backsolve (the constant system's and the
/// predictor's solutions, formed explicitly: the embedding's tau row needs their products with
/// the gradient row, which the forward sums give only with cancellation), predict (the affine
/// direction, its step, and Mehrotra's corrector in three parts linear in sigma and sigma mu, so
/// that sigma can be chosen after the pass), backsolve_corrector and correct. The driver solves
/// its 6 x 6 systems between the passes.
///
/// Storage is a structure of arrays, one row of `stride` lanes per component (no heap); lanes past
/// the last contact hold u = z = e, A = 0, P = 1, q = 0 and no bound, and are masked out of every
/// sum and step.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "grip/core/simd.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/cone_packs.hpp"

namespace grip {
namespace detail {

/// The pack of the interior-point lanes for up to Cap contacts: the widest compiled in, except
/// that with AVX-512 a grasp of at most 4 contacts takes 4-lane packs (half the work).
template <class S, int Cap>
struct ConicPackOf {
  using type = SimdPack<S>;
};
#if GRIP_SIMD_AVX512 && GRIP_SIMD_AVX2
template <int Cap>
struct ConicPackOf<double, Cap> {
  using type = typename std::conditional<(Cap <= 4), PackD4, PackD8>::type;
};
#endif

/// The sums of ConicLanes::assemble, at the iterate (u, z, s, t, y, tau). gq_i and gp_i are the
/// right-hand sides of the constant system and of the predictor (see ConicLanes).
template <class S>
struct AssembleSums {
  Matrix6<S> schur;  ///< S = sum A_i B_i^-1 A_i^T (symmetric)
  Wrench<S> au;      ///< sum A_i u_i
  Wrench<S> a_bq;    ///< sum A_i B_i^-1 gq_i
  Wrench<S> a_bp;    ///< sum A_i B_i^-1 gp_i
  S kp{0};           ///< sum -c_i (t_i / s_i)(rb_i - s_i): the predictor's bound term of the tau row
  Wrench<S> h;       ///< sum A_i B_i^-1 c_i, c_i = q_i + 2 P_i u_i / tau + e c_i t_i / s_i (the tau row)
  S c_bq{0};         ///< sum c_i^T B_i^-1 gq_i
  S c_bp{0};         ///< sum c_i^T B_i^-1 gp_i
  S cc_hb{0};        ///< sum c_i^2 t_i / s_i (bound rows)
  S upu{0};          ///< sum u_i^T P_i u_i
  S qu{0};           ///< sum q_i^T u_i
  S ct{0};           ///< sum c_i t_i (b^T z over the bound rows)
  S gap{0};          ///< sum u_i^T z_i + s_i t_i
  S rx2{0};          ///< |rx|^2, rx_i = P_i u_i + A_i^T y - z_i + q_i tau + e t_i
  S rb2{0};          ///< |rb|^2, rb_i = u_i0 + s_i - c_i tau (bound rows)
  S x2{0};           ///< sum |M_i u_i|^2 (ConicLanes::set's metric): the forces' squared norm
  S z2{0};           ///< sum |z_i|^2 + t_i^2
  S certificate{0};  ///< min_i margin(A_i^T y + e t_i): a primal infeasibility certificate needs >= 0
  bool ok{true};     ///< every scaling valid (both variables interior, finite)
};

/// The sums of ConicLanes::predict. The corrector's right-hand side is g0 + sigma g1 + sigma mu g2.
template <class S>
struct PredictSums {
  Wrench<S> a_bg[3];  ///< sum A_i B_i^-1 g_k,i (k = 0, 1, 2)
  S c_bg[3]{};        ///< sum c_i^T B_i^-1 g_k,i
  S k[3]{};           ///< the corrector's bound terms of the tau row, parts 0, 1, 2
  S step{0};          ///< the largest step in [0, inf) keeping u, z, s, t in their cones
  S gap1{0};          ///< sum u^T dz + du^T z + s dt + ds t
  S gap2{0};          ///< sum du^T dz + ds dt
  /// sum |W^-1 u2|^2 + (u2 - u / tau)^T P (u2 - u / tau) + (t / s)(u2_0 - c)^2: minus the tau
  /// row's denominator less kappa / tau, as a sum of squares (the linear form from assemble's
  /// sums cancels, which float cannot afford near the optimum).
  S den{0};
};

/// The contacts' cones, data and iterate in SIMD lanes (see the file comment).
template <class S, int D, int Cap>
class ConicLanes {
 public:
  using P = typename ConicPackOf<S, Cap>::type;
  using Mask = typename P::Mask;
  using Vec = ConeVec<P, D>;
  static constexpr int width = P::width;
  static constexpr int stride = (Cap + 7) / 8 * 8;  ///< lanes per component (a multiple of every width)
  static constexpr int tri = D * (D + 1) / 2;       ///< entries of a symmetric D x D matrix
  using Field = std::array<S, static_cast<std::size_t>(D * stride)>;
  using Column = std::array<S, static_cast<std::size_t>(stride)>;
  using Map = Eigen::Matrix<S, 6, D>;
  using ConeVector = Eigen::Matrix<S, D, 1>;

  /// `contacts` cones (at most Cap), all inert (A = 0, P = 1, q = 0, no bound) until set().
  explicit ConicLanes(int contacts) { clear(contacts); }

  /// As constructed: `contacts` inert cones at the centre.
  void clear(int contacts) {
    n_ = contacts;
    blocks_ = (contacts + width - 1) / width;
    bounded_ = false;
    bound_count_ = 0;
    bound_scale_ = S(0);
    a_.fill(S(0));
    q_.fill(S(0));
    p_.fill(S(1));
    metric_.fill(S(0));
    c_.fill(std::numeric_limits<S>::infinity());
    start();
  }

  /// Contacts.
  int size() const { return n_; }
  /// The cones' degree in the embedding's centring: one per cone and one per bound.
  int degree() const { return n_ + bound_count_; }
  /// The largest finite bound c_i (0 without any): the scale of the bound rows' residuals.
  S bound_scale() const { return bound_scale_; }

  /// Contact i's data: A_i, the diagonal of P_i (entries >= 0, the last two equal when D = 3),
  /// q_i, the bound c_i on u_i0 (a finite value > 0, or infinity for none), and the diagonal of
  /// M_i^T M_i, the metric in which |u_i| measures the contact's force (AssembleSums::x2).
  void set(int i, const Map& a, const ConeVector& p, const ConeVector& q, S bound, const ConeVector& metric) {
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < D; ++k) a_[at(r * D + k, i)] = a(r, k);
    for (int k = 0; k < D; ++k) {
      p_[at(k, i)] = p(k);
      q_[at(k, i)] = q(k);
      metric_[at(k, i)] = metric(k);
    }
    c_[idx(i)] = bound;
    if (bound < std::numeric_limits<S>::infinity()) {
      bounded_ = true;
      ++bound_count_;
      bound_scale_ = std::max(bound_scale_, bound);
    }
  }

  /// Every variable at its cone's centre: u = z = e, and s = t = 1 for a bound.
  void start() {
    u_.fill(S(0));
    z_.fill(S(0));
    du_.fill(S(0));
    dz_.fill(S(0));
    for (int i = 0; i < stride; ++i) {
      u_[idx(i)] = z_[idx(i)] = S(1);
      s_[idx(i)] = t_[idx(i)] = S(1);
      ds_[idx(i)] = dt_[idx(i)] = S(0);
    }
  }

  /// Contact i's cone variable u_i and dual z_i, and its bound's slack and dual.
  ConeVector u(int i) const { return read(u_, i); }
  ConeVector z(int i) const { return read(z_, i); }
  S bound_slack(int i) const { return s_[idx(i)]; }
  S bound_dual(int i) const { return t_[idx(i)]; }

  /// Pass 1: takes the last step (u += alpha du, z += alpha dz, and the bounds' s, t; nothing for
  /// alpha = 0), then at the new point and multipliers y, tau: the residuals rx_i, rb_i, the
  /// scalings, B_i^-1 (all kept for the next passes) and the sums of AssembleSums.
  AssembleSums<S> assemble(S alpha, const Wrench<S>& y, S tau) {
    return bounded_ ? assemble_impl<true>(alpha, y, tau) : assemble_impl<false>(alpha, y, tau);
  }

  /// Pass 2, the predictor (affine direction): with the constant system's y2, the predictor's y1,
  /// the direction's dtau and dy = y1 + dtau y2 (the driver's solves from assemble's sums):
  /// u2_i = B_i^-1 (gq_i - A_i^T y2) (kept), du_i = B_i^-1 (gp_i - A_i^T y1) + dtau u2_i and the
  /// rest of the direction (kept), its step length, and the corrector's parts (kept, and summed).
  PredictSums<S> predict(const Wrench<S>& y1, const Wrench<S>& y2, S dtau, const Wrench<S>& dy, S tau) {
    return bounded_ ? predict_impl<true>(y1, y2, dtau, dy, tau) : predict_impl<false>(y1, y2, dtau, dy, tau);
  }

  /// Pass 3, the corrector: with its y1 (the driver's solve of the summed right-hand side), dtau
  /// and dy = y1 + dtau y2, the direction du_i = B_i^-1 (g_i - A_i^T y1) + dtau u2_i and the rest
  /// (kept for assemble's step); returns its step length. `sigma_mu` = sigma mu.
  S correct(const Wrench<S>& y1, S dtau, const Wrench<S>& dy, S sigma, S sigma_mu) {
    return bounded_ ? correct_impl<true>(y1, dtau, dy, sigma, sigma_mu) : correct_impl<false>(y1, dtau, dy, sigma, sigma_mu);
  }

 private:
  /// The passes, for grasps with (Bounded) and without bounds: without, every bound term is
  /// compiled out.
  template <bool Bounded>
  AssembleSums<S> assemble_impl(S alpha, const Wrench<S>& y, S tau) {
    const P pa = P::set1(alpha), ptau = P::set1(tau), zero = P::set1(S(0));
    const P one = P::set1(S(1)), inf = P::set1(std::numeric_limits<S>::infinity());
    P py[6];
    for (int r = 0; r < 6; ++r) py[r] = P::set1(y(r));
    // Sums: au 0-5, S 6-26, a_bq 27-32, a_bp 33-38, the scalars 39-47, h 48-53, c_bq 54, c_bp 55,
    // cc_hb 56.
    constexpr int nacc = 64;
    const P itau2 = P::set1(S(2) / tau);
    P acc[nacc];
    for (P& e : acc) e = zero;
    P cert = inf;
    bool ok = true;
    for (int b = 0; b < blocks_; ++b) {
      const int o = b * width;
      const Mask valid = P::first(n_ - o);
      Vec u = load(u_, o), z = load(z_, o);
      P s = P::load(&s_[idx(o)]), t = P::load(&t_[idx(o)]);
      if (alpha != S(0)) {
        const Vec du = load(du_, o), dz = load(dz_, o);
        for (int r = 0; r < D; ++r) {
          u[r] = mul_add(pa, du[r], u[r]);
          z[r] = mul_add(pa, dz[r], z[r]);
        }
        store(u_, o, u);
        store(z_, o, z);
        if constexpr (Bounded) {
          s = mul_add(pa, P::load(&ds_[idx(o)]), s);
          t = mul_add(pa, P::load(&dt_[idx(o)]), t);
          s.store(&s_[idx(o)]);
          t.store(&t_[idx(o)]);
        }
      }
      const auto a = load_map(o);
      const Vec p = load(p_, o), q = load(q_, o);
      // The bound row (lanes without one: t = 0, so it adds nothing).
      P bt = zero, bs = one, cb = zero, hb = zero, rb = zero;
      Mask has = P::first(0);
      if constexpr (Bounded) {
        const P c = P::load(&c_[idx(o)]);
        has = c < inf;
        bt = select(has, t, zero);
        bs = select(has, s, one);
        cb = select(has, c, zero);
        hb = bt / bs;  // t / s
        rb = select(has, u[0] + bs - cb * ptau, zero);
        rb.store(&rb_[idx(o)]);
        hb.store(&hb_[idx(o)]);
      }
      // A^T y and the dual residual rx = P u + A^T y - z + q tau + e t.
      Vec aty, rx, pu;
      for (int k = 0; k < D; ++k) {
        P v = a[0][k] * py[0];
        for (int r = 1; r < 6; ++r) v = mul_add(a[r][k], py[r], v);
        aty[k] = v;
        pu[k] = p[k] * u[k];
        rx[k] = mul_add(q[k], ptau, pu[k] + v - z[k]);
      }
      if constexpr (Bounded) {
        rx[0] = rx[0] + bt;
        aty[0] = aty[0] + bt;
      }
      store(rx_, o, rx);
      const P margin = cone_margin<P, D>(aty);
      cert = select(valid & (margin < cert), margin, cert);
      // The scaling (its frame kept) and B^-1.
      const NtFrame<P, D> k = nt_frame<P, D>(u, z);
      ok = ok && and_not(valid, k.ok & (bs > zero) & !(bt < zero)).bits() == 0u;
      store_frame(o, k);
      const Sym bi = inverse_from_frame(k, p, hb);
      for (int e = 0; e < tri; ++e) bi[idx(e)].store(&binv_[at(e, o)]);
      // B^-1 applied to the constant system's and the predictor's right-hand sides.
      const Vec fq = sym_apply(bi, constant_rhs<Bounded>(q, hb, cb)),
                fp = sym_apply(bi, predictor_rhs<Bounded>(rx, z, hb, bs, rb));
      const Vec cgt = gradient_row<Bounded>(p, q, u, itau2, cb, hb);
      const Vec fc = sym_apply(bi, cgt);
      for (int r = 0; r < 6; ++r) acc[48 + r] = acc[48 + r] + cone_dot<P, D>(a[r], fc);
      acc[54] = acc[54] + select(valid, cone_dot<P, D>(cgt, fq), zero);
      acc[55] = acc[55] + select(valid, cone_dot<P, D>(cgt, fp), zero);
      // A B^-1 (for S), A u and the forward sums.
      P ab[6][D];
      for (int r = 0; r < 6; ++r)
        for (int j = 0; j < D; ++j) {
          P v = zero;
          for (int l = 0; l < D; ++l) v = mul_add(a[r][l], bi[sym(l, j)], v);
          ab[r][j] = v;
        }
      int e = 6;
      for (int r = 0; r < 6; ++r) {
        acc[r] = acc[r] + cone_dot<P, D>(a[r], u);
        acc[27 + r] = acc[27 + r] + cone_dot<P, D>(a[r], fq);
        acc[33 + r] = acc[33 + r] + cone_dot<P, D>(a[r], fp);
        for (int l = r; l < 6; ++l, ++e) {
          P v = acc[e];
          for (int j = 0; j < D; ++j) v = mul_add(ab[r][j], a[l][j], v);
          acc[e] = v;
        }
      }
      // Scalars, masked to the contacts.
      const auto add = [&](int j, P v) { acc[j] = acc[j] + select(valid, v, zero); };
      add(40, cone_dot<P, D>(u, pu));
      add(41, cone_dot<P, D>(q, u));
      add(44, cone_dot<P, D>(rx, rx));
      if constexpr (Bounded) {
        add(39, zero - cb * hb * (rb - bs));
        add(42, cb * bt);
        add(56, cb * cb * hb);
        add(43, mul_add(bs, bt, cone_dot<P, D>(u, z)));
        add(45, rb * rb);
        add(46, metric_norm(o, u));
        add(47, mul_add(bt, bt, cone_dot<P, D>(z, z)));
      } else {
        add(43, cone_dot<P, D>(u, z));
        add(46, metric_norm(o, u));
        add(47, cone_dot<P, D>(z, z));
      }
    }
    S tot[nacc];
    sum_all(acc, tot, nacc);
    AssembleSums<S> out;
    int e = 6;
    for (int r = 0; r < 6; ++r) {
      out.au(r) = tot[r];
      out.a_bq(r) = tot[27 + r];
      out.a_bp(r) = tot[33 + r];
      for (int l = r; l < 6; ++l, ++e) out.schur(r, l) = out.schur(l, r) = tot[e];
    }
    out.kp = tot[39];
    out.upu = tot[40];
    out.qu = tot[41];
    out.ct = tot[42];
    out.gap = tot[43];
    out.rx2 = tot[44];
    out.rb2 = tot[45];
    out.x2 = tot[46];
    out.z2 = tot[47];
    for (int r = 0; r < 6; ++r) out.h(r) = tot[48 + r];
    out.c_bq = tot[54];
    out.c_bp = tot[55];
    out.cc_hb = tot[56];
    out.certificate = least(cert);
    out.ok = ok && std::isfinite(out.schur.sum());
    return out;
  }

  template <bool Bounded>
  PredictSums<S> predict_impl(const Wrench<S>& y1, const Wrench<S>& y2, S dtau, const Wrench<S>& dy, S tau) {
    const P zero = P::set1(S(0)), one = P::set1(S(1)), inf = P::set1(std::numeric_limits<S>::infinity());
    const P pdt = P::set1(dtau), itau2 = P::set1(S(2) / tau);
    P pdy[6], py1[6], py2[6];
    for (int r = 0; r < 6; ++r) {
      pdy[r] = P::set1(dy(r));
      py1[r] = P::set1(y1(r));
      py2[r] = P::set1(y2(r));
    }
    // Sums: a_bg[0..2] 0-17, k 18-20, gap1 21, gap2 22, den 23, c_bg 24-26.
    constexpr int nacc = 32;
    P acc[nacc];
    for (P& e : acc) e = zero;
    P step = inf;
    for (int b = 0; b < blocks_; ++b) {
      const int o = b * width;
      const Mask valid = P::first(n_ - o);
      const auto a = load_map(o);
      const Vec p = load(p_, o), q = load(q_, o), u = load(u_, o), z = load(z_, o), rx = load(rx_, o);
      Bound b0;
      if constexpr (Bounded) b0 = load_bound(o);
      const Sym bi = load_sym(o);
      const Vec u2 = sym_apply(bi, minus_transpose(constant_rhs<Bounded>(q, b0.hb, b0.c), a, py2));
      store(u2_, o, u2);
      const NtFrame<P, D> frame = load_frame(o);
      {
        const Vec wu = nt_frame_apply<true, P, D>(frame, u2);
        P sq = cone_dot<P, D>(wu, wu);
        const P itau = P::set1(S(1) / tau);
        for (int j = 0; j < D; ++j) {
          const P e = neg_mul_add(u[j], itau, u2[j]);
          sq = mul_add(p[j] * e, e, sq);
        }
        if constexpr (Bounded) {
          const P e = u2[0] - b0.c;
          sq = mul_add(b0.hb * e, e, sq);
        }
        acc[23] = acc[23] + select(valid, sq, zero);
      }
      Vec du = sym_apply(bi, minus_transpose(predictor_rhs<Bounded>(rx, z, b0.hb, b0.s, b0.rb), a, py1));
      for (int k = 0; k < D; ++k) du[k] = mul_add(pdt, u2[k], du[k]);
      // The bound's direction: dt = (t/s)(du_0 - c dtau + rb - s), ds = -s - (s/t) dt.
      P dt = zero, ds = zero;
      if constexpr (Bounded) {
        dt = select(b0.has, b0.hb * (du[0] - b0.c * pdt + b0.rb - b0.s), zero);
        ds = select(b0.has, zero - b0.s - b0.s * b0.it * dt, zero);
        ds.store(&ds_[idx(o)]);
        dt.store(&dt_[idx(o)]);
      }
      const Vec dz = dual_direction<Bounded>(a, p, q, du, pdy, pdt, rx, dt);
      store(du_, o, du);
      store(dz_, o, dz);
      step = min(step, step_length<Bounded>(u, frame.det_u, du, z, frame.det_z, dz, b0, ds, dt, valid));
      const auto add = [&](int j, P v) { acc[j] = acc[j] + select(valid, v, zero); };
      P g1 = cone_dot<P, D>(u, dz) + cone_dot<P, D>(du, z), g2 = cone_dot<P, D>(du, dz);
      if constexpr (Bounded) {
        g1 = g1 + mul_add(b0.s, dt, ds * b0.t);
        g2 = mul_add(ds, dt, g2);
      }
      add(21, g1);
      add(22, g2);
      // Mehrotra: W^-1 (lambda \ (lambda o lambda + (W^-1 du) o (W dz))) = z + W^-1 (lambda \ m),
      // m = (W^-1 du) o (W dz); and W^-1 (lambda \ e) = u^-1 = J u / det u (lambda = W^-1 u).
      const Vec l = load(lambda_, o);
      const Vec m = jordan_product<P, D>(nt_frame_apply<true, P, D>(frame, du), nt_frame_apply<false, P, D>(frame, dz));
      Vec cc = nt_frame_apply<true, P, D>(frame, jordan_divide<P, D>(l, frame.det_lambda, m));
      for (int j = 0; j < D; ++j) cc[j] = cc[j] + z[j];
      const P idu = one / frame.det_u;
      Vec ce;
      ce[0] = u[0] * idu;
      for (int j = 1; j < D; ++j) ce[j] = zero - u[j] * idu;
      store(cc_, o, cc);
      store(ce_, o, ce);
      P dsdt = zero;
      if constexpr (Bounded) {
        dsdt = ds * dt;
        dsdt.store(&bc_[idx(o)]);
      }
      Vec g[3];
      corrector_parts<Bounded>(rx, cc, ce, b0, dsdt, g);
      const Vec cg = gradient_row<Bounded>(p, q, u, itau2, b0.c, b0.hb);
      for (int j = 0; j < 3; ++j) {
        const Vec f = sym_apply(bi, g[j]);
        for (int r = 0; r < 6; ++r) acc[6 * j + r] = acc[6 * j + r] + cone_dot<P, D>(a[r], f);
        add(24 + j, cone_dot<P, D>(cg, f));
      }
      if constexpr (Bounded) {
        // The tau row's bound terms: -c (t/s)((1 - sigma) rb - s - ds dt / t + sigma mu / t).
        add(18, zero - b0.c * b0.hb * (b0.rb - b0.s - dsdt * b0.it));
        add(19, b0.c * b0.hb * b0.rb);
        add(20, zero - b0.c * b0.is);
      }
    }
    S tot[nacc];
    sum_all(acc, tot, nacc);
    PredictSums<S> out;
    for (int j = 0; j < 3; ++j) {
      for (int r = 0; r < 6; ++r) out.a_bg[j](r) = tot[6 * j + r];
      out.k[j] = tot[18 + j];
      out.c_bg[j] = tot[24 + j];
    }
    out.gap1 = tot[21];
    out.gap2 = tot[22];
    out.den = tot[23];
    out.step = least(step);
    return out;
  }

  template <bool Bounded>
  S correct_impl(const Wrench<S>& y1, S dtau, const Wrench<S>& dy, S sigma, S sigma_mu) {
    const P zero = P::set1(S(0)), inf = P::set1(std::numeric_limits<S>::infinity());
    const P pdt = P::set1(dtau), psig = P::set1(sigma), psm = P::set1(sigma_mu), keep = P::set1(S(1) - sigma);
    P pdy[6], py1[6];
    for (int r = 0; r < 6; ++r) {
      pdy[r] = P::set1(dy(r));
      py1[r] = P::set1(y1(r));
    }
    P step = inf;
    for (int b = 0; b < blocks_; ++b) {
      const int o = b * width;
      const Mask valid = P::first(n_ - o);
      const auto a = load_map(o);
      const Vec p = load(p_, o), q = load(q_, o), u = load(u_, o), z = load(z_, o), rx = load(rx_, o);
      const Vec u2 = load(u2_, o), cc = load(cc_, o), ce = load(ce_, o);
      Bound b0;
      P dsdt = zero;
      if constexpr (Bounded) {
        b0 = load_bound(o);
        dsdt = P::load(&bc_[idx(o)]);
      }
      Vec g[3];
      corrector_parts<Bounded>(rx, cc, ce, b0, dsdt, g);
      Vec gc;
      for (int k = 0; k < D; ++k) gc[k] = mul_add(psm, g[2][k], mul_add(psig, g[1][k], g[0][k]));
      Vec du = sym_apply(load_sym(o), minus_transpose(gc, a, py1));
      for (int k = 0; k < D; ++k) du[k] = mul_add(pdt, u2[k], du[k]);
      P dt = zero, ds = zero;
      if constexpr (Bounded) {
        // d_b = (1 - sigma) rb, d_sb / t = s + (ds dt - sigma mu) / t.
        const P dsb = b0.s + (dsdt - psm) * b0.it;
        dt = select(b0.has, b0.hb * (du[0] - b0.c * pdt + keep * b0.rb - dsb), zero);
        ds = select(b0.has, zero - dsb - b0.s * b0.it * dt, zero);
        ds.store(&ds_[idx(o)]);
        dt.store(&dt_[idx(o)]);
      }
      Vec krx;
      for (int k = 0; k < D; ++k) krx[k] = keep * rx[k];
      const Vec dz = dual_direction<Bounded>(a, p, q, du, pdy, pdt, krx, dt);
      store(du_, o, du);
      store(dz_, o, dz);
      step = min(step, step_length<Bounded>(u, P::load(&detu_[idx(o)]), du, z, P::load(&detz_[idx(o)]), dz, b0, ds, dt,
                                            valid));
    }
    return least(step);
  }

  using Sym = std::array<P, static_cast<std::size_t>(tri)>;
  /// A contact's bound row in lanes: lanes without one hold s = 1, t = 0, c = 0.
  struct Bound {
    Mask has{P::first(0)};
    P s{P::set1(S(1))}, t{P::set1(S(0))}, c{P::set1(S(0))}, hb{P::set1(S(0))}, rb{P::set1(S(0))};
    P it{P::set1(S(1))}, is{P::set1(S(1))};  ///< 1 / t (1 without a bound), 1 / s
  };
  Bound load_bound(int o) const {
    const P zero = P::set1(S(0)), one = P::set1(S(1));
    Bound b;
    const P c = P::load(&c_[idx(o)]);
    b.has = c < P::set1(std::numeric_limits<S>::infinity());
    b.s = select(b.has, P::load(&s_[idx(o)]), one);
    b.t = select(b.has, P::load(&t_[idx(o)]), zero);
    b.c = select(b.has, c, zero);
    b.hb = P::load(&hb_[idx(o)]);
    b.rb = P::load(&rb_[idx(o)]);
    b.it = one / select(b.has, b.t, one);
    b.is = select(b.has, b.hb * b.it, zero);
    return b;
  }
  static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
  static std::size_t at(int row, int lane) { return static_cast<std::size_t>(row * stride + lane); }
  /// The entry (r, c) of a symmetric D x D matrix stored as its upper triangle, row by row.
  static constexpr std::size_t sym(int r, int c) {
    return r <= c ? static_cast<std::size_t>(r * D - r * (r - 1) / 2 + (c - r))
                  : static_cast<std::size_t>(c * D - c * (c - 1) / 2 + (r - c));
  }

  template <class F>
  static Vec load(const F& f, int o) {
    Vec v;
    for (int r = 0; r < D; ++r) v[idx(r)] = P::load(&f[at(r, o)]);
    return v;
  }
  template <class F>
  static void store(F& f, int o, const Vec& v) {
    for (int r = 0; r < D; ++r) v[idx(r)].store(&f[at(r, o)]);
  }
  std::array<Vec, 6> load_map(int o) const {
    std::array<Vec, 6> m;
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < D; ++k) m[idx(r)][idx(k)] = P::load(&a_[at(r * D + k, o)]);
    return m;
  }
  Sym load_sym(int o) const {
    Sym m;
    for (int e = 0; e < tri; ++e) m[idx(e)] = P::load(&binv_[at(e, o)]);
    return m;
  }
  void store_frame(int o, const NtFrame<P, D>& k) {
    k.beta.store(&beta_[idx(o)]);
    k.inv_beta.store(&inv_beta_[idx(o)]);
    k.dp.store(&dp_[idx(o)]);
    k.dm.store(&dm_[idx(o)]);
    k.det_u.store(&detu_[idx(o)]);
    k.det_z.store(&detz_[idx(o)]);
    k.det_lambda.store(&detl_[idx(o)]);
    store(f_, o, k.f);
    store(lambda_, o, k.lambda);
  }
  NtFrame<P, D> load_frame(int o) const {
    NtFrame<P, D> k;
    k.beta = P::load(&beta_[idx(o)]);
    k.inv_beta = P::load(&inv_beta_[idx(o)]);
    k.dp = P::load(&dp_[idx(o)]);
    k.dm = P::load(&dm_[idx(o)]);
    k.det_u = P::load(&detu_[idx(o)]);
    k.det_z = P::load(&detz_[idx(o)]);
    k.det_lambda = P::load(&detl_[idx(o)]);
    k.f = load(f_, o);
    k.lambda = load(lambda_, o);
    return k;
  }
  ConeVector read(const Field& f, int i) const {
    ConeVector v;
    for (int r = 0; r < D; ++r) v(r) = f[at(r, i)];
    return v;
  }
  static P min(P x, P y) { return select(x < y, x, y); }
  /// |M u|^2 = sum_k metric_k u_k^2 for the lanes at o.
  P metric_norm(int o, const Vec& u) const {
    const Vec m = load(metric_, o);
    P v = m[0] * u[0] * u[0];
    for (int k = 1; k < D; ++k) v = mul_add(m[idx(k)] * u[idx(k)], u[idx(k)], v);
    return v;
  }
  /// g - A^T y.
  static Vec minus_transpose(const Vec& g, const std::array<Vec, 6>& a, const P (&y)[6]) {
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
  static Vec dual_direction(const std::array<Vec, 6>& a, const Vec& p, const Vec& q, const Vec& du, const P (&dy)[6],
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
  static void corrector_parts(const Vec& rx, const Vec& cc, const Vec& ce, const Bound& b, P dsdt, Vec (&g)[3]) {
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
  /// The sums across the lanes of `count` packs (a multiple of 8).
  static void sum_all(const P* acc, S* out, int count) {
    if constexpr (P::width > 1) {
      P::sum_each(acc, count, out);
    } else {
      for (int e = 0; e < count; ++e) out[e] = acc[e].sum();
    }
  }
  /// The least lane.
  static S least(P v) {
    alignas(64) S lanes[8];
    v.store(lanes);
    S m = lanes[0];
    for (int k = 1; k < width; ++k) m = lanes[k] < m ? lanes[k] : m;
    return m;
  }

  int n_{0};
  int blocks_{0};
  bool bounded_{false};
  int bound_count_{0};
  S bound_scale_{0};
  // The problem.
  std::array<S, static_cast<std::size_t>(6 * D * stride)> a_;
  Field p_, q_, metric_;
  Column c_;
  // The iterate, its direction, and what the passes hand on to each other.
  Field u_, z_, du_, dz_, rx_, f_, lambda_, u2_, cc_, ce_;
  std::array<S, static_cast<std::size_t>(tri * stride)> binv_;
  Column s_, t_, ds_, dt_, rb_, hb_, bc_, beta_, inv_beta_, dp_, dm_, detu_, detz_, detl_;
};

}  // namespace detail
}  // namespace grip
