#pragma once
/// \file
/// The best command of one actuator per phalanx (PhalanxActuators, device_policy.hpp): the
/// pushes within the actuators' limits whose net wrench on the hand comes closest to the one
/// the hand should feel, instead of each phalanx clipped on its own. No heap, no exceptions.
///
/// Phalanx k's actuator pushes with f_k in [0, c_k] along its direction d_k at the phalanx's
/// felt point p_k (FeltForces); a phalanx out of contact renders nothing (c_k = 0 for it). The
/// hand should feel w* = sum_b (F_b, (p_b - o) x F_b) over every body b, the palm's included
/// (which no phalanx actuator renders). With A the 6 x 14 matrix of columns
/// (d_k, (p_k - o) x d_k), the moments divided by the lever length L, the command solves
///
///     minimise   1/2 |T (A f - w*)|^2 + 1/2 eps |f - f_0|^2     subject to 0 <= f_k <= c_k,
///
/// T = diag(1, 1, 1, 1/L, 1/L, 1/L), o the mean of the contact bodies' points, L the largest
/// distance of one from o (at least 1 cm), f_0 the phalanges' own clipped pushes (the
/// tie-breaker) and eps = tie_weight times the largest diagonal entry of A^T T^2 A. The
/// problem is strictly convex: a primal active-set method (bounded-variable least squares,
/// P. B. Stark and R. L. Parker, Computational Statistics 10, 1995) reaches its optimum exactly, in at most 3 x 14
/// steps of a 14 x 14 Cholesky solve. What is left, w* - A f, is the unrenderable part of the wrench.

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/phalanx.hpp"

namespace grip {

/// What net_wrench_command returns.
template <class Scalar>
struct NetWrenchCommand {
  std::array<Scalar, hand_phalanx_count> force{};  ///< each actuator's push (N), in [0, c_k]
  /// w* - A f: the wrench the hand should feel and the actuators do not render (N; N m about
  /// `point`).
  Wrench<Scalar> unrendered{Wrench<Scalar>::Zero()};
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< o, the moments' reference point (m, world)
  int steps{0};                                    ///< active-set steps taken
  /// Ok; InvalidInput (all zero) for non-finite input or a negative limit; IterationLimit if the
  /// bound on steps is reached (the last feasible iterate is returned).
  Status status{Status::InvalidInput};
};

namespace detail {

/// The box-constrained strictly convex quadratic min 1/2 f^T H f - g^T f, lo <= f <= hi (lo <=
/// hi), by a primal active-set method from the feasible `f` (clipped into the box first).
/// Returns the steps taken, or -1 when `max_steps` ran out.
template <class Scalar, int M>
int box_quadratic(const Eigen::Matrix<Scalar, M, M>& h, const Eigen::Matrix<Scalar, M, 1>& g,
                  const Eigen::Matrix<Scalar, M, 1>& lo, const Eigen::Matrix<Scalar, M, 1>& hi,
                  Eigen::Matrix<Scalar, M, 1>& f, int max_steps) {
  using Vec = Eigen::Matrix<Scalar, M, 1>;
  using Mat = Eigen::Matrix<Scalar, M, M>;
  f = f.cwiseMax(lo).cwiseMin(hi);
  std::array<bool, M> fixed{};  // held at a bound
  for (int k = 0; k < M; ++k) fixed[idx(k)] = f(k) == lo(k) || f(k) == hi(k);
  for (int step = 0; step < max_steps; ++step) {
    // The minimiser over the free variables, the fixed ones held: rows of a fixed variable
    // replaced by the identity.
    Mat m = h;
    Vec rhs = g;
    for (int j = 0; j < M; ++j) {
      if (!fixed[idx(j)]) continue;
      rhs -= h.col(j) * f(j);
      m.row(j).setZero();
      m.col(j).setZero();
      m(j, j) = Scalar(1);
    }
    for (int j = 0; j < M; ++j)
      if (fixed[idx(j)]) rhs(j) = f(j);
    const Vec target = Eigen::LLT<Mat>(m).solve(rhs);
    // Toward it until the first free variable meets its bound.
    Scalar alpha(1);
    int blocking = -1;
    bool upper = false;
    for (int k = 0; k < M; ++k) {
      if (fixed[idx(k)]) continue;
      const Scalar d = target(k) - f(k);
      if (target(k) > hi(k) && d > Scalar(0)) {
        const Scalar a = (hi(k) - f(k)) / d;
        if (a < alpha) alpha = a, blocking = k, upper = true;
      } else if (target(k) < lo(k) && d < Scalar(0)) {
        const Scalar a = (lo(k) - f(k)) / d;
        if (a < alpha) alpha = a, blocking = k, upper = false;
      }
    }
    if (blocking >= 0) {
      for (int k = 0; k < M; ++k)
        if (!fixed[idx(k)]) f(k) = std::fmin(hi(k), std::fmax(lo(k), f(k) + alpha * (target(k) - f(k))));
      f(blocking) = upper ? hi(blocking) : lo(blocking);
      fixed[idx(blocking)] = true;
      continue;
    }
    for (int k = 0; k < M; ++k)
      if (!fixed[idx(k)]) f(k) = target(k);
    // Optimal on this face; free the fixed variable whose multiplier has the wrong sign most.
    const Vec grad = h * f - g;
    int release = -1;
    Scalar worst(0);
    for (int k = 0; k < M; ++k) {
      if (!fixed[idx(k)] || lo(k) == hi(k)) continue;
      const Scalar v = f(k) == lo(k) ? -grad(k) : grad(k);  // > 0: moving inward lowers the cost
      if (v > worst) worst = v, release = k;
    }
    if (release < 0) return step + 1;
    fixed[idx(release)] = false;
  }
  return -1;
}

}  // namespace detail

/// The net wrench w* the hand should feel (N; N m about `point`), over every body's felt force
/// `force` at `point`: `point` is o, the mean of the contact bodies' points (the origin when none
/// touches), and `lever` L, the largest distance of one from o (at least 1 cm).
template <class Scalar>
struct FeltNetWrench {
  Wrench<Scalar> wrench{Wrench<Scalar>::Zero()};   ///< w* (N; N m about `point`)
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< o (m, world)
  Scalar lever{Scalar(0.01)};                      ///< L (m)
};

/// w*, o and L of `force` and `point` with contacts `in_contact` (see FeltNetWrench).
template <class Scalar>
FeltNetWrench<Scalar> felt_net_wrench(const std::array<Vector3<Scalar>, hand_body_count>& force,
                                      const std::array<Vector3<Scalar>, hand_body_count>& point,
                                      const std::array<bool, hand_body_count>& in_contact) {
  FeltNetWrench<Scalar> out;
  int touching = 0;
  for (int b = 0; b < hand_body_count; ++b)
    if (in_contact[detail::idx(b)]) out.point += point[detail::idx(b)], ++touching;
  if (touching > 0) out.point /= Scalar(touching);
  for (int b = 0; b < hand_body_count; ++b) {
    const auto i = detail::idx(b);
    if (in_contact[i]) out.lever = std::fmax(out.lever, (point[i] - out.point).norm());
    out.wrench.template head<3>() += force[i];
    out.wrench.template tail<3>() += (point[i] - out.point).cross(force[i]);
  }
  return out;
}

/// The part of `felt`'s wrench that pushes `push` (N) along `direction` at the phalanges'
/// `point`s do not render: w* - sum_k push_k (d_k, (p_k - o) x d_k).
template <class Scalar>
Wrench<Scalar> unrendered_wrench(const FeltNetWrench<Scalar>& felt,
                                 const std::array<Vector3<Scalar>, hand_body_count>& point,
                                 const std::array<Vector3<Scalar>, hand_phalanx_count>& direction,
                                 const std::array<Scalar, hand_phalanx_count>& push) {
  Wrench<Scalar> r = felt.wrench;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    const auto i = detail::idx(k);
    r.template head<3>() -= push[i] * direction[i];
    r.template tail<3>() -= push[i] * (point[i] - felt.point).cross(direction[i]);
  }
  return r;
}

