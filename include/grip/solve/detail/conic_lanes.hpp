#pragma once
/// \file
/// The per-contact passes of the interior-point method (interior_point.hpp), on the contacts in
/// SIMD lanes (namespace grip::detail), over the storage of conic_storage.hpp: the problem
///
///     minimise   sum_i 1/2 u_i^T P_i u_i + q_i^T u_i  (+ 1/2 |sum_i A_i u_i - b|^2: the soft form)
///     subject to sum_i A_i u_i = b  (six rows; none in the soft form),
///                u_i in Q,   u_i0 <= c_i  (an optional bound on the first component).
///
/// Eliminating each contact's dual and bound from the Newton system leaves its block B_i
/// (cone_blocks.hpp) and the driver's 6 x 6 Schur complement S = sum_i A_i B_i^-1 A_i^T.
///
/// Each iteration makes three passes: assemble (the step just taken, the residuals, the
/// scalings, B_i^-1 (cone_blocks.hpp), S and the right-hand sides' forward sums, with the tau
/// row's products in their linear form), predict (the constant system's and the affine
/// direction's solutions, the affine step, and Mehrotra's corrector in three parts linear in
/// sigma and sigma mu, so that sigma can be chosen after the pass) and correct (the direction and
/// its step). The driver solves its 6 x 6 systems between the passes. This file holds the class
/// and the assemble pass; the predictor's and corrector's bodies, the search direction, are in
/// conic_direction.hpp.

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include <Eigen/Core>

#include "grip/core/simd.hpp"
#include "grip/core/simd_blocks.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/cone_blocks.hpp"
#include "grip/solve/detail/cone_packs.hpp"
#include "grip/solve/detail/conic_storage.hpp"
#include "grip/solve/detail/conic_sums.hpp"

namespace grip {
namespace detail {

/// True where the build optimises for size (-Os, __OPTIMIZE_SIZE__: a microcontroller's flash):
/// there one variant of each pass, the one with bound rows, serves every grasp (a lane without a
/// bound adds nothing to them); elsewhere grasps without bounds take a variant without the rows.
#if defined(__OPTIMIZE_SIZE__)
constexpr bool conic_one_variant = true;
#else
constexpr bool conic_one_variant = false;
#endif

/// The interior-point method's passes over the contacts in SIMD lanes (see the file comment);
/// the data are set through ConicStorage's public part.
template <class S, int D, int Cap>
class ConicLanes : public ConicStorage<S, D, Cap> {
  using Base = ConicStorage<S, D, Cap>;
  using typename Base::Block;
  using typename Base::Bound;
  using typename Base::Sym;
  using Block::min;
  using Block::minus_transpose;
  using Block::sym_apply;
  using Base::load_bound;
  using Base::idx;
  using Base::load;
  using Base::store;
  using Base::load_map;
  using Base::load_sym;
  using Base::metric_norm;
  using Base::sum_all;
  using Base::least;

 public:
  using typename Base::P;
  using typename Base::Mask;
  using typename Base::Vec;
  using Base::width;
  using Base::stride;
  using Base::tri;
  /// True when the contacts always fit one block of lanes (for_each_block's Single).
  static constexpr bool single = stride == width;

  /// `contacts` cones (at most Cap), all inert (A = 0, P = 1, q = 0, no bound) until set().
  explicit ConicLanes(int contacts) : Base(contacts) {}

  /// Pass 1: takes the last step (u += alpha du, z += alpha dz, and the bounds' s, t; nothing for
  /// alpha = 0), then at the new point and multipliers y, tau: the residuals rx_i, rb_i, the
  /// scalings, B_i^-1 (all kept for the next passes) and the sums of AssembleSums.
  AssembleSums<S> assemble(S alpha, const Wrench<S>& y, S tau) {
    if constexpr (conic_one_variant) {
      return assemble_impl<true>(alpha, y, tau);
    } else {
      return this->bounded_ ? assemble_impl<true>(alpha, y, tau) : assemble_impl<false>(alpha, y, tau);
    }
  }

