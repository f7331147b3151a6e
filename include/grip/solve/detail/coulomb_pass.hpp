#pragma once
/// \file
/// solve_constrained's pass for hard fingers over a structure of arrays, one contact per SIMD
/// lane (detail::SimdPackFor, core/simd.hpp: 8 doubles with AVX-512 (4 for at most 4 contacts), 4
/// with AVX2, else one scalar).
///
/// A pass at multipliers lambda takes every contact i through
///   v_i = s_i a_i + k_i G_i^T lambda          (k_i = 1/w_i; s_i a_i = t_i, eq. 7)
///   x_i = P_i(v_i)                             (projection onto the Coulomb cone of eq. 4-5)
/// and sums what the Newton iteration reads: G x + w_ext, F2(x), |x| and
/// sum_i k_i G_i J_i G_i^T with J_i = dP_i/dv (minus the dual's generalised Hessian). Same
/// regions and formulas as coulomb_project_accumulate in detail/constrained_passes.hpp (the
/// contact-by-contact form, kept as the reference the tests compare with):
/// - interior (|v_t| < mu v.a): x = v, J = I, added in GramAccumulator's closed form;
/// - polar cone, v_t = 0 outside the interior, and v with a component beyond max_magnitude or
///   not finite: x = 0, J = 0;
/// - boundary part: x = sn a + beta v_t, sn = (v.a + mu |v_t|)/(1 + mu^2), beta = mu sn/|v_t|,
///   and J = beta b b^T + ku d d^T with e = v_t/|v_t|, b = a x e, d = a + mu e, ku = 1/(1 + mu^2):
///   the projection onto the cone's generator through v plus beta times the direction around
///   the cone. (projection_jacobian writes it beta I + [a e] C [a e]^T; the two agree because
///   beta I_2 + C = ku (1, mu)(1, mu)^T.) So k G J G^T is two rank-one terms k beta g_b g_b^T +
///   k ku g_d g_d^T, g_u = (u, r x u): 42 multiply-adds into 21 sums per contact.
///
/// Branch-free: the region is a per-lane select, so that a mix of sticking and sliding contacts
/// costs no mispredicted branches. The sums are kept per lane and added across the lanes once
/// per pass.

#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "grip/contact/contact_model.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/simd.hpp"
#include "grip/core/simd_blocks.hpp"
#include "grip/core/types.hpp"

namespace grip {
namespace detail {

/// Sums of one pass of solve_constrained.
template <class Scalar>
struct ConstrainedPass {
  Wrench<Scalar> residual;  ///< G x + w_ext
  Scalar f2{0};             ///< F2(x)
  Scalar scale{0};          ///< |w_ext| + |x|: the scale of the equilibrium tolerance
  Scalar dual{0};           ///< q = F2 - lambda.residual
};

/// The hard-finger grasp of a solve, copied once into columns (one array per coordinate,
/// padded with inert contacts to whole SIMD blocks), with the pass over it.
///
/// Invariants: rows() is size() rounded up to a multiple of `block`; rows [size(), rows())
/// hold inert contacts (a = e_z, mu = 0, k = s = w = 0, r = 0), whose v is 0 for any finite
/// lambda, so that they project to x = 0 and add nothing to any sum.
/// Memory: 11 columns of max_rows scalars here, 3 in each Forces (no heap).
template <class GraspT>
class CoulombPassTable {
 public:
  using Scalar = typename GraspT::ScalarType;
  /// The SIMD register type of the pass (core/simd.hpp: SimdPackFor the grasp's capacity), and
  /// its lanes: rows are padded to whole registers.
  using Pack = SimdPackFor<Scalar, GraspT::capacity>;
  static constexpr int block = Pack::width;
  static constexpr int round_up(int n) { return (n + block - 1) / block * block; }
  static constexpr int rows_at_compile_time =
      GraspT::fixed_size == Eigen::Dynamic ? Eigen::Dynamic : round_up(GraspT::fixed_size);
  static constexpr int max_rows = round_up(GraspT::capacity);
  /// One coordinate of every contact (rows() entries).
  using Column = Eigen::Array<Scalar, rows_at_compile_time, 1, Eigen::ColMajor, max_rows, 1>;

  /// Contact forces in columns: x_i = (x(i), y(i), z(i)).
  struct Forces {
    Column x, y, z;
  };

