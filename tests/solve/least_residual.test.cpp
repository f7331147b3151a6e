// The least-residual problem of solve_constrained (solve/detail/least_residual.hpp) on a
// stand-in pass whose dual has a ridge: the stopping rule for steps below the multipliers'
// resolution, which real grasps meet only rarely and in a build-dependent way.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/solve/solve_constrained.hpp>

using namespace grip;

namespace {

// A pass engine for least_residual whose dual phi(l) = -|l|^2/2 + l.r + delta f2 has a steep
// ridge: the residual r is the constant r0 = l* + e_0 and F2 = lift - steep / delta *
// max(0, l_0 - l*_0), so phi rises along Newton's direction (r0 - l: the reported Hessian
// is 0) up to the plane l_0 = l*_0 and falls by `steep` per unit beyond it. With |l*| = 1e7
// and a lift of 3e20, |phi| is about 3e20, and the Armijo test's round-off slack (16 eps of
// it, about 2e6) lets a step of about 1.5e-8 across the plane pass: below l's resolution,
// 16 eps |l| = 3.5e-8, yet a change of l's components. One stage: the caller sets
// least_residual_weight 1, so that delta is the delta given and l = -delta * (the pass's input).
struct RidgePasses {
  using Scalar = double;
  using Forces = Eigen::Matrix<double, 3, 1>;
  double delta{1};
  double steep{1e14};
  double lift{3e20};
  Wrench<double> l_star{(Wrench<double>() << 1e7, 1e-3, 0, 0, 0, 0).finished()};
  Forces make_forces() const { return Forces::Zero(); }
  detail::ConstrainedPass<double> pass(const Wrench<double>&, const Wrench<double>& input, Forces& x,
                               Matrix6<double>& hessian) const {
    const Wrench<double> l = -delta * input;
    x.setZero();
    hessian.setZero();
    detail::ConstrainedPass<double> p;
    p.residual = l_star + Wrench<double>::Unit(0);
    p.f2 = lift - steep / delta * std::max(0.0, l(0) - l_star(0));
    p.scale = 1;
    p.dual = 0;
    return p;
  }
  // Where l + alpha d reaches the plane, if in (0, 1); else 1.
  double first_break(const Wrench<double>& input, const Wrench<double>& input_dir) const {
    const double l0 = -delta * input(0), d0 = -delta * input_dir(0);
    const double alpha = d0 > 0 ? (l_star(0) - l0) / d0 : 1.0;
    return alpha > 64 * std::numeric_limits<double>::epsilon() && alpha < 1 ? alpha : 1.0;
  }
};

}  // namespace

TEST_CASE("least_residual: a step below the multipliers' resolution ends the stage") {
  const RidgePasses passes;
  ConstrainedSettings<double> settings;
  settings.least_residual_weight = 1;  // one stage, at delta
  const detail::EquilibriumNorm<double> norm;  // L = 1: T = I
  detail::PassBudget budget{std::numeric_limits<int>::max()};
  RidgePasses::Forces x, xt;
  Matrix6<double> trial_h;
  Wrench<double> l;
  double f2 = 0;
  const int iterations = detail::least_residual(passes, Wrench<double>::Zero(), norm, 0.0, passes.delta, settings,
                                                settings.max_iterations, budget, x, l, f2, xt, trial_h);
  // It halves its way to the plane (22 iterations of 2 to 3 passes), lands on it by the kink
  // trial, and stops at the first step that only rounding would take (24 iterations and 74
  // passes in all). Taking that step again and again instead runs to the iteration bound: 60
  // iterations and about 1 000 passes.
  CHECK(iterations < settings.max_iterations);
  CHECK(budget.used < 150);
  // It ends on the ridge: on the plane to within a few of l's last places.
  CHECK(std::abs(l(0) - passes.l_star(0)) <= 1e-6);
  CHECK(std::abs(l(1) - passes.l_star(1)) <= 1e-9 * std::abs(passes.l_star(1)) + 1e-9);
}
