#pragma once
/// \file
/// The best command of a 3-D force device per phalanx (VectorForces, device_policy.hpp): the
/// forces within the devices' limits whose net wrench on the hand comes closest to the one the
/// hand should feel, instead of each phalanx scaled down on its own. No heap, no exceptions.
///
/// Phalanx k's device renders any force F_k with |F_k| <= c_k at the phalanx's felt point p_k
/// (c_k = 0 out of contact or without a device). With w*, o, L and T as in
/// net_wrench_command.hpp and B_k = T (I; [p_k - o]x) (6 x 3), the command solves
///
///     minimise   1/2 |sum_k B_k F_k - T w*|^2 + 1/2 eps sum_k |F_k - F0_k|^2
///     subject to |F_k| <= c_k,
///
/// F0_k the phalanx's own force scaled into its ball (the tie-breaker) and eps = tie_weight
/// times the largest |B_k|^2 = 1 + |p_k - o|^2 / L^2 over the phalanges with a device. Its dual
/// is a smooth strongly concave function of the six multipliers y = T (A F - w*) (the weighted
/// residual), with F_k(y) = P_k(F0_k - B_k^T y / eps), P_k the projection onto the ball:
///
///     g(y) = sum_k [eps/2 |F_k(y) - F0_k|^2 + y . B_k F_k(y)] - y . T w* - 1/2 |y|^2,
///     grad g = sum_k B_k F_k(y) - T w* - y,   -Hessian = I + sum_k B_k J_k B_k^T / eps,
///
/// J_k the projection's Jacobian (I inside the ball, (c_k / |v|)(I - v v^T / |v|^2) outside).
/// Newton's method on g with an Armijo line search converges from y = 0 (g is strongly concave
/// and its gradient semismooth), each iteration O(14) and a 6 x 6 solve; it stops when the
/// gradient is at its rounding level (64 eps times its terms, a free force's rounding amplified
/// by 1 / eps included) or a step no longer moves y. What is left, w* - A F, is
/// the unrenderable part of the wrench. Reference: the projection dual, as in
/// solve/detail/dual_newton.hpp (L. Qi and J. Sun, Math. Program. 58, 1993).

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/phalanx.hpp"
#include "grip/pipeline/net_wrench_command.hpp"

namespace grip {

/// What net_wrench_vector_command returns.
template <class Scalar>
struct NetWrenchVectorCommand {
  std::array<Vector3<Scalar>, hand_phalanx_count> force{};  ///< each device's force (N, world), |F_k| <= c_k
  /// w* - A F: the wrench the hand should feel and the devices do not render (N; N m about
  /// `point`).
  Wrench<Scalar> unrendered{Wrench<Scalar>::Zero()};
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};  ///< o, the moments' reference point (m, world)
  int iterations{0};                               ///< Newton iterations taken
  /// Ok; InvalidInput (all zero) for non-finite input or a negative limit; IterationLimit when
  /// the bound of 50 iterations is reached (the last iterate's forces, within their limits).
  Status status{Status::InvalidInput};
  NetWrenchVectorCommand() { force.fill(Vector3<Scalar>::Zero()); }
};

