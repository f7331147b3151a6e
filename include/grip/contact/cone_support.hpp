#pragma once
/// \file
/// Shared pieces of the friction-cone value types: conventions for invalid input,
/// the deterministic tangent basis of a contact normal, and the Euclidean projection
/// onto a cone spanned by a cyclic list of edge rays (used by the pyramid and the
/// linear soft-finger cones).
///
/// Conventions shared by every cone type (CoulombCone, PyramidCone, SoftFingerCone,
/// CompressionCone):
/// - an input is *valid* when every coordinate is finite and |x_k| <= ScalarTraits::max_magnitude;
/// - for an invalid input: is_inside() is false, margin() and relative_margin() return
///   cone_margin_floor<S>() = -ScalarTraits<S>::max_magnitude (finite, below any margin
///   of valid input that matters), project() returns the zero vector (the apex);
/// - margins are positive strictly inside, zero on the boundary, negative outside, so
///   `is_inside(x) == (margin(x) >= 0) == (relative_margin(x) >= 0)` exactly.

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// The margin reported for invalid (NaN, Inf, out-of-range) input, and the lower clamp of
/// relative margins: -ScalarTraits<S>::max_magnitude.
template <class Scalar>
constexpr Scalar cone_margin_floor() {
  return -ScalarTraits<Scalar>::max_magnitude;
}

/// The friction coefficient that stands for "infinite" (a half-space): the dual of a cone
/// with mu = 0 (a ray) has this mu, and the dual of a cone with mu >= it has mu = 0.
template <class Scalar>
constexpr Scalar cone_half_space_mu() {
  return ScalarTraits<Scalar>::max_magnitude;
}

/// Everything a monitor reads from one contact force, computed by a cone's measure(x) in one
/// pass (one square root, few divisions): the same numbers as normal_part(),
/// tangential_part(), margin() and relative_margin() (same operations, so equal to round-off).
template <class Scalar>
struct ConeMeasure {
  Scalar normal_force{0};                                     ///< f_n = f.a (N)
  Vector3<Scalar> tangential_force{Vector3<Scalar>::Zero()};  ///< f_t (N)
  Scalar tangential_norm{0};                                  ///< |f_t| (N)
  Scalar moment{0};                                           ///< torsional moment (N m), soft finger only
  Scalar margin{cone_margin_floor<Scalar>()};                 ///< as margin(x)
  Scalar relative_margin{cone_margin_floor<Scalar>()};        ///< as relative_margin(x)
};

namespace detail {

/// True if every coordinate of v is finite and within max_magnitude.
template <class Derived>
bool cone_input_valid(const Eigen::MatrixBase<Derived>& v) {
  using S = typename Derived::Scalar;
  int bad = 0;  // a count, not an early exit: the loop vectorises
  for (Eigen::Index i = 0; i < v.size(); ++i)
    bad += static_cast<int>(!(std::abs(v(i)) <= ScalarTraits<S>::max_magnitude));
  return bad == 0;  // NaN fails the comparison, so it counts
}

/// 1/mu with the half-space convention: 0 <-> cone_half_space_mu().
template <class Scalar>
Scalar dual_coefficient(Scalar mu) {
  if (!(mu > Scalar(0))) return cone_half_space_mu<Scalar>();
  if (mu >= cone_half_space_mu<Scalar>()) return Scalar(0);
  const Scalar inv = Scalar(1) / mu;
  return inv < cone_half_space_mu<Scalar>() ? inv : cone_half_space_mu<Scalar>();
}

/// Turns a tangential "load" (>= 0) and a capacity (>= 0, in the same units) into the
/// relative margin 1 - load / capacity, clamped below at cone_margin_floor(); 0/0 is 0 load.
template <class Scalar>
Scalar relative_from(Scalar load, Scalar capacity) {
  if (load <= Scalar(0)) return Scalar(1);
  const Scalar floor = cone_margin_floor<Scalar>();
  // 1 - load/capacity < floor  <=>  load > (1 - floor) capacity.
  if (!(capacity > Scalar(0)) || load > (Scalar(1) - floor) * capacity) return floor;
  return Scalar(1) - load / capacity;
}

/// A negative-normal ("pulling") correction: for f_n < 0 the margin is min(m, f_n), so a
/// pull is outside even when the friction coefficient is 0 (where mu f_n - |f_t| can be 0).
template <class Scalar>
Scalar pull_corrected(Scalar margin, Scalar f_n) {
  return f_n < Scalar(0) && f_n < margin ? f_n : margin;
}

}  // namespace detail

