#pragma once
/// \file
/// The interior-point method's search direction over the contacts in SIMD lanes (namespace
/// grip::detail): the bodies of ConicLanes' predictor and corrector passes (conic_lanes.hpp
/// declares them and includes this file; include that header instead).
///
/// Predictor: the constant system's u2_i = B_i^-1 (gq_i - A_i^T y2), the affine direction
/// du_i = B_i^-1 (gp_i - A_i^T y1) + dtau u2_i with its dual part and bound, the largest step that
/// keeps every cone, and Mehrotra's corrector right-hand side in three parts linear in sigma and
/// sigma mu (the driver picks sigma after the pass). Corrector: the same direction from the summed
/// right-hand side, and its step. The blocks B_i and their products: cone_blocks.hpp.

#include "grip/solve/detail/conic_lanes.hpp"

namespace grip {
namespace detail {

template <class S, int D, int Cap>
template <bool Bounded>
PredictSums<S> ConicLanes<S, D, Cap>::predict_impl(const Wrench<S>& y1, const Wrench<S>& y2, S dtau,
                                                   const Wrench<S>& dy, S tau, S root_gamma_mu) {
  const P zero = P::set1(S(0)), one = P::set1(S(1)), inf = P::set1(std::numeric_limits<S>::infinity());
  const P prgm = P::set1(root_gamma_mu);
  const P pdt = P::set1(dtau), itau2 = P::set1(S(2) / tau);
  P pdy[6], py1[6], py2[6];
  for (int r = 0; r < 6; ++r) {
    pdy[r] = P::set1(dy(r));
    py1[r] = P::set1(y1(r));
    py2[r] = P::set1(y2(r));
  }
  // Sums: a_bg[0..2] 0-17, k 18-20, gap1 21, gap2 22, den 23, c_bg[0..2] 24-26, a_bg[3] 27-32,
  // c_bg[3] 33.
  constexpr int nacc = 40;
  P acc[nacc];
  for (P& e : acc) e = zero;
  P step = inf;
  for_each_block<single, width>(this->blocks_, [&](int o, auto first) GRIP_BLOCK_BODY {
    constexpr bool First = decltype(first)::value;
    const Mask valid = P::first(this->n_ - o);
    const auto a = load_map(o);
    const Vec p = load(this->p_, o), q = load(this->q_, o), u = load(this->u_, o), z = load(this->z_, o),
              rx = load(this->rx_, o);
    Bound b0;
    if constexpr (Bounded) b0 = load_bound(o);
    const Sym bi = load_sym(o);
    const Vec u2 = sym_apply(bi, minus_transpose(Block::template constant_rhs<Bounded>(q, b0.hb, b0.c), a, py2));
    store(this->u2_, o, u2);
    const NtFrame<P, D> frame = this->load_frame(o);
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
      lane_add<First>(acc[23], select(valid, sq, zero));
    }
    Vec du = sym_apply(bi, minus_transpose(Block::template predictor_rhs<Bounded>(rx, z, b0.hb, b0.s, b0.rb), a, py1));
    for (int k = 0; k < D; ++k) du[k] = mul_add(pdt, u2[k], du[k]);
    // The bound's direction: dt = (t/s)(du_0 - c dtau + rb - s), ds = -s - (s/t) dt.
    P dt = zero, ds = zero;
    if constexpr (Bounded) {
      dt = select(b0.has, b0.hb * (du[0] - b0.c * pdt + b0.rb - b0.s), zero);
      ds = select(b0.has, zero - b0.s - b0.s * b0.it * dt, zero);
      ds.store(&this->ds_[idx(o)]);
      dt.store(&this->dt_[idx(o)]);
    }
    const Vec dz = Block::template dual_direction<Bounded>(a, p, q, du, pdy, pdt, rx, dt);
    store(this->du_, o, du);
    store(this->dz_, o, dz);
    step = min(step, Block::template step_length<Bounded>(u, frame.det_u, du, z, frame.det_z, dz, b0, ds, dt, valid));
    const auto add = [&](int j, P v) { lane_add<First>(acc[j], select(valid, v, zero)); };
    P g1 = cone_dot<P, D>(u, dz) + cone_dot<P, D>(du, z), g2 = cone_dot<P, D>(du, dz);
    if constexpr (Bounded) {
      g1 = g1 + mul_add(b0.s, dt, ds * b0.t);
      g2 = mul_add(ds, dt, g2);
    }
    add(21, g1);
    add(22, g2);
    // Mehrotra: W^-1 (lambda \ (lambda o lambda + (W^-1 du) o (W dz))) = z + W^-1 (lambda \ m),
    // m = (W^-1 du) o (W dz); and W^-1 (lambda \ e) = u^-1 = J u / det u (lambda = W^-1 u).
    const Vec l = load(this->lambda_, o);
    const Vec m = jordan_product<P, D>(nt_frame_apply<true, P, D>(frame, du), nt_frame_apply<false, P, D>(frame, dz));
    Vec cc = nt_frame_apply<true, P, D>(frame, jordan_divide<P, D>(l, frame.det_lambda, m));
    for (int j = 0; j < D; ++j) cc[j] = cc[j] + z[j];
    const P idu = one / frame.det_u;
    Vec ce;
    ce[0] = u[0] * idu;
    for (int j = 1; j < D; ++j) ce[j] = zero - u[j] * idu;
    store(this->cc_, o, cc);
    store(this->ce_, o, ce);
    P dsdt = zero;
    if constexpr (Bounded) {
      dsdt = ds * dt;
      dsdt.store(&this->bc_[idx(o)]);
    }
    Vec g[4];
    Block::template corrector_parts<Bounded>(rx, cc, ce, b0, dsdt, g);
    g[3] = Block::recentre_part(l, ce, prgm);
    const Vec cg = Block::template gradient_row<Bounded>(p, q, u, itau2, b0.c, b0.hb);
    for (int j = 0; j < 4; ++j) {
      const Vec f = sym_apply(bi, g[j]);
      const int at = j < 3 ? 6 * j : 27;
      for (int r = 0; r < 6; ++r) lane_add<First>(acc[at + r], cone_dot<P, D>(a[r], f));
      add(j < 3 ? 24 + j : 33, cone_dot<P, D>(cg, f));
    }
    if constexpr (Bounded) {
      // The tau row's bound terms: -c (t/s)((1 - sigma) rb - s - ds dt / t + sigma mu / t).
      add(18, zero - b0.c * b0.hb * (b0.rb - b0.s - dsdt * b0.it));
      add(19, b0.c * b0.hb * b0.rb);
      add(20, zero - b0.c * b0.is);
    }
  });
  const Totals<nacc> tot(acc);
  PredictSums<S> out;
  for (int j = 0; j < 3; ++j) {
    for (int r = 0; r < 6; ++r) out.a_bg[j](r) = tot(6 * j + r);
    out.k[j] = tot(18 + j);
    out.c_bg[j] = tot(24 + j);
  }
  for (int r = 0; r < 6; ++r) out.a_bg[3](r) = tot(27 + r);
  out.c_bg[3] = tot(33);
  out.gap1 = tot(21);
  out.gap2 = tot(22);
  out.den = tot(23);
  out.step = least(step);
  return out;
}

template <class S, int D, int Cap>
template <bool Bounded>
S ConicLanes<S, D, Cap>::correct_impl(const Wrench<S>& y1, S dtau, const Wrench<S>& dy, S sigma, S sigma_mu,
                                      S root_gamma_mu, S extra_mu) {
  const P zero = P::set1(S(0)), inf = P::set1(std::numeric_limits<S>::infinity());
  const P prgm = P::set1(root_gamma_mu), pem = P::set1(extra_mu);
  const P pdt = P::set1(dtau), psig = P::set1(sigma), psm = P::set1(sigma_mu), keep = P::set1(S(1) - sigma);
  P pdy[6], py1[6];
  for (int r = 0; r < 6; ++r) {
    pdy[r] = P::set1(dy(r));
    py1[r] = P::set1(y1(r));
  }
  P step = inf;
  for (int b = 0; b < this->blocks_; ++b) {
    const int o = b * width;
    const Mask valid = P::first(this->n_ - o);
    const auto a = load_map(o);
    const Vec p = load(this->p_, o), q = load(this->q_, o), u = load(this->u_, o), z = load(this->z_, o),
              rx = load(this->rx_, o);
    const Vec u2 = load(this->u2_, o), cc = load(this->cc_, o), ce = load(this->ce_, o);
    Bound b0;
    P dsdt = zero;
    if constexpr (Bounded) {
      b0 = load_bound(o);
      dsdt = P::load(&this->bc_[idx(o)]);
    }
    Vec g[3];
    Block::template corrector_parts<Bounded>(rx, cc, ce, b0, dsdt, g);
    const Vec g3 = Block::recentre_part(load(this->lambda_, o), ce, prgm);
    Vec gc;
    for (int k = 0; k < D; ++k) gc[k] = mul_add(pem, g3[k], mul_add(psm, g[2][k], mul_add(psig, g[1][k], g[0][k])));
    Vec du = sym_apply(load_sym(o), minus_transpose(gc, a, py1));
    for (int k = 0; k < D; ++k) du[k] = mul_add(pdt, u2[k], du[k]);
    P dt = zero, ds = zero;
    if constexpr (Bounded) {
      // d_b = (1 - sigma) rb, d_sb / t = s + (ds dt - sigma mu) / t.
      const P dsb = b0.s + (dsdt - psm) * b0.it;
      dt = select(b0.has, b0.hb * (du[0] - b0.c * pdt + keep * b0.rb - dsb), zero);
      ds = select(b0.has, zero - dsb - b0.s * b0.it * dt, zero);
      ds.store(&this->ds_[idx(o)]);
      dt.store(&this->dt_[idx(o)]);
    }
    Vec krx;
    for (int k = 0; k < D; ++k) krx[k] = keep * rx[k];
    const Vec dz = Block::template dual_direction<Bounded>(a, p, q, du, pdy, pdt, krx, dt);
    store(this->du_, o, du);
    store(this->dz_, o, dz);
    step = min(step, Block::template step_length<Bounded>(u, P::load(&this->detu_[idx(o)]), du, z,
                                                          P::load(&this->detz_[idx(o)]), dz, b0, ds, dt, valid));
  }
  return least(step);
}

}  // namespace detail
}  // namespace grip
