#pragma once
/// \file
/// The objectives F1 (eq. 6) and F2 (eq. 7) of the paper, with per-contact weights.

#include "grip/grasp/grasp.hpp"

namespace grip {

/// F2 = 1/2 sum_i w_i |x_i - t_i|^2 (eq. 7 with weights), t_i = Model::target (s_i a_i for a
/// hard finger). `x` holds grasp.unknowns() values. Units: N^2 times the weights' units.
template <class GraspT, class Derived>
typename GraspT::ScalarType objective_f2(const GraspT& grasp, const Eigen::MatrixBase<Derived>& x) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  S sum(0);
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    sum += c.weight * (x.template segment<d>(i * d) - M::target(c)).squaredNorm();
  }
  return S(0.5) * sum;
}

/// F1 = 1/2 sum_i w_i |x_i|^2 (eq. 6 with weights): F2 with every squeeze s_i = 0.
template <class GraspT, class Derived>
typename GraspT::ScalarType objective_f1(const GraspT& grasp, const Eigen::MatrixBase<Derived>& x) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  S sum(0);
  for (int i = 0; i < grasp.size(); ++i) sum += grasp.contact(i).weight * x.template segment<d>(i * d).squaredNorm();
  return S(0.5) * sum;
}

}  // namespace grip
