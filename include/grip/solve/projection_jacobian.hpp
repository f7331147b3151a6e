#pragma once
/// \file
/// Generalised Jacobians of the Euclidean projections onto the exact friction cones, as the
/// semi-smooth Newton method of solve_constrained needs them.
///
/// For a closed convex cone K and a point v, P_K(v) is Lipschitz and piecewise smooth; the
/// matrices below are elements of its (Clarke) generalised Jacobian dP(v): symmetric,
/// 0 <= J <= I. Regions: the interior of K (J = identity on the span of K), the polar cone
/// (J = 0), and the part that projects onto the boundary (closed forms, rank deficient).

#include <cmath>

#include <Eigen/LU>

#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/normal_cone.hpp"
#include "grip/contact/soft_finger_cone.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// Where a point v lies relative to a cone K, as far as the projection's Jacobian is concerned.
enum class ProjectionRegion {
  Interior,  ///< P(v) = v nearby: the Jacobian is the identity on the span of K.
  Polar,     ///< P(v) = 0 nearby: the Jacobian is 0.
  Boundary,  ///< P(v) on the boundary of K: a general symmetric 0 <= J <= I.
};

/// A projection Jacobian and its region (solvers skip the products for Interior and Polar).
template <class Scalar, int Dim>
struct ProjectionJacobian {
  Eigen::Matrix<Scalar, Dim, Dim> matrix;  ///< dP/dv (Dim x Dim, symmetric)
  ProjectionRegion region;                 ///< Interior: matrix = I; Polar: matrix = 0
};

/// dP/dv for the compression cone {x >= 0}: 1 (Interior) for v > 0, else 0 (Polar).
/// `p` is cone.project(v) (unused, for a uniform interface).
template <class Scalar>
ProjectionJacobian<Scalar, 1> projection_jacobian(const CompressionCone<Scalar>&, const Eigen::Matrix<Scalar, 1, 1>& v,
                                                  const Eigen::Matrix<Scalar, 1, 1>&) {
  const bool in = v(0) > Scalar(0);
  return {Eigen::Matrix<Scalar, 1, 1>::Constant(in ? Scalar(1) : Scalar(0)),
          in ? ProjectionRegion::Interior : ProjectionRegion::Polar};
}

/// dP/dv (3x3) for the Coulomb cone with normal a and coefficient mu, at v (p = cone.project(v)).
///
/// Writing n = v.a, f_t = v - n a, tau = |f_t|, e = f_t / tau:
/// - mu = 0 (the ray {n a, n >= 0}): a a^T for n > 0, else 0;
/// - interior (tau < mu n): I;   polar cone (mu tau <= -n): 0;
/// - otherwise P(v) = alpha u with u = a + mu e, alpha = (n + mu tau)/(1 + mu^2), so
///   dP = u u^T / (1 + mu^2) + (alpha mu / tau) (I - a a^T - e e^T)
///   (d alpha/dv = u/(1 + mu^2), d e/dv = (I - a a^T - e e^T)/tau).
template <class Scalar>
ProjectionJacobian<Scalar, 3> projection_jacobian(const CoulombCone<Scalar>& cone, const Vector3<Scalar>& v,
                                                  const Vector3<Scalar>&) {
  using R = ProjectionJacobian<Scalar, 3>;
  const Vector3<Scalar>& a = cone.normal;
  const Scalar mu = cone.mu;
  const Scalar n = v.dot(a);
  const Vector3<Scalar> ft = v - n * a;
  const Scalar tau = ft.norm();
  if (!(mu > Scalar(0))) {
    if (n > Scalar(0)) return R{Matrix3<Scalar>(a * a.transpose()), ProjectionRegion::Boundary};
    return R{Matrix3<Scalar>::Zero(), ProjectionRegion::Polar};
  }
  if (tau < mu * n) return R{Matrix3<Scalar>::Identity(), ProjectionRegion::Interior};
  if (mu * tau <= -n || !(tau > Scalar(0))) return R{Matrix3<Scalar>::Zero(), ProjectionRegion::Polar};
  const Vector3<Scalar> e = ft / tau;
  const Vector3<Scalar> u = a + mu * e;
  const Scalar k = Scalar(1) / (Scalar(1) + mu * mu);
  const Scalar alpha = (n + mu * tau) * k;
  const Scalar beta = alpha * mu / tau;
  Matrix3<Scalar> j = (k * u) * u.transpose();
  j.noalias() += beta * (Matrix3<Scalar>::Identity() - a * a.transpose() - e * e.transpose());
  return R{j, ProjectionRegion::Boundary};
}

