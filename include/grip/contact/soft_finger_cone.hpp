#pragma once
/// \file
/// The friction cone of a soft finger: force plus torsional moment about the normal.

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact.hpp"
#include "grip/core/types.hpp"

namespace grip {

namespace detail {

/// The value halfway between 0 <= lo < hi (finite floats) in the order of their
/// representations: for non-negative IEEE values the bit patterns, read as unsigned integers,
/// are ordered as the values, so this midpoint halves the count of values between the bounds.
/// A bisection on it reaches adjacent values in at most 8 sizeof(S) steps whatever the
/// magnitude of the root (the arithmetic midpoint resolves a root near 0 only absolutely).
template <class S>
S representation_midpoint(S lo, S hi) {
  static_assert(sizeof(S) == 4 || sizeof(S) == 8, "float or double");
  using Bits = typename std::conditional<sizeof(S) == 8, std::uint64_t, std::uint32_t>::type;
  Bits a, b;
  std::memcpy(&a, &lo, sizeof(S));
  std::memcpy(&b, &hi, sizeof(S));
  const Bits m = static_cast<Bits>(a + (b - a) / 2);
  S out;
  std::memcpy(&out, &m, sizeof(S));
  return out;
}

}  // namespace detail

/// How the tangential force and the torsional moment share the friction budget of a soft finger.
/// With f_n = f.a (N), t = |f_t| (N), m the moment about a (N m), mu >= 0 and mu_t >= 0 (m):
enum class SoftFingerNorm {
  Elliptic,   ///< t^2/mu^2 + m^2/mu_t^2 <= f_n^2 (the usual soft-finger model)
  Linear,     ///< t/mu + |m|/mu_t <= f_n (its linear, conservative variant)
  Decoupled,  ///< t <= mu f_n and |m| <= mu_t f_n (the dual of Linear; contains Elliptic)
};

/// The soft-finger cone over the contact unknown x = (f, m) (4-vector, grip's order, docs/conventions.md:
/// force on the object in N, then the moment about the inward normal a in N m).
///
/// Writing rho(x) = N(t/mu, |m|/mu_t) for the normal force the tangential load needs
/// (N = 2-norm, 1-norm or max-norm per SoftFingerNorm; 0/0 counts as 0, y/0 with y > 0 as
/// infinite), the cone is {rho(x) <= f_n}.
///
/// Margin (N), positive inside, 0 on the boundary, negative outside:
/// - mu > 0, mu_t > 0: mu (f_n - rho) (for m = 0 this is CoulombCone's mu f_n - |f_t|);
/// - mu > 0, mu_t = 0 (no torsion transmissible): mu f_n - t if m = 0, else
///   min(mu f_n - t, 0) - |m| / (1 m) (a moment counts as the force over a 1 m lever);
/// - mu = 0, mu_t > 0: -t if |m| <= mu_t f_n, else -t - (|m|/mu_t - f_n);
/// - mu = mu_t = 0 (a ray): -t - |m| / (1 m);
/// then, for f_n < 0, the pull correction min(margin, f_n).
/// Relative margin: 1 - rho / f_n with CoulombCone's conventions (1 for no tangential load
/// and f_n > 0, 0 for x = 0, cone_margin_floor() for f_n <= 0 otherwise or rho infinite).
/// Invalid input follows cone_support.hpp. Preconditions: |a| = 1, mu, mu_t >= 0 finite.
template <class Scalar, SoftFingerNorm Norm = SoftFingerNorm::Elliptic>
struct SoftFingerCone {
  using ScalarType = Scalar;                    ///< the scalar type (float or double)
  static constexpr int dim = 4;                 ///< size of the contact unknown (f, m)
  static constexpr SoftFingerNorm norm = Norm;  ///< the coupling of force and moment
  using Vector = Eigen::Matrix<Scalar, 4, 1>;   ///< (f (N), m (N m))
  /// The norm of dual(): Elliptic -> Elliptic, Linear <-> Decoupled.
  static constexpr SoftFingerNorm dual_norm = Norm == SoftFingerNorm::Linear      ? SoftFingerNorm::Decoupled
                                              : Norm == SoftFingerNorm::Decoupled ? SoftFingerNorm::Linear
                                                                                  : SoftFingerNorm::Elliptic;
  /// The type of dual(): Elliptic -> Elliptic, Linear <-> Decoupled.
  using DualType = SoftFingerCone<Scalar, dual_norm>;

  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};  ///< a, unit, into the object
  Scalar mu{0};                                      ///< Coulomb coefficient, >= 0
  Scalar mu_t{0};                                    ///< torsional coefficient (m), >= 0

  /// Bisection steps of the elliptic projection: the bits of Scalar (64 double, 32 float).
  /// Each step halves the count of Scalar values between the bounds, so this many always
  /// reach adjacent values, whatever the root's magnitude.
  static constexpr int projection_iterations = static_cast<int>(8 * sizeof(Scalar));