/// The best force of each phalanx's 3-D device (see the file comment) for the felt forces
/// `force` and points `point` of the hand's bodies, in contact where `in_contact`, and the
/// limits `limit` (N, >= 0; 0 for a phalanx without a device). `tie_weight` (> 0, default
/// 1e-6) weighs the forces' distance from each phalanx's own force scaled into its limit.
template <class Scalar>
NetWrenchVectorCommand<Scalar> net_wrench_vector_command(const std::array<Vector3<Scalar>, hand_body_count>& force,
                                                         const std::array<Vector3<Scalar>, hand_body_count>& point,
                                                         const std::array<bool, hand_body_count>& in_contact,
                                                         const std::array<Scalar, hand_phalanx_count>& limit,
                                                         Scalar tie_weight = Scalar(1e-6)) {
  constexpr int m = hand_phalanx_count;
  using V3 = Vector3<Scalar>;
  using B = Eigen::Matrix<Scalar, 6, 3>;
  NetWrenchVectorCommand<Scalar> out;
  bool ok = std::isfinite(tie_weight) && tie_weight > Scalar(0);
  for (int b = 0; b < hand_body_count && ok; ++b)
    ok = force[detail::idx(b)].allFinite() && point[detail::idx(b)].allFinite();
  for (int k = 0; k < m && ok; ++k) ok = std::isfinite(limit[detail::idx(k)]) && limit[detail::idx(k)] >= Scalar(0);
  if (!ok) return out;
  const FeltNetWrench<Scalar> felt = felt_net_wrench(force, point, in_contact);
  out.point = felt.point;
  const Scalar il = Scalar(1) / felt.lever;
  Wrench<Scalar> tw = felt.wrench;
  tw.template tail<3>() *= il;
  // The devices: B_k, the limit c_k, the tie-breaker F0_k; eps from the largest |B_k|^2.
  std::array<B, m> bk;
  std::array<Scalar, m> c{};
  std::array<V3, m> f0;
  Scalar bmax(1), scale = tw.norm();
  for (int k = 0; k < m; ++k) {
    const auto i = detail::idx(k);
    const V3 r = point[i] - felt.point;
    bk[i].template topRows<3>().setIdentity();
    bk[i].template bottomRows<3>() << Scalar(0), -r.z(), r.y(), r.z(), Scalar(0), -r.x(), -r.y(), r.x(), Scalar(0);
    bk[i].template bottomRows<3>() *= il;
    c[i] = in_contact[i] ? limit[i] : Scalar(0);
    const Scalar n = force[i].norm();
    f0[i] = n > c[i] ? V3(force[i] * (c[i] / n)) : force[i];
    if (c[i] > Scalar(0)) bmax = std::fmax(bmax, Scalar(1) + r.squaredNorm() * il * il);
    scale += std::sqrt(Scalar(1) + r.squaredNorm() * il * il) * c[i];
  }
  const Scalar eps = tie_weight * bmax;
  // F_k(y), g(y) and grad g(y).
  std::array<V3, m> f;
  const auto forces_at = [&](const Wrench<Scalar>& y, std::array<V3, m>& into, Wrench<Scalar>& grad) {
    Scalar value = -y.dot(tw) - Scalar(0.5) * y.squaredNorm();
    grad = -tw - y;
    for (int k = 0; k < m; ++k) {
      const auto i = detail::idx(k);
      const V3 v = f0[i] - bk[i].transpose() * y / eps;
      const Scalar n = v.norm();
      into[i] = n > c[i] ? V3(v * (c[i] / n)) : v;
      const Wrench<Scalar> bf = bk[i] * into[i];
      value += Scalar(0.5) * eps * (into[i] - f0[i]).squaredNorm() + y.dot(bf);
      grad += bf;
    }
    return value;
  };
  Wrench<Scalar> y = Wrench<Scalar>::Zero(), grad;
  Scalar value = forces_at(y, f, grad);
  // The gradient's rounding: its terms' size, and a free force's rounding in y amplified by
  // 1 / eps (F_k = F0_k - B_k^T y / eps inside the ball).
  const Scalar unit = Scalar(64) * std::numeric_limits<Scalar>::epsilon();
  const auto tolerance = [&](const Wrench<Scalar>& at) {
    return unit * (scale + bmax * at.norm() / tie_weight) + std::numeric_limits<Scalar>::min();
  };
  constexpr int max_iterations = 50;
  out.status = Status::IterationLimit;
  for (int it = 0; it <= max_iterations; ++it) {
    out.iterations = it;
    if (grad.norm() <= tolerance(y)) {
      out.status = Status::Ok;
      break;
    }
    if (it == max_iterations) break;
    // -Hessian = I + sum_k B_k J_k B_k^T / eps at the current y.
    Matrix6<Scalar> h = Matrix6<Scalar>::Identity();
    for (int k = 0; k < m; ++k) {
      const auto i = detail::idx(k);
      if (c[i] == Scalar(0)) continue;
      const V3 v = f0[i] - bk[i].transpose() * y / eps;
      const Scalar n = v.norm();
      Matrix3<Scalar> j = Matrix3<Scalar>::Identity();
      if (n > c[i]) j = (c[i] / n) * (Matrix3<Scalar>::Identity() - v * v.transpose() / (n * n));
      h += bk[i] * j * bk[i].transpose() / eps;
    }
    const Wrench<Scalar> d = Eigen::LLT<Matrix6<Scalar>>(h).solve(grad);
    // Armijo on g (maximised): halve until it rises by a fraction of its slope (or no step does).
    const Scalar slope = grad.dot(d);
    Scalar t(1);
    std::array<V3, m> trial;
    Wrench<Scalar> trial_grad;
    Scalar trial_value = value;
    bool moved = false;
    for (int half = 0; half < 40; ++half, t *= Scalar(0.5)) {
      trial_value = forces_at(Wrench<Scalar>(y + t * d), trial, trial_grad);
      if (trial_value >= value + Scalar(1e-4) * t * slope) {
        moved = true;
        break;
      }
    }
    if (!moved || !(slope > Scalar(0))) {
      // At rounding level: no step raises g. The iterate is the answer to the precision there is.
      out.status = Status::Ok;
      break;
    }
    const Wrench<Scalar> step = t * d;
    y += step;
    f = trial;
    grad = trial_grad;
    value = trial_value;
    if (step.norm() <= unit * y.norm()) {  // no progress left at this precision
      out.status = Status::Ok;
      break;
    }
  }
  out.force = f;
  Wrench<Scalar> rendered = Wrench<Scalar>::Zero();
  for (int k = 0; k < m; ++k) {
    const auto i = detail::idx(k);
    rendered.template head<3>() += f[i];
    rendered.template tail<3>() += (point[i] - felt.point).cross(f[i]);
  }
  out.unrendered = felt.wrench - rendered;
  return out;
}

}  // namespace grip
