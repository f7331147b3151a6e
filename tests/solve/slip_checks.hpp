#pragma once
// Checks of a slip's answer from their definitions (docs/solve.md), for the solve_constrained
// tests: the certificate against the dual cones, and the least-residual objective P that the
// forces of a slip minimise. In double, from the contacts' data, not through the solver's code.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <grip/grip.hpp>

#include "solve/constrained_support.hpp"
#include "support/equilibrium_norm.hpp"
#include "support/tolerance.hpp"

namespace grip_test {

/// Checks that y is a certificate of hard-finger grasp g under w: y.w > 0, dual norm 1, and every
/// G_i^T y within 1.5 certificate_tolerance (y.w) / |w|_L of K_i^* (plus the rounding in S).
template <class GraspT>
void check_certificate(const GraspT& g, const grip::Wrench<typename GraspT::ScalarType>& w,
                       const grip::Wrench<typename GraspT::ScalarType>& certificate) {
  using S = typename GraspT::ScalarType;
  const grip::ConstrainedSettings<S> st;
  const grip::Wrench<double> y = certificate.template cast<double>(), wd = w.template cast<double>();
  const double len = grasp_lever_length(g);
  const double yw = y.dot(wd);
  CHECK(yw > 0.0);
  CHECK(std::abs(dual_norm_l(y, len) - 1.0) <= roundoff<S>(8, 1, 1));
  const double tol = 1.5 * double(st.certificate_tolerance) * yw / norm_l(wd, len);
  for (int i = 0; i < g.size(); ++i) {
    const grip::Contact<double> c = cast_contact<double>(g.contact(i));
    CHECK(dual_cone_violation<grip::HardFinger>(c, grip::HardFinger::wrench_transpose(c, y)) <=
          tol + roundoff<S>(8, 1 + c.friction, 1 + c.position.norm() / len));
  }
}

/// delta of the least-residual problem: least_residual_weight times the largest diagonal entry of
/// G W^-1 G^T in the equilibrium norm's units (hard fingers).
template <class GraspT>
double least_residual_delta(const GraspT& g) {
  const double len = grasp_lever_length(g);
  double delta = 0;
  for (int j = 0; j < 6; ++j) {
    double dj = 0;
    for (int i = 0; i < g.size(); ++i) {
      const grip::Contact<double> c = cast_contact<double>(g.contact(i));
      dj += grip::HardFinger::wrench_transpose(c, grip::Wrench<double>(grip::Wrench<double>::Unit(j))).squaredNorm() /
            c.weight;
    }
    delta = std::max(delta, j < 3 ? dj : dj / (len * len));
  }
  return delta * double(grip::ConstrainedSettings<typename GraspT::ScalarType>{}.least_residual_weight);
}

/// P(x) = |G x + w_ext|_L^2 / 2 + delta F2(x), the least-residual objective, in double (hard fingers).
template <class GraspT, class Forces>
double least_residual_objective(const GraspT& g, const grip::Wrench<double>& w, const Forces& x, double delta) {
  const double len = grasp_lever_length(g);
  grip::Wrench<double> r = w;
  double f2 = 0;
  for (int i = 0; i < g.size(); ++i) {
    const grip::Contact<double> c = cast_contact<double>(g.contact(i));
    const grip::Vector3<double> xi = x.template segment<3>(3 * i).template cast<double>();
    r += grip::HardFinger::wrench(c, xi);
    f2 += 0.5 * c.weight * (xi - grip::HardFinger::target(c)).squaredNorm();
  }
  const double rl = norm_l(r, len);
  return 0.5 * rl * rl + delta * f2;
}

}  // namespace grip_test