  /// Pass 2, the predictor (affine direction): with the constant system's y2, the predictor's y1,
  /// the direction's dtau and dy = y1 + dtau y2 (the driver's solves from assemble's sums):
  /// u2_i = B_i^-1 (gq_i - A_i^T y2) (kept), du_i = B_i^-1 (gp_i - A_i^T y1) + dtau u2_i and the
  /// rest of the direction (kept), its step length, and the corrector's parts (kept, and summed).
  /// `root_gamma_mu` = sqrt(gamma mu): the pairs outside the wide neighbourhood
  /// (ConeBlock::recentre_part; gamma = ScalarTraits::interior_neighbourhood) give the fourth
  /// part of the corrector.
  PredictSums<S> predict(const Wrench<S>& y1, const Wrench<S>& y2, S dtau, const Wrench<S>& dy, S tau,
                         S root_gamma_mu) {
    if constexpr (conic_one_variant) {
      return predict_impl<true>(y1, y2, dtau, dy, tau, root_gamma_mu);
    } else {
      return this->bounded_ ? predict_impl<true>(y1, y2, dtau, dy, tau, root_gamma_mu)
                            : predict_impl<false>(y1, y2, dtau, dy, tau, root_gamma_mu);
    }
  }

  /// Pass 3, the corrector: with its y1 (the driver's solve of the summed right-hand side), dtau
  /// and dy = y1 + dtau y2, the direction du_i = B_i^-1 (g_i - A_i^T y1) + dtau u2_i and the rest
  /// (kept for assemble's step); returns its step length. `sigma_mu` = sigma mu; `root_gamma_mu` as in
  /// predict; `extra_mu` = max(gamma - sigma, 0) mu, the fourth part's weight.
  S correct(const Wrench<S>& y1, S dtau, const Wrench<S>& dy, S sigma, S sigma_mu, S root_gamma_mu, S extra_mu) {
    if constexpr (conic_one_variant) {
      return correct_impl<true>(y1, dtau, dy, sigma, sigma_mu, root_gamma_mu, extra_mu);
    } else {
      return this->bounded_ ? correct_impl<true>(y1, dtau, dy, sigma, sigma_mu, root_gamma_mu, extra_mu)
                            : correct_impl<false>(y1, dtau, dy, sigma, sigma_mu, root_gamma_mu, extra_mu);
    }
  }