  /// The cone of contact c: a = c.normal, mu = c.friction, mu_t = c.torsional_friction.
  static SoftFingerCone from_contact(const Contact<Scalar>& c) {
    return SoftFingerCone{c.normal, c.friction, c.torsional_friction};
  }

  /// f_n = f.a (N).
  Scalar normal_part(const Vector& x) const { return x.template head<3>().dot(normal); }
  /// f_t = f - (f.a) a (N).
  Vector3<Scalar> tangential_part(const Vector& x) const { return x.template head<3>() - normal_part(x) * normal; }
  /// |f_t| (N).
  Scalar tangential_norm(const Vector& x) const { return tangential_part(x).norm(); }
  /// The torsional moment m (N m).
  Scalar moment(const Vector& x) const { return x(3); }

  /// True iff rho(x) <= f_n. False for invalid x.
  bool is_inside(const Vector& x) const { return margin(x) >= Scalar(0); }

  /// Signed margin (N), see the class comment.
  Scalar margin(const Vector& x) const {
    if (!detail::cone_input_valid(x)) return cone_margin_floor<Scalar>();
    const Scalar fn = normal_part(x);
    return margin_of(fn, (x.template head<3>() - fn * normal).norm(), std::abs(x(3)));
  }

  /// Relative margin 1 - rho / f_n, see the class comment.
  Scalar relative_margin(const Vector& x) const {
    if (!detail::cone_input_valid(x)) return cone_margin_floor<Scalar>();
    const Scalar fn = normal_part(x);
    return relative_of(fn, (x.template head<3>() - fn * normal).norm(), std::abs(x(3)));
  }

  /// The monitor's slip test: margin(x) < -slack, for a valid x with f_n > 0 and slack >= 0 (N).
  bool slips(const Vector& x, Scalar slack) const { return margin(x) < -slack; }

  /// normal_part, tangential_part, moment, margin and relative_margin of x in one pass.
  ConeMeasure<Scalar> measure(const Vector& x) const {
    ConeMeasure<Scalar> m;
    if (!detail::cone_input_valid(x)) return m;
    m.normal_force = normal_part(x);
    m.tangential_force = x.template head<3>() - m.normal_force * normal;
    m.tangential_norm = m.tangential_force.norm();
    m.moment = x(3);
    const Scalar q = std::abs(x(3));
    m.margin = margin_of(m.normal_force, m.tangential_norm, q);
    m.relative_margin = relative_of(m.normal_force, m.tangential_norm, q);
    return m;
  }

  /// Euclidean projection onto the cone (in the coordinates (f, m), N and N m alike).
  /// By the cone's symmetry the answer keeps the direction of f_t and the sign of m, so it is
  /// found in the 3 coordinates (f_n, t, m):
  /// - inside: x; mu = 0 or mu_t = 0: the closed form of a 2-D cone (CoulombCone's) in the
  ///   coordinates that remain, the others set to 0;
  /// - Linear, Decoupled: the 4-edged pyramid in (f_n, t, m), closed form over its faces;
  /// - Elliptic: 0 if x is in the polar cone sqrt(mu^2 t^2 + mu_t^2 m^2) <= -f_n; otherwise
  ///   the KKT point t' = t mu^2/(mu^2 + l), m' = m mu_t^2/(mu_t^2 + l),
  ///   f_n' = sqrt(t'^2/mu^2 + m'^2/mu_t^2), whose multiplier l > 0 solves
  ///   (1 - l) f_n'(l) = f_n; it is the only root and is found by bisection on
  ///   l = s/(1 - s), s in (0, 1), in at most projection_iterations steps (bounded time). The
  ///   bisection halves the representations between the bounds, not their distance, so l is
  ///   found to round-off relative to itself: the moment's share, which is decided where l
  ///   is of the order of mu_t^2 (1e-10 for a torsional coefficient of 10 micrometres), is
  ///   as exact as the force's.
  /// Invalid x gives 0.
  Vector project(const Vector& x) const {
    if (!detail::cone_input_valid(x)) return Vector::Zero();
    if (is_inside(x)) return x;
    const Scalar s = normal_part(x);
    const Vector3<Scalar> ftv = tangential_part(x);
    const Scalar t = ftv.norm(), q = x(3);
    Scalar s2 = 0, t2 = 0, q2 = 0;
    const bool has_mu = positive(mu), has_mu_t = positive(mu_t);  // denormal: 0 (see positive())
    if (!has_mu && !has_mu_t) {
      s2 = s > Scalar(0) ? s : Scalar(0);
    } else if (!has_mu) {
      Scalar qa;
      detail::project_2d_cone(s, std::abs(q), mu_t, s2, qa);
      q2 = q < Scalar(0) ? -qa : qa;
    } else if (!has_mu_t) {
      detail::project_2d_cone(s, t, mu, s2, t2);
    } else if (Norm == SoftFingerNorm::Elliptic) {
      project_elliptic(s, t, q, s2, t2, q2);
    } else {
      std::array<Vector3<Scalar>, 4> e;
      if (Norm == SoftFingerNorm::Linear) {
        e[0] << Scalar(1), mu, Scalar(0);
        e[1] << Scalar(1), Scalar(0), mu_t;
        e[2] << Scalar(1), -mu, Scalar(0);
        e[3] << Scalar(1), Scalar(0), -mu_t;
      } else {
        e[0] << Scalar(1), mu, mu_t;
        e[1] << Scalar(1), -mu, mu_t;
        e[2] << Scalar(1), -mu, -mu_t;
        e[3] << Scalar(1), mu, -mu_t;
      }
      for (auto& v : e) v /= v.norm();
      const Vector3<Scalar> p = detail::project_onto_edge_cone(Vector3<Scalar>(s, t, q), e);
      s2 = p(0);
      t2 = p(1) > Scalar(0) ? p(1) : Scalar(0);
      q2 = p(2);
    }
    Vector out;
    out.template head<3>() = s2 * normal;
    if (t > Scalar(0)) out.template head<3>() += (t2 / t) * ftv;
    out(3) = q2;
    return out;
  }