/// The best push of each phalanx actuator (see the file comment) for the felt forces `force`
/// and points `point` of the hand's bodies, in contact where `in_contact`, the phalanges'
/// actuation directions `direction` and limits `limit` (N, >= 0). `tie_weight` (> 0, default
/// 1e-6) weighs the pushes' distance from each phalanx's own clipped push.
template <class Scalar>
NetWrenchCommand<Scalar> net_wrench_command(const std::array<Vector3<Scalar>, hand_body_count>& force,
                                            const std::array<Vector3<Scalar>, hand_body_count>& point,
                                            const std::array<bool, hand_body_count>& in_contact,
                                            const std::array<Vector3<Scalar>, hand_phalanx_count>& direction,
                                            const std::array<Scalar, hand_phalanx_count>& limit,
                                            Scalar tie_weight = Scalar(1e-6)) {
  constexpr int m = hand_phalanx_count;
  using Vec = Eigen::Matrix<Scalar, m, 1>;
  NetWrenchCommand<Scalar> out;
  bool ok = std::isfinite(tie_weight) && tie_weight > Scalar(0);
  for (int b = 0; b < hand_body_count && ok; ++b)
    ok = force[detail::idx(b)].allFinite() && point[detail::idx(b)].allFinite();
  for (int k = 0; k < m && ok; ++k) ok = direction[detail::idx(k)].allFinite() && limit[detail::idx(k)] >= Scalar(0);
  if (!ok) return out;
  const FeltNetWrench<Scalar> felt = felt_net_wrench(force, point, in_contact);
  const Vector3<Scalar>& o = felt.point;
  const Scalar lever = felt.lever;
  const Wrench<Scalar>& want = felt.wrench;
  out.point = o;
  Eigen::Matrix<Scalar, 6, m> a;
  Vec lo = Vec::Zero(), hi, f0;
  for (int k = 0; k < m; ++k) {
    const auto i = detail::idx(k);
    a.col(k).template head<3>() = direction[i];
    a.col(k).template tail<3>() = (point[i] - o).cross(direction[i]);
    hi(k) = in_contact[i] ? limit[i] : Scalar(0);
    f0(k) = std::fmin(hi(k), std::fmax(Scalar(0), force[i].dot(direction[i])));
  }
  Wrench<Scalar> t = Wrench<Scalar>::Ones();
  t.template tail<3>().setConstant(Scalar(1) / lever);
  const Eigen::Matrix<Scalar, 6, m> ta = t.asDiagonal() * a;
  const Wrench<Scalar> tw = t.cwiseProduct(want);
  Eigen::Matrix<Scalar, m, m> h = ta.transpose() * ta;
  const Scalar eps = tie_weight * std::fmax(h.diagonal().maxCoeff(), Scalar(1));
  h.diagonal().array() += eps;
  const Vec g = ta.transpose() * tw + eps * f0;
  Vec f = f0;
  const int steps = detail::box_quadratic<Scalar, m>(h, g, lo, hi, f, 3 * m);
  out.steps = steps < 0 ? 3 * m : steps;
  out.status = steps < 0 ? Status::IterationLimit : Status::Ok;
  for (int k = 0; k < m; ++k) out.force[detail::idx(k)] = f(k);
  out.unrendered = unrendered_wrench(felt, point, direction, out.force);
  return out;
}

}  // namespace grip