namespace detail {

/// dP/dv of the projection onto the 2-D cone spanned by the orthonormal pair (b1, b2) inside
/// R^4, {s b1 + y b2 : |y| <= c s}: the helper for a soft finger with mu = 0 or mu_t = 0,
/// where the cone has no interior in R^4 (coordinates off its plane are projected away).
template <class Scalar>
ProjectionJacobian<Scalar, 4> planar_cone_jacobian(const Eigen::Matrix<Scalar, 4, 1>& b1,
                                                   const Eigen::Matrix<Scalar, 4, 1>& b2, Scalar c,
                                                   const Eigen::Matrix<Scalar, 4, 1>& v) {
  using M4 = Eigen::Matrix<Scalar, 4, 4>;
  using R = ProjectionJacobian<Scalar, 4>;
  const Scalar s = v.dot(b1), y = v.dot(b2);
  const Scalar ay = std::abs(y);
  if (!(c > Scalar(0))) {
    if (s > Scalar(0)) return R{M4(b1 * b1.transpose()), ProjectionRegion::Boundary};
    return R{M4::Zero(), ProjectionRegion::Polar};
  }
  if (ay < c * s) return R{M4(b1 * b1.transpose() + b2 * b2.transpose()), ProjectionRegion::Boundary};
  if (c * ay <= -s) return R{M4::Zero(), ProjectionRegion::Polar};
  const Eigen::Matrix<Scalar, 4, 1> u = (b1 + (y < Scalar(0) ? -c : c) * b2) / std::sqrt(Scalar(1) + c * c);
  return R{M4(u * u.transpose()), ProjectionRegion::Boundary};  // the boundary ray: locally linear
}

}  // namespace detail

/// dP/dv (4x4) for the elliptic soft-finger cone {|f_t|^2/mu^2 + m^2/mu_t^2 <= f_n^2} at
/// v = (f, m), p = cone.project(v).
///
/// - mu > 0 and mu_t > 0: I inside, 0 at the apex (polar cone); on the boundary part, with
///   g(x) = (|f_t|^2/mu^2 + m^2/mu_t^2 - f_n^2)/2 and the projection's multiplier l
///   (p - v + l grad g(p) = 0, recovered from p: l = 1 - v.a / p.a), differentiating the
///   KKT system [H, grad g; grad g^T, 0] [dp; dl] = [dv; 0], H = I + l hess g, gives dp/dv as
///   the leading 4x4 block of the inverse of that 5x5 matrix (solved by LU; it is
///   non-singular even where H is, at l = 1).
/// - mu = 0 or mu_t = 0: the cone is planar (or a ray) in R^4; see detail::planar_cone_jacobian.
template <class Scalar>
ProjectionJacobian<Scalar, 4> projection_jacobian(const SoftFingerCone<Scalar, SoftFingerNorm::Elliptic>& cone,
                                                  const Eigen::Matrix<Scalar, 4, 1>& v,
                                                  const Eigen::Matrix<Scalar, 4, 1>& p) {
  using V4 = Eigen::Matrix<Scalar, 4, 1>;
  using M4 = Eigen::Matrix<Scalar, 4, 4>;
  using R = ProjectionJacobian<Scalar, 4>;
  const Vector3<Scalar>& a = cone.normal;
  const Scalar mu = cone.mu, mt = cone.mu_t;
  V4 an;
  an << a, Scalar(0);
  if (!(mu > Scalar(0)) || !(mt > Scalar(0))) {
    if (mu > Scalar(0)) {  // mu_t = 0: Coulomb on f, m projected to 0
      M4 j = M4::Zero();
      const Vector3<Scalar> f = v.template head<3>();
      const auto jf = projection_jacobian(CoulombCone<Scalar>{a, mu}, f, f);
      if (jf.region == ProjectionRegion::Polar) return R{j, ProjectionRegion::Polar};
      j.template topLeftCorner<3, 3>() = jf.matrix;
      return R{j, ProjectionRegion::Boundary};
    }
    V4 e4 = V4::Zero();
    e4(3) = Scalar(1);
    return detail::planar_cone_jacobian(an, e4, mt, v);  // mu = 0: the plane of (a, m)
  }
  const Scalar vn = v.template head<3>().dot(a);
  const Vector3<Scalar> vt = v.template head<3>() - vn * a;
  const Scalar mu2 = mu * mu, mt2 = mt * mt;
  if (vt.squaredNorm() / mu2 + v(3) * v(3) / mt2 < vn * vn && vn > Scalar(0))
    return R{M4::Identity(), ProjectionRegion::Interior};
  const Scalar pn = p.template head<3>().dot(a);
  if (!(pn > Scalar(0))) return R{M4::Zero(), ProjectionRegion::Polar};  // the apex
  const Vector3<Scalar> pt = p.template head<3>() - pn * a;
  const Scalar l = Scalar(1) - vn / pn;
  Eigen::Matrix<Scalar, 5, 5> k = Eigen::Matrix<Scalar, 5, 5>::Zero();
  const Matrix3<Scalar> aa = a * a.transpose();
  k.template topLeftCorner<3, 3>() = (Scalar(1) + l / mu2) * (Matrix3<Scalar>::Identity() - aa) + (Scalar(1) - l) * aa;
  k(3, 3) = Scalar(1) + l / mt2;
  V4 grad;
  grad << pt / mu2 - pn * a, p(3) / mt2;
  k.template block<4, 1>(0, 4) = grad;
  k.template block<1, 4>(4, 0) = grad.transpose();
  Eigen::Matrix<Scalar, 5, 4> rhs = Eigen::Matrix<Scalar, 5, 4>::Zero();
  rhs.template topRows<4>().setIdentity();
  const Eigen::Matrix<Scalar, 5, 4> sol = k.partialPivLu().solve(rhs);
  M4 j = sol.template topRows<4>();
  j = Scalar(0.5) * (j + j.transpose()).eval();
  if (!j.allFinite()) return R{M4::Zero(), ProjectionRegion::Polar};
  return R{j, ProjectionRegion::Boundary};
}

}  // namespace grip