  /// The dual cone {y : y.x >= 0 for all x in the cone}, pairing (f, m) with (v, w) as
  /// f.v + m w: Elliptic(mu, mu_t) -> Elliptic(1/mu, 1/mu_t); Linear(mu, mu_t) <->
  /// Decoupled(1/mu, 1/mu_t). A zero coefficient maps to cone_half_space_mu() and back.
  DualType dual() const { return DualType{normal, detail::dual_coefficient(mu), detail::dual_coefficient(mu_t)}; }

 private:
  /// A coefficient counts as positive only when its square does not underflow (a denormal mu
  /// is treated as 0: the formulas divide by mu and mu^2; the difference is below mu |x|).
  static bool positive(Scalar c) { return c * c >= std::numeric_limits<Scalar>::min(); }

  Scalar margin_of(Scalar fn, Scalar t, Scalar q) const {
    const bool has_mu = positive(mu), has_mu_t = positive(mu_t);
    Scalar m;
    if (has_mu && has_mu_t) {
      m = mu * (fn - combine(t / mu, q / mu_t));
    } else if (has_mu) {
      const Scalar c = mu * fn - t;
      m = q == Scalar(0) ? c : (c < Scalar(0) ? c : Scalar(0)) - q;
    } else if (has_mu_t) {
      m = q <= mu_t * fn ? -t : -t - (q / mu_t - fn);
    } else {
      m = -t - q;
    }
    if (!(m >= cone_margin_floor<Scalar>())) m = cone_margin_floor<Scalar>();  // overflow: keep it finite
    return detail::pull_corrected(m, fn);
  }

  Scalar relative_of(Scalar fn, Scalar t, Scalar q) const {
    if (fn <= Scalar(0))
      return (fn == Scalar(0) && t == Scalar(0) && q == Scalar(0)) ? Scalar(0) : cone_margin_floor<Scalar>();
    if ((t > Scalar(0) && !positive(mu)) || (q > Scalar(0) && !positive(mu_t))) return cone_margin_floor<Scalar>();
    const Scalar a = t > Scalar(0) ? t / mu : Scalar(0);
    const Scalar b = q > Scalar(0) ? q / mu_t : Scalar(0);
    return detail::relative_from(combine(a, b), fn);
  }

  static Scalar combine(Scalar a, Scalar b) {
    if (Norm == SoftFingerNorm::Elliptic) return std::sqrt(a * a + b * b);
    if (Norm == SoftFingerNorm::Linear) return a + b;
    return a > b ? a : b;
  }

  void project_elliptic(Scalar s, Scalar t, Scalar q, Scalar& s2, Scalar& t2, Scalar& q2) const {
    const Scalar qa = std::abs(q);
    const Scalar m2 = mu * mu, mt2 = mu_t * mu_t;
    if (std::sqrt(m2 * t * t + mt2 * qa * qa) <= -s) return;  // polar cone: the apex
    const auto at = [&](Scalar l, Scalar& tl, Scalar& ql) {
      tl = t * (m2 / (m2 + l));
      ql = qa * (mt2 / (mt2 + l));
      return std::sqrt(tl * tl / m2 + ql * ql / mt2);
    };
    Scalar lo = 0, hi = 1;  // in s = l / (1 + l)
    for (int k = 0; k < projection_iterations; ++k) {
      const Scalar mid = detail::representation_midpoint(lo, hi);
      if (!(mid > lo && mid < hi)) break;  // adjacent values: done
      const Scalar l = mid / (Scalar(1) - mid);
      Scalar tl, ql;
      const Scalar sl = at(l, tl, ql);
      if ((Scalar(1) - l) * sl - s > Scalar(0))
        lo = mid;
      else
        hi = mid;
    }
    const Scalar mid = detail::representation_midpoint(lo, hi);
    Scalar tl, ql;
    s2 = at(mid / (Scalar(1) - mid), tl, ql);
    t2 = tl;
    q2 = q < Scalar(0) ? -ql : ql;
  }
};

}  // namespace grip
