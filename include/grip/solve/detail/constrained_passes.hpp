#pragma once
/// \file
/// The passes of solve_constrained over the contacts (namespace grip::detail): at multipliers
/// lambda, x_i = P_i(t_i + w_i^-1 G_i^T lambda) for every contact (P_i: the Euclidean
/// projection onto the contact's exact cone K_i), the sums the iteration reads (G x + w_ext,
/// F2(x), |x|, the dual q) and sum_i w_i^-1 G_i J_i G_i^T, J_i a generalised
/// Jacobian of P_i (projection_jacobian.hpp): minus the dual's generalised Hessian.
///
/// Hard fingers copy the grasp once per solve (after the fast path) into columns and run every
/// pass over them in SIMD packs (CoulombPassTable, coulomb_pass.hpp: 8 contacts per step with
/// AVX-512, 4 with AVX2, one otherwise); soft fingers and frictionless points go contact by
/// contact through the cone's projection (ContactPasses). ConstrainedPasses picks the engine;
/// coulomb_project_accumulate, the contact-by-contact hard-finger kernel, is the reference the
/// tests compare CoulombPassTable with.

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Geometry>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/types.hpp"
#include "grip/solve/detail/coulomb_pass.hpp"
#include "grip/solve/projection_jacobian.hpp"

