#pragma once
/// \file
/// The exact Coulomb friction cone of a hard finger: the paper's eq. 4 with eq. 5.

#include <cmath>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// The Coulomb cone {f : |f_t| <= mu f_n} of a contact with unit inward normal a and
/// friction coefficient mu >= 0, where f_n = f.a (N) and f_t = f - f_n a (N).
///
/// For mu > 0 this is exactly the set allowed by the paper's eq. 4 and 5,
/// f.a / |f| >= 1/sqrt(1 + mu^2) and f.a > 0, plus its apex f = 0 (which eq. 5 excludes;
/// the monitor reports a zero force as separating). mu = 0 gives the ray {f_n a, f_n >= 0};
/// mu >= cone_half_space_mu() stands for the half-space f_n >= 0 (see dual()).
///
/// Invalid input (NaN, Inf, beyond max_magnitude) follows cone_support.hpp: outside,
/// margins cone_margin_floor(), projection 0. Precondition for the cone itself: |a| = 1 and
/// mu >= 0 finite (from_contact() of a validated Contact guarantees it).
template <class Scalar>
struct CoulombCone {
  using ScalarType = Scalar;                   ///< the scalar type (float or double)
  static constexpr int dim = 3;                ///< size of the contact unknown
  using Vector = Eigen::Matrix<Scalar, 3, 1>;  ///< a contact force f (N)

  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};  ///< a, unit, into the object
  Scalar mu{0};                                      ///< friction coefficient, >= 0

  /// The cone of contact c: a = c.normal, mu = c.friction.
  static CoulombCone from_contact(const Contact<Scalar>& c) { return CoulombCone{c.normal, c.friction}; }

  /// Normal part f_n = f.a (N); positive pushes into the object.
  Scalar normal_part(const Vector& f) const { return f.dot(normal); }
  /// Tangential part f_t = f - (f.a) a (N), a 3-vector orthogonal to a.
  Vector3<Scalar> tangential_part(const Vector& f) const { return f - normal_part(f) * normal; }
  /// |f_t| (N).
  Scalar tangential_norm(const Vector& f) const { return tangential_part(f).norm(); }

  /// True iff |f_t| <= mu f_n (and f_n >= 0). False for invalid f.
  bool is_inside(const Vector& f) const { return margin(f) >= Scalar(0); }

  /// Signed margin (N): mu f_n - |f_t| for f_n >= 0, i.e. how much more tangential load the
  /// contact takes before slipping; for f_n < 0 (pulling) min(mu f_n - |f_t|, f_n), which is
  /// < 0 even for mu = 0. Positive inside, 0 on the boundary, negative outside.
  Scalar margin(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return cone_margin_floor<Scalar>();
    const Scalar fn = normal_part(f);
    return margin_of(fn, (f - fn * normal).norm());
  }

  /// Relative margin 1 - |f_t| / (mu f_n) in [cone_margin_floor(), 1] (1: no friction used,
  /// 0: on the verge of slipping). Conventions: f_t = 0 with f_n > 0 gives 1 (also for
  /// mu = 0); f = 0 gives 0 (the apex: on the boundary); f_n <= 0 otherwise, or f_t != 0 with
  /// mu = 0, gives cone_margin_floor(). Same sign as margin().
  Scalar relative_margin(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return cone_margin_floor<Scalar>();
    const Scalar fn = normal_part(f);
    return relative_of(fn, (f - fn * normal).norm());
  }

  /// The monitor's slip test: margin(f) < -slack, for a valid f with f_n > 0 and slack >= 0
  /// (N), decided without a square root as |f_t|^2 > (mu f_n + slack)^2.
  bool slips(const Vector& f, Scalar slack) const {
    const Scalar fn = normal_part(f);
    const Scalar lim = mu * fn + slack;
    return (lim < Scalar(0)) | ((f - fn * normal).squaredNorm() > lim * lim);  // no branch
  }

  /// normal_part, tangential_part, margin and relative_margin of f in one pass.
  ConeMeasure<Scalar> measure(const Vector& f) const {
    ConeMeasure<Scalar> m;
    if (!detail::cone_input_valid(f)) return m;
    m.normal_force = normal_part(f);
    m.tangential_force = f - m.normal_force * normal;
    m.tangential_norm = m.tangential_force.norm();
    m.margin = margin_of(m.normal_force, m.tangential_norm);
    m.relative_margin = relative_of(m.normal_force, m.tangential_norm);
    return m;
  }

  /// Euclidean projection onto the cone (closed form): f itself if inside; 0 if f is in the
  /// polar cone (f_n <= -mu |f_t|); otherwise the nearest point on the boundary ray in the
  /// plane of a and f_t: f_n' = (f_n + mu |f_t|) / (1 + mu^2), f_t' = mu f_n' f_t / |f_t|.
  /// Invalid f gives 0.
  Vector project(const Vector& f) const {
    if (!detail::cone_input_valid(f)) return Vector::Zero();
    const Scalar fn = normal_part(f);
    const Vector3<Scalar> ftv = f - fn * normal;
    const Scalar ft = ftv.norm();
    Scalar sn, st;
    detail::project_2d_cone(fn, ft, mu, sn, st);
    if (sn == fn && st == ft) return f;
    Vector p = sn * normal;
    if (ft > Scalar(0)) p += (st / ft) * ftv;
    return p;
  }

  /// The dual cone {y : y.x >= 0 for all x in the cone}: the Coulomb cone with 1/mu about the
  /// same normal. Convention: the dual of the ray (mu = 0) is the half-space y.a >= 0,
  /// represented by mu = cone_half_space_mu(); and the dual of that is mu = 0 again.
  CoulombCone dual() const { return CoulombCone{normal, detail::dual_coefficient(mu)}; }

 private:
  Scalar margin_of(Scalar fn, Scalar ft) const { return detail::pull_corrected(mu * fn - ft, fn); }
  Scalar relative_of(Scalar fn, Scalar ft) const {
    if (fn <= Scalar(0)) return (fn == Scalar(0) && ft == Scalar(0)) ? Scalar(0) : cone_margin_floor<Scalar>();
    return detail::relative_from(ft, mu * fn);
  }
};

}  // namespace grip
