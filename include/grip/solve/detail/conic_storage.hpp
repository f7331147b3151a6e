#pragma once
/// \file
/// The storage of the interior-point method's lanes (namespace grip::detail): ConicStorage keeps
/// each contact's data and iterate, one contact per SIMD lane, as a structure of arrays (one row
/// of `stride` lanes per component, no heap), and the pack type they use. ConicLanes
/// (conic_lanes.hpp) runs the method's passes over it. Every contact i owns a second-order cone
/// Q of dimension D (cone_packs.hpp) and the data of
///
///     minimise   sum_i 1/2 u_i^T P_i u_i + q_i^T u_i
///     subject to sum_i A_i u_i = b,   u_i in Q,   u_i0 <= c_i (an optional bound),
///
/// with P_i diagonal (D entries >= 0, the last D - 1 equal when D = 3), q_i (D), A_i (6 x D) and
/// the metric diag(M_i^T M_i) in which |u_i| measures the contact's force. The homogeneous
/// embedding (interior_point.hpp) keeps here the cone variable u_i (its own slack), its dual z_i,
/// and for a bound the slack s_i = c_i tau - u_i0 >= 0 and its dual t_i >= 0; the multipliers y,
/// tau, kappa and, in the soft form, r = A u - b live in the driver. Lanes past the last
/// contact hold u = z = e, A = 0, P = 1, q = 0 and no bound, and are masked out of every sum and
/// step.

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "grip/core/simd.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/cone_blocks.hpp"
#include "grip/solve/detail/cone_packs.hpp"

namespace grip {
namespace detail {

/// The contacts' data and iterate in SIMD lanes (see the file comment): the public part sets
/// the data and reads the answer; the protected part is for the passes (ConicLanes).
template <class S, int D, int Cap>
class ConicStorage : protected ConeBlock<SimdPackFor<S, Cap>, D> {
 protected:
  using Block = ConeBlock<SimdPackFor<S, Cap>, D>;
  using typename Block::Bound;
  using typename Block::Sym;

 public:
  using P = SimdPackFor<S, Cap>;
  using Mask = typename P::Mask;
  using Vec = ConeVec<P, D>;
  static constexpr int width = P::width;
  static constexpr int stride = (Cap + width - 1) / width * width;  ///< lanes per component (whole packs)
  static constexpr int tri = Block::tri;                            ///< entries of a symmetric D x D matrix
  using Field = std::array<S, static_cast<std::size_t>(D* stride)>;
  using Column = std::array<S, static_cast<std::size_t>(stride)>;
  using Map = Eigen::Matrix<S, 6, D>;
  using ConeVector = Eigen::Matrix<S, D, 1>;

  /// `contacts` cones (at most Cap), all inert (A = 0, P = 1, q = 0, no bound) until set().
  explicit ConicStorage(int contacts) { clear(contacts); }

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
    start_bound(idx(i), S(1));  // where start() puts it: a fresh run at scale 1 starts here
  }

  /// Every variable at `scale` (> 0) times its cone's centre: u = z = scale e; a bound's slack
  /// at what its row leaves at tau = 1, s = c - scale (at least scale), and its dual t = scale^2 / s
  /// (each pair's product scale^2). A bound far above `scale` (a device's limit under a light load)
  /// would otherwise start its slack far below its value at the solution, and the method would
  /// spend its iterations growing it.
  void start(S scale = S(1)) {
    u_.fill(S(0));
    z_.fill(S(0));
    du_.fill(S(0));
    dz_.fill(S(0));
    for (int i = 0; i < stride; ++i) {
      u_[idx(i)] = z_[idx(i)] = scale;
      start_bound(idx(i), scale);
    }
  }

  /// Contact i's cone variable u_i and dual z_i, and its bound's slack and dual.
  ConeVector u(int i) const { return read(u_, i); }
  ConeVector z(int i) const { return read(z_, i); }
  S bound_slack(int i) const { return s_[idx(i)]; }
  S bound_dual(int i) const { return t_[idx(i)]; }

 protected:
  /// Lane j's bound slack and dual at start(scale)'s values (see there), their direction zero.
  void start_bound(std::size_t j, S scale) {
    const S c = c_[j];
    s_[j] = c < std::numeric_limits<S>::infinity() ? std::max(c - scale, scale) : scale;
    t_[j] = scale * (scale / s_[j]);
    ds_[j] = dt_[j] = S(0);
  }
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
  IntArray<Vec, 6> load_map(int o) const {
    IntArray<Vec, 6> m;
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
  /// |M u|^2 = sum_k metric_k u_k^2 for the lanes at o.
  P metric_norm(int o, const Vec& u) const {
    const Vec m = load(metric_, o);
    P v = m[0] * u[0] * u[0];
    for (int k = 1; k < D; ++k) v = mul_add(m[idx(k)] * u[idx(k)], u[idx(k)], v);
    return v;
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
  std::array<S, static_cast<std::size_t>(tri* stride)> binv_;
  Column s_, t_, ds_, dt_, rb_, hb_, bc_, beta_, inv_beta_, dp_, dm_, detu_, detz_, detl_;
};

}  // namespace detail
}  // namespace grip