namespace grip {
namespace detail {

/// The cone's own projection, except a Coulomb cone with mu = 0 (the ray {f_n a, f_n >= 0}):
/// there CoulombCone::project keeps f = f_n a with f_n < 0 (reported to the cone's owner), so
/// the ray's projection max(f.a, 0) a is used.
template <class Cone, class V>
V project_onto(const Cone& k, const V& v) {
  return k.project(v);
}
template <class Scalar>
Vector3<Scalar> project_onto(const CoulombCone<Scalar>& k, const Vector3<Scalar>& v) {
  if (k.mu > Scalar(0)) return k.project(v);
  const Scalar n = v.dot(k.normal);
  return n > Scalar(0) && detail::cone_input_valid(v) ? Vector3<Scalar>(n * k.normal) : Vector3<Scalar>::Zero();
}

/// Hard finger, fused: x = P(v) onto the Coulomb cone of c (exactly project_onto's value) and,
/// when `acc` is given, k G_i J G_i^T added to it with J = dP/dv (projection_jacobian's
/// formulas and regions), from one evaluation of v.a, v_t and |v_t|. On the boundary part
/// J = beta I + [a e] C [a e]^T with C = [[k_u - beta, k_u mu], [k_u mu, k_u mu^2 - beta]],
/// k_u = 1/(1 + mu^2), beta = |x_t|/|v_t|, so G_i J G_i^T = beta G_i G_i^T (closed form) plus
/// W C W^T, W = [G_i a, G_i e] (6x2): two cross products and a rank-2 update instead of the
/// 6x3 by 3x3 by 3x6 product of the generic path.
template <class S>
EIGEN_ALWAYS_INLINE Vector3<S> coulomb_project_accumulate(const Contact<S>& c, S k, const Vector3<S>& v,
                                                          GramAccumulator<S>* acc) {
  const Vector3<S>& a = c.normal;
  const Vector3<S>& r = c.position;
  const S mu = c.friction;
  if (!cone_input_valid(v)) return Vector3<S>::Zero();  // Polar for the Jacobian: no term
  // Branch-free in the region (which depends on the square root, so a branch would stall every
  // contact on a misprediction): one formula covers the boundary part and, with |v_t| = mu n,
  // the boundary itself (sn = n, beta = 1: x = v), and mu = 0 (the ray: beta = 0, x = n a);
  // selects pick v (interior) and 0 (polar cone).
  const S n = v.dot(a);
  const Vector3<S> ftv = v - n * a;
  const S ft = ftv.norm();
  const bool inside = ft < mu * n;  // J = I
  // J = 0 (projection_jacobian's regions): for mu > 0 the polar cone, and v_t = 0 outside the
  // interior (v = 0, or mu n underflowing); for mu = 0 (the ray) n <= 0.
  const bool polar = mu > S(0) ? (n <= -mu * ft || !(ft > S(0))) : !(n > S(0));
  const S ku = S(1) / (S(1) + mu * mu);
  const S sn = (n + mu * ft) * ku;  // alpha of projection_jacobian
  // beta = mu sn / |v_t| lies in [0, 1] on the boundary part.
  const S beta = ft > S(0) ? (sn * mu) / ft : S(0);
  const bool boundary = !inside & !polar;
  if (acc != nullptr) {
    if (inside) {
      acc->add_point_force(k, r);
    } else if (boundary) {
      // v_t = 0 on the boundary part only for mu = 0 (the ray), where e has no weight.
      const Vector3<S> e = ft > S(0) ? Vector3<S>(ftv / ft) : Vector3<S>::Zero();
      Wrench<S> wa, we;
      wa.template head<3>() = a;
      wa.template tail<3>() = r.cross(a);
      we.template head<3>() = e;
      we.template tail<3>() = r.cross(e);
      const S caa = k * (ku - beta), cae = k * ku * mu, cee = k * (ku * mu * mu - beta);
      const Wrench<S> za = caa * wa + cae * we, ze = cae * wa + cee * we;
      if (beta > S(0)) acc->add_point_force(k * beta, r);
      for (int j = 0; j < 6; ++j)  // extra += za wa^T + ze we^T (symmetric: C is)
        for (int i = 0; i < 6; ++i) acc->extra(i, j) += za(i) * wa(j) + ze(i) * we(j);
    }
  }
  const S keep = inside ? S(1) : S(0);
  const S sb = boundary ? sn : S(0);
  const S bb = boundary ? beta : S(0);
  return keep * v + sb * a + bb * ftv;
}

/// x_i = P_i(v) and, when `acc` is given, k G_i J_i G_i^T added to it, J_i the generalised
/// Jacobian of the projection at v: the contact's block of minus the dual's generalised Hessian.
/// Hard fingers take the fused kernel above; the other models the cone's projection and
/// projection_jacobian.
template <class GraspT>
typename GraspT::ContactVector project_accumulate(const typename GraspT::ContactType& c, typename GraspT::ScalarType k,
                                                  const typename GraspT::ContactVector& v,
                                                  GramAccumulator<typename GraspT::ScalarType>* acc) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  if constexpr (std::is_same<M, HardFinger>::value) {
    return coulomb_project_accumulate(c, k, v, acc);
  } else {
    const auto cone = ExactConeT<M, S>::from_contact(c);
    const typename GraspT::ContactVector xi = project_onto(cone, v);
    if (acc != nullptr) {
      const auto j = projection_jacobian(cone, v, xi);
      if (j.region == ProjectionRegion::Interior) {
        M::accumulate(*acc, c, k);
      } else if (j.region == ProjectionRegion::Boundary) {
        const Eigen::Matrix<S, 6, d> g = M::basis(c);
        const Eigen::Matrix<S, 6, d> gj = k * (g * j.matrix);
        acc->extra.noalias() += gj * g.transpose();
      }
    }
    return xi;
  }
}

/// x_i = the projection of v onto the contact's cone truncated at its bound c = max_normal_force
/// (K_i with f_n <= c), and, when `acc` is given, k G_i J G_i^T added to it, J the projection's
/// generalised Jacobian; hard fingers and frictionless points (Newton is not run on a soft finger
/// with a bound). When the cone's projection keeps f_n <= c it is the answer (it lies in the
/// truncated cone and is the nearest point of a larger set); otherwise the answer lies on the
/// cap f_n = c (a point of the cap's interior side would be a local, hence the global, nearest
/// point of K): x = c a + v_t clipped to the disc |x_t| <= mu c, with J = I - a a^T inside the
/// disc and (mu c / |v_t|)(I - a a^T - e e^T), e = v_t / |v_t|, on its rim. A frictionless
/// point: x = min(max(v, 0), c), J = 1 strictly between. Unbounded contacts: project_accumulate.
template <class GraspT>
typename GraspT::ContactVector project_accumulate_bounded(const typename GraspT::ContactType& c,
                                                          typename GraspT::ScalarType k,
                                                          const typename GraspT::ContactVector& v,
                                                          GramAccumulator<typename GraspT::ScalarType>* acc) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using CV = typename GraspT::ContactVector;
  constexpr int d = GraspT::dim;
  static_assert(d != 4, "no bounded projection for soft fingers");
  const S cap = c.max_normal_force;
  if (!(cap < std::numeric_limits<S>::infinity())) return project_accumulate<GraspT>(c, k, v, acc);
  if constexpr (d == 1) {
    const S x = v(0) > S(0) ? (v(0) < cap ? S(v(0)) : cap) : S(0);
    if (acc != nullptr && v(0) > S(0) && v(0) < cap) M::accumulate(*acc, c, k);
    return CV::Constant(cone_input_valid(v) ? x : S(0));
  } else {
    const CV free = project_accumulate<GraspT>(c, k, v, nullptr);
    if (!(free.dot(c.normal) > cap)) return project_accumulate<GraspT>(c, k, v, acc);
    const Vector3<S>& a = c.normal;
    const Vector3<S> vt = v - v.dot(a) * a;
    const S ft = vt.norm(), rim = c.friction * cap;
    const bool inside = ft <= rim;
    const S keep = inside ? S(1) : rim / ft;
    if (acc != nullptr && keep > S(0)) {
      // J = keep (I - a a^T) (- keep e e^T on the rim).
      Matrix3<S> j = keep * (Matrix3<S>::Identity() - a * a.transpose());
      if (!inside) {
        const Vector3<S> e = vt / ft;
        j -= keep * e * e.transpose();
      }
      const Eigen::Matrix<S, 6, d> g = M::basis(c);
      acc->extra.noalias() += (k * (g * j)) * g.transpose();
    }
    return CV(cap * a + keep * vt);
  }
}