  explicit CoulombPassTable(const GraspT& grasp) : n_(grasp.size()), rows_(round_up(grasp.size())) {
    for (Column* c : {&rx_, &ry_, &rz_, &ax_, &ay_, &az_, &mu_, &ku_, &k_, &s_, &w_}) c->resize(rows_);
    for (int i = 0; i < rows_; ++i) {
      if (i < n_) {
        const auto& c = grasp.contact(i);
        rx_(i) = c.position.x();
        ry_(i) = c.position.y();
        rz_(i) = c.position.z();
        ax_(i) = c.normal.x();
        ay_(i) = c.normal.y();
        az_(i) = c.normal.z();
        mu_(i) = c.friction;
        ku_(i) = Scalar(1) / (Scalar(1) + c.friction * c.friction);
        k_(i) = grasp.inverse_weight(i);
        s_(i) = c.squeeze;
        w_(i) = c.weight;
      } else {
        rx_(i) = ry_(i) = rz_(i) = ax_(i) = ay_(i) = Scalar(0);
        az_(i) = Scalar(1);
        mu_(i) = Scalar(0);
        ku_(i) = Scalar(1);
        k_(i) = s_(i) = w_(i) = Scalar(0);
      }
    }
  }

  /// Contacts n, and rows (n rounded up to whole blocks).
  int size() const { return n_; }
  int rows() const { return rows_; }

  /// Columns sized for this grasp (values unspecified).
  Forces make_forces() const {
    Forces f;
    f.x.resize(rows_);
    f.y.resize(rows_);
    f.z.resize(rows_);
    return f;
  }

  /// Writes the forces of x into the stacked vector `out` (3 size() entries, already sized).
  /// The least alpha in (0, 1) at which the projection of some contact changes region along
  /// lambda + alpha d: its input v_i(alpha) = s_i a_i + k_i G_i^T (lambda + alpha d) crosses
  /// the surface of the cone |v_t| = mu v_n (v_n >= 0) or of its polar cone mu |v_t| = -v_n
  /// (v_n <= 0); 1 if none does before 1. Up to there the dual is smooth along the segment;
  /// the line searches try it when the full step fails (a kink in the dual usually stops a
  /// Newton step there, and halving would find it only after many passes). Each surface is
  /// a quadratic in alpha per contact; roots within 64 eps of 0 (the current point on a
  /// surface) are skipped. One scalar pass over the contacts, no projection.
  Scalar first_break(const Wrench<Scalar>& lambda, const Wrench<Scalar>& d) const {
    using S = Scalar;
    const S tiny = S(64) * std::numeric_limits<S>::epsilon();
    S first = S(1);
    for (int i = 0; i < n_; ++i) {
      if (!(mu_(i) > S(0))) continue;  // the ray: its region changes at v_n = 0 only
      const Vector3<S> r(rx_(i), ry_(i), rz_(i)), a(ax_(i), ay_(i), az_(i));
      const Vector3<S> v0 = s_(i) * a + k_(i) * (lambda.template head<3>() - r.cross(lambda.template tail<3>()));
      const Vector3<S> u = k_(i) * (d.template head<3>() - r.cross(d.template tail<3>()));
      const S n0 = v0.dot(a), nu = u.dot(a);
      const Vector3<S> t0 = v0 - n0 * a, tu = u - nu * a;
      for (int side = 0; side < 2; ++side) {  // |t|^2 = c n^2: c = mu^2 (cone), 1 / mu^2 (polar)
        const S c = side == 0 ? mu_(i) * mu_(i) : S(1) / (mu_(i) * mu_(i));
        const S qa = tu.squaredNorm() - c * nu * nu, qb = S(2) * (t0.dot(tu) - c * n0 * nu);
        const S qc = t0.squaredNorm() - c * n0 * n0;
        S roots[2];
        int count = 0;
        if (std::abs(qa) <= tiny * (tu.squaredNorm() + c * nu * nu)) {
          if (qb != S(0)) roots[count++] = -qc / qb;
        } else if (const S disc = qb * qb - S(4) * qa * qc; disc >= S(0)) {
          const S q = qb >= S(0) ? -S(0.5) * (qb + std::sqrt(disc)) : -S(0.5) * (qb - std::sqrt(disc));
          if (q != S(0)) {
            roots[count++] = q / qa;
            roots[count++] = qc / q;
          }
        }
        for (int k = 0; k < count; ++k) {
          const S alpha = roots[k], n = n0 + alpha * nu;
          if (alpha > tiny && alpha < first && (side == 0 ? n >= S(0) : n <= S(0))) first = alpha;
        }
      }
    }
    return first;
  }