/// An orthonormal right-handed frame (t1, t2, a) built deterministically from a unit normal a:
/// t1 = normalise(a x e_k) with e_k the world axis of smallest |a_k| (first such index on ties),
/// t2 = a x t1. The same a always gives the same t1, t2 (bitwise).
template <class Scalar>
struct TangentBasis {
  Vector3<Scalar> t1{Vector3<Scalar>::UnitX()};  ///< first tangent (unit)
  Vector3<Scalar> t2{Vector3<Scalar>::UnitY()};  ///< second tangent (unit), a x t1

  /// The frame of normal `a` (|a| = 1 assumed; a zero or NaN `a` gives the default frame).
  static TangentBasis from_normal(const Vector3<Scalar>& a) {
    TangentBasis b;
    if (!detail::cone_input_valid(a) || !(a.squaredNorm() > Scalar(0))) return b;
    int k = 0;
    if (std::abs(a(1)) < std::abs(a(k))) k = 1;
    if (std::abs(a(2)) < std::abs(a(k))) k = 2;
    const Vector3<Scalar> t = a.cross(Vector3<Scalar>::Unit(k));
    b.t1 = t / t.norm();
    b.t2 = a.cross(b.t1);
    return b;
  }
};

namespace detail {

/// Euclidean projection of the 3-vector x onto the convex cone spanned by the K edge
/// rays e_0..e_{K-1}, given in cyclic order around the axis (consecutive edges bound a
/// face). Precondition: x is valid and NOT inside the cone (the caller checks with its own
/// exact test, which also covers cones flattened to a plane or a ray). The answer is the
/// nearest among the finitely many candidates on the faces: the apex, the projection on
/// each edge ray, and the projection on each face plane when it falls inside that face's
/// wedge. Every candidate lies in the cone and the true projection is one of them, so the
/// nearest candidate is the projection. Cost O(K), no iteration.
template <class Scalar, std::size_t K>
Vector3<Scalar> project_onto_edge_cone(const Vector3<Scalar>& x, const std::array<Vector3<Scalar>, K>& e) {
  Vector3<Scalar> best = Vector3<Scalar>::Zero();
  Scalar best_d = x.squaredNorm();
  const auto consider = [&](const Vector3<Scalar>& p) {
    const Scalar d = (x - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = p;
    }
  };
  for (std::size_t j = 0; j < K; ++j) {
    const Scalar ee = e[j].squaredNorm();
    const Scalar xe = x.dot(e[j]);
    if (xe > Scalar(0) && ee > Scalar(0)) consider(Vector3<Scalar>((xe / ee) * e[j]));
    const Vector3<Scalar>& e0 = e[j];
    const Vector3<Scalar>& e1 = e[(j + 1) % K];
    const Vector3<Scalar> n = e0.cross(e1);
    const Scalar nn = n.squaredNorm();
    if (!(nn > Scalar(0))) continue;  // coincident or opposite edges: no 2-D face here
    const Vector3<Scalar> p = x - (x.dot(n) / nn) * n;
    // p = alpha e0 + beta e1 with alpha = (p x e1).n / |n|^2, beta = (e0 x p).n / |n|^2.
    const Scalar alpha = p.cross(e1).dot(n);
    const Scalar beta = e0.cross(p).dot(n);
    if (alpha >= Scalar(0) && beta >= Scalar(0)) consider(p);
  }
  return best;
}

/// Projection of (s, t) onto the 2-D cone {|t| <= mu s} with t >= 0 (closed form):
/// inside -> itself; s <= -mu t (polar cone) -> 0; otherwise onto the edge (1, mu):
/// s' = (s + mu t) / (1 + mu^2), t' = mu s'.
template <class Scalar>
void project_2d_cone(Scalar s, Scalar t, Scalar mu, Scalar& s_out, Scalar& t_out) {
  if (t <= mu * s) {
    s_out = s;
    t_out = t;
    return;
  }
  if (s <= -mu * t) {
    s_out = Scalar(0);
    t_out = Scalar(0);
    return;
  }
  s_out = (s + mu * t) / (Scalar(1) + mu * mu);
  t_out = mu * s_out;
}

}  // namespace detail

}  // namespace grip