/// x_i = P_i(t_i + w_i^-1 G_i^T lambda) for every contact, with the sums of ConstrainedPass;
/// with `hessian` given, also sum_i w_i^-1 G_i J_i G_i^T at lambda in the same pass (so that an
/// accepted line-search point needs no second pass for the next Newton step). `bounded`: P_i
/// projects onto the cone truncated at the contact's max_normal_force (project_accumulate_bounded).
template <class GraspT, class Vec>
ConstrainedPass<typename GraspT::ScalarType> constrained_pass(
    const GraspT& grasp, const Wrench<typename GraspT::ScalarType>& w_ext,
    const Wrench<typename GraspT::ScalarType>& lambda, Vec& x,
    GramAccumulator<typename GraspT::ScalarType>* hessian = nullptr, bool bounded = false) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  using CV = typename GraspT::ContactVector;
  constexpr int d = GraspT::dim;
  ConstrainedPass<S> p;
  p.residual = w_ext;
  if (hessian != nullptr) *hessian = GramAccumulator<S>{};
  S xx = S(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const CV t = M::target(c);
    const CV v = t + grasp.inverse_weight(i) * M::wrench_transpose(c, lambda);
    CV xi;
    if constexpr (d != 4) {
      xi = bounded ? project_accumulate_bounded<GraspT>(c, grasp.inverse_weight(i), v, hessian)
                   : project_accumulate<GraspT>(c, grasp.inverse_weight(i), v, hessian);
    } else {
      xi = project_accumulate<GraspT>(c, grasp.inverse_weight(i), v, hessian);
    }
    x.template segment<d>(i * d) = xi;
    p.residual += M::wrench(c, xi);
    p.f2 += S(0.5) * c.weight * (xi - t).squaredNorm();
    xx += xi.squaredNorm();
  }
  p.scale = w_ext.norm() + std::sqrt(xx);
  p.dual = p.f2 - lambda.dot(p.residual);
  return p;
}

/// The passes of solve_constrained contact by contact, through the model's functions (soft
/// fingers, frictionless points); hard fingers take CoulombPassTable, the same pass over a
/// structure of arrays. Both offer Forces, make_forces, pass and store.
template <class GraspT>
class ContactPasses {
 public:
  using Scalar = typename GraspT::ScalarType;
  using Forces = typename GraspT::ForceVector;
  explicit ContactPasses(const GraspT& grasp) : grasp_(grasp) {}
  Forces make_forces() const { return Forces(grasp_.unknowns()); }
  ConstrainedPass<Scalar> pass(const Wrench<Scalar>& w_ext, const Wrench<Scalar>& lambda, Forces& x,
                               Matrix6<Scalar>& hessian, bool bounded = false) const {
    GramAccumulator<Scalar> acc;
    const ConstrainedPass<Scalar> p = constrained_pass(grasp_, w_ext, lambda, x, &acc, bounded);
    hessian = acc.matrix();
    return p;
  }
  /// Where the projections change region along lambda + alpha d (CoulombPassTable::first_break):
  /// not computed for these cones, so 1 (the line searches then only halve).
  Scalar first_break(const Wrench<Scalar>&, const Wrench<Scalar>&) const { return Scalar(1); }
  template <class Vec>
  void store(const Forces& x, Vec& out) const {
    out = x;
  }
  template <class Vec>
  void load(const Vec& in, Forces& x) const {
    x = in;
  }

 private:
  const GraspT& grasp_;
};

/// The second trial of Newton's line search (after the full step failed) from multipliers `l`
/// along `dir`: just past the first kink of the dual, kink (1 + sqrt(eps)) (`passes.first_break`
/// at l, dir), if it comes before `alpha` and lies beyond l's rounding (a step of more than
/// 16 eps |l|); else `alpha`. A step accepted at a kink would leave l on that surface, to its
/// rounding; past it, the next pass takes its Hessian from the region the step entered (on the
/// surface rounding picks either side, and the side left behind gives the next step the same
/// overshoot: Newton would zig-zag across the kink). The dual is C^1, so the margin changes
/// nothing else.
template <class Passes, class S>
S second_trial(const Passes& passes, const Wrench<S>& l, const Wrench<S>& dir, S alpha) {
  const S eps = std::numeric_limits<S>::epsilon();
  const S kink = passes.first_break(l, dir);
  const bool ahead = kink * dir.norm() > S(16) * eps * l.norm();
  return kink < alpha && ahead ? kink * (S(1) + std::sqrt(eps)) : alpha;
}

/// The pass engine of solve_constrained for a grasp type: CoulombPassTable for hard fingers,
/// except where the build optimises for size (-Os, __OPTIMIZE_SIZE__: a microcontroller's flash),
/// which takes the contact-by-contact ContactPasses for every model (one pass's code instead of
/// two: the bounded projections need it anyway).
#if defined(__OPTIMIZE_SIZE__)
constexpr bool vectorised_passes = false;
#else
constexpr bool vectorised_passes = true;
#endif
template <class GraspT>
using ConstrainedPasses =
    typename std::conditional<vectorised_passes && std::is_same<typename GraspT::ModelType, HardFinger>::value,
                              CoulombPassTable<GraspT>, ContactPasses<GraspT>>::type;

}  // namespace detail
}  // namespace grip