 private:
  /// The sums across the lanes of `count` accumulator packs: summed into an array, or read from
  /// the packs themselves when they have one lane (no second array on a microcontroller's stack).
  template <int count>
  struct Totals {
    explicit Totals(const P* packs) : acc(packs) {
      if constexpr (width > 1) sum_all(packs, sums, count);
    }
    S operator()(int e) const {
      if constexpr (width > 1) {
        return sums[e];
      } else {
        return acc[e].sum();
      }
    }
    const P* acc;
    S sums[width > 1 ? count : 1]{};
  };
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
    for_each_block<single, width>(this->blocks_, [&](int o, auto first) GRIP_BLOCK_BODY {
      constexpr bool First = decltype(first)::value;
      const Mask valid = P::first(this->n_ - o);
      Vec u = load(this->u_, o), z = load(this->z_, o);
      P s = P::load(&this->s_[idx(o)]), t = P::load(&this->t_[idx(o)]);
      if (alpha != S(0)) {
        const Vec du = load(this->du_, o), dz = load(this->dz_, o);
        for (int r = 0; r < D; ++r) {
          u[r] = mul_add(pa, du[r], u[r]);
          z[r] = mul_add(pa, dz[r], z[r]);
        }
        store(this->u_, o, u);
        store(this->z_, o, z);
        if constexpr (Bounded) {
          s = mul_add(pa, P::load(&this->ds_[idx(o)]), s);
          t = mul_add(pa, P::load(&this->dt_[idx(o)]), t);
          s.store(&this->s_[idx(o)]);
          t.store(&this->t_[idx(o)]);
        }
      }
      const auto a = load_map(o);
      const Vec p = load(this->p_, o), q = load(this->q_, o);
      // The bound row (lanes without one: t = 0, so it adds nothing).
      P bt = zero, bs = one, cb = zero, hb = zero, rb = zero;
      Mask has = P::first(0);
      if constexpr (Bounded) {
        const P c = P::load(&this->c_[idx(o)]);
        has = c < inf;
        bt = select(has, t, zero);
        bs = select(has, s, one);
        cb = select(has, c, zero);
        hb = bt / bs;  // t / s
        rb = select(has, u[0] + bs - cb * ptau, zero);
        rb.store(&this->rb_[idx(o)]);
        hb.store(&this->hb_[idx(o)]);
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
      store(this->rx_, o, rx);
      const P margin = cone_margin<P, D>(aty);
      cert = select(valid & (margin < cert), margin, cert);
      // The scaling (its frame kept) and B^-1.
      const NtFrame<P, D> k = nt_frame<P, D>(u, z);
      ok = ok && and_not(valid, k.ok & (bs > zero) & !(bt < zero)).bits() == 0u;
      this->store_frame(o, k);
      const Sym bi = Block::inverse_from_frame(k, p, hb);
      for (int e = 0; e < tri; ++e) bi[idx(e)].store(&this->binv_[Base::at(e, o)]);
      // B^-1 applied to the constant system's and the predictor's right-hand sides.
      const Vec fq = sym_apply(bi, Block::template constant_rhs<Bounded>(q, hb, cb)),
                fp = sym_apply(bi, Block::template predictor_rhs<Bounded>(rx, z, hb, bs, rb));
      const Vec cgt = Block::template gradient_row<Bounded>(p, q, u, itau2, cb, hb);
      const Vec fc = sym_apply(bi, cgt);
      for (int r = 0; r < 6; ++r) lane_add<First>(acc[48 + r], cone_dot<P, D>(a[r], fc));
      lane_add<First>(acc[54], select(valid, cone_dot<P, D>(cgt, fq), zero));
      lane_add<First>(acc[55], select(valid, cone_dot<P, D>(cgt, fp), zero));
      // A B^-1 (for S), A u and the forward sums.
      P ab[6][D];
      for (int r = 0; r < 6; ++r)
        for (int j = 0; j < D; ++j) {
          P v = zero;
          for (int l = 0; l < D; ++l) v = mul_add(a[r][l], bi[Block::sym(l, j)], v);
          ab[r][j] = v;
        }
      int e = 6;
      for (int r = 0; r < 6; ++r) {
        lane_add<First>(acc[r], cone_dot<P, D>(a[r], u));
        lane_add<First>(acc[27 + r], cone_dot<P, D>(a[r], fq));
        lane_add<First>(acc[33 + r], cone_dot<P, D>(a[r], fp));
        for (int l = r; l < 6; ++l, ++e) {
          lane_add_mul<First>(acc[e], ab[r][0], a[l][0]);
          for (int j = 1; j < D; ++j) acc[e] = mul_add(ab[r][j], a[l][j], acc[e]);
        }
      }
      // Scalars, masked to the contacts.
      const auto add = [&](int j, P v) { lane_add<First>(acc[j], select(valid, v, zero)); };
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
    });
    const Totals<nacc> tot(acc);
    AssembleSums<S> out;
    int e = 6;
    for (int r = 0; r < 6; ++r) {
      out.au(r) = tot(r);
      out.a_bq(r) = tot(27 + r);
      out.a_bp(r) = tot(33 + r);
      for (int l = r; l < 6; ++l, ++e) out.schur(r, l) = out.schur(l, r) = tot(e);
    }
    out.kp = tot(39);
    out.upu = tot(40);
    out.qu = tot(41);
    out.ct = tot(42);
    out.gap = tot(43);
    out.rx2 = tot(44);
    out.rb2 = tot(45);
    out.x2 = tot(46);
    out.z2 = tot(47);
    for (int r = 0; r < 6; ++r) out.h(r) = tot(48 + r);
    out.c_bq = tot(54);
    out.c_bp = tot(55);
    out.cc_hb = tot(56);
    out.certificate = least(cert);
    S schur_sum(0);
    for (int j = 6; j < 27; ++j) schur_sum += tot(j);
    out.ok = ok && std::isfinite(schur_sum);
    return out;
  }

  /// Pass 2's and pass 3's bodies (conic_direction.hpp), for grasps with and without bounds.
  template <bool Bounded>
  PredictSums<S> predict_impl(const Wrench<S>& y1, const Wrench<S>& y2, S dtau, const Wrench<S>& dy, S tau,
                              S root_gamma_mu);
  template <bool Bounded>
  S correct_impl(const Wrench<S>& y1, S dtau, const Wrench<S>& dy, S sigma, S sigma_mu, S root_gamma_mu, S extra_mu);
};

}  // namespace detail
}  // namespace grip

#include "grip/solve/detail/conic_direction.hpp"