  /// The forces in columns `x` stacked into `out` (3 size() entries), and back (load; the padding
  /// rows set to 0).
  template <class Vec>
  void store(const Forces& x, Vec& out) const {
    for (int i = 0; i < n_; ++i) {
      out(3 * i) = x.x(i);
      out(3 * i + 1) = x.y(i);
      out(3 * i + 2) = x.z(i);
    }
  }
  template <class Vec>
  void load(const Vec& in, Forces& x) const {
    for (int i = 0; i < rows_; ++i) {
      const bool real = i < n_;
      x.x(i) = real ? in(3 * i) : Scalar(0);
      x.y(i) = real ? in(3 * i + 1) : Scalar(0);
      x.z(i) = real ? in(3 * i + 2) : Scalar(0);
    }
  }

  /// One pass at multipliers `lambda` (see the file comment): x_i = P_i(v_i) into `x`, the
  /// sums returned, and sum_i k_i G_i J_i G_i^T written into `hessian`, assembled and
  /// symmetric (every pass of the solver reads it: an accepted line-search point for the next
  /// Newton step).
  ConstrainedPass<Scalar> pass(const Wrench<Scalar>& w_ext, const Wrench<Scalar>& l, Forces& x,
                               Matrix6<Scalar>& hessian) const {
    using S = Scalar;
    using P = Pack;
    // Per-lane sums, in this order: G x (6), w |x - t|^2, |x|^2; the interior point-force sums
    // k, k r (3), k (|r|^2 I - r r^T) upper triangle (6); the 21 upper-triangle entries of the
    // rank-one terms. In whole groups of 8.
    constexpr int sums = (8 + 10 + 21 + 7) / 8 * 8;
    const P zero = P::set1(S(0)), one = P::set1(S(1)), big = P::set1(ScalarTraits<S>::max_magnitude);
    const P l0 = P::set1(l(0)), l1 = P::set1(l(1)), l2 = P::set1(l(2)), l3 = P::set1(l(3)), l4 = P::set1(l(4)),
            l5 = P::set1(l(5));
    P acc[sums];
    for (P& a : acc) a = zero;
    // The first block writes the sums (core/simd_blocks.hpp: Peel) where a pack has several
    // lanes; a one-lane pack's sums are single scalars, with nothing to save.
    for_each_block<max_rows == block, block, (block > 1)>(rows_ / block, [&](int i, auto first) GRIP_BLOCK_BODY {
      constexpr bool First = decltype(first)::value;
      const P rx = P::load(rx_.data() + i), ry = P::load(ry_.data() + i), rz = P::load(rz_.data() + i);
      const P ax = P::load(ax_.data() + i), ay = P::load(ay_.data() + i), az = P::load(az_.data() + i);
      const P m = P::load(mu_.data() + i), ku = P::load(ku_.data() + i), k = P::load(k_.data() + i),
              s = P::load(s_.data() + i);
      // v = s a + k G^T l, G^T l = l_f - r x l_m (HardFinger::wrench_transpose)
      const P vx = s * ax + k * (l0 - (ry * l5 - rz * l4));
      const P vy = s * ay + k * (l1 - (rz * l3 - rx * l5));
      const P vz = s * az + k * (l2 - (rx * l4 - ry * l3));
      const P n = vx * ax + vy * ay + vz * az;
      const P tx = vx - n * ax, ty = vy - n * ay, tz = vz - n * az;
      const P f = sqrt(tx * tx + ty * ty + tz * tz);
      // Regions (coulomb_project_accumulate's, lane by lane).
      const auto valid = (abs(vx) <= big) & (abs(vy) <= big) & (abs(vz) <= big);
      const auto pos = f > zero;
      const auto interior = f < m * n;
      const auto mpos = m > zero;
      const auto polar = (mpos & ((n <= zero - m * f) | (!pos))) | ((!mpos) & (!(n > zero)));
      const auto inside = interior & valid;
      const auto boundary = (!interior) & (!polar) & valid;
      const P sn = (n + m * f) * ku;
      const P inv = one / select(pos, f, one);
      const P beta = sn * m * inv;
      const P px = select(inside, vx, select(boundary, sn * ax + beta * tx, zero));
      const P py = select(inside, vy, select(boundary, sn * ay + beta * ty, zero));
      const P pz = select(inside, vz, select(boundary, sn * az + beta * tz, zero));
      px.store(x.x.data() + i);
      py.store(x.y.data() + i);
      pz.store(x.z.data() + i);
      lane_add<First>(acc[0], px);
      lane_add<First>(acc[1], py);
      lane_add<First>(acc[2], pz);
      lane_add<First>(acc[3], ry * pz - rz * py);
      lane_add<First>(acc[4], rz * px - rx * pz);
      lane_add<First>(acc[5], rx * py - ry * px);
      const P dx = px - s * ax, dy = py - s * ay, dz = pz - s * az;
      lane_add<First>(acc[6], P::load(w_.data() + i) * (dx * dx + dy * dy + dz * dz));
      lane_add<First>(acc[7], px * px + py * py + pz * pz);
      // Interior: k G G^T in GramAccumulator's closed form.
      const P ki = select(inside, k, zero);
      const P kx = ki * rx, ky = ki * ry, kz = ki * rz;
      lane_add<First>(acc[8], ki);
      lane_add<First>(acc[9], kx);
      lane_add<First>(acc[10], ky);
      lane_add<First>(acc[11], kz);
      lane_add<First>(acc[12], ky * ry + kz * rz);
      lane_add<First>(acc[13], kx * rx + kz * rz);
      lane_add<First>(acc[14], kx * rx + ky * ry);
      lane_sub_mul<First>(acc[15], kx, ry);
      lane_sub_mul<First>(acc[16], kx, rz);
      lane_sub_mul<First>(acc[17], ky, rz);
      // Boundary part: k beta g_b g_b^T + k ku g_d g_d^T; e = v_t/|v_t| (0 elsewhere, so that
      // every term stays finite).
      const auto dir = boundary & pos;
      const P ex = select(dir, tx * inv, zero), ey = select(dir, ty * inv, zero), ez = select(dir, tz * inv, zero);
      const P cb = select(boundary, k * beta, zero), cd = select(boundary, k * ku, zero);
      const P bx = ay * ez - az * ey, by = az * ex - ax * ez, bz = ax * ey - ay * ex;  // b = a x e
      const P dx2 = ax + m * ex, dy2 = ay + m * ey, dz2 = az + m * ez;                 // d = a + mu e
      const P gb[6] = {bx, by, bz, ry * bz - rz * by, rz * bx - rx * bz, rx * by - ry * bx};
      const P gd[6] = {dx2, dy2, dz2, ry * dz2 - rz * dy2, rz * dx2 - rx * dz2, rx * dy2 - ry * dx2};
      // The 21 upper-triangle entries, row by row. Unrolled where the build optimises for
      // speed (GRIP_UNROLL): constant indices keep every term in registers; a loop under -Os.
      int e = 18;
      GRIP_UNROLL(6)
      for (int r = 0; r < 6; ++r) {
        GRIP_UNROLL(6)
        for (int c = r; c < 6; ++c, ++e) {
          lane_add_mul<First>(acc[e], cd * gd[r], gd[c]);
          acc[e] = mul_add(cb * gb[r], gb[c], acc[e]);
        }
      }
    });
    // The sums across the lanes (a one-lane pack is its own sum: no copy on the stack).
    S lanes[P::width > 1 ? sums : 1];
    if constexpr (P::width > 1) P::sum_each(acc, sums, lanes);
    const auto total = [&](int e) -> S {
      if constexpr (P::width > 1)
        return lanes[e];
      else
        return acc[e].v;
    };
    ConstrainedPass<S> p;
    for (int r = 0; r < 6; ++r) p.residual(r) = w_ext(r) + total(r);
    p.f2 = S(0.5) * total(6);
    p.scale = w_ext.norm() + std::sqrt(total(7));
    p.dual = p.f2 - l.dot(p.residual);
    // The Hessian: the rank-one terms, then the interior point forces' closed form added.
    Matrix6<S>& h = hessian;
    int e = 18;
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c, ++e) {
        h(r, c) = total(e);
        h(c, r) = total(e);
      }
    Matrix3<S> s2;  // upper triangle
    s2(0, 0) = total(12);
    s2(1, 1) = total(13);
    s2(2, 2) = total(14);
    s2(0, 1) = total(15);
    s2(0, 2) = total(16);
    s2(1, 2) = total(17);
    GramAccumulator<S>::add_closed_form(h, total(8), Vector3<S>(total(9), total(10), total(11)), s2);
    return p;
  }

 private:
  int n_;
  int rows_;
  Column rx_, ry_, rz_, ax_, ay_, az_, mu_, ku_, k_, s_, w_;
};

}  // namespace detail
}  // namespace grip
