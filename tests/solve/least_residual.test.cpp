// The least-residual problem of solve_constrained (solve/detail/least_residual.hpp) on a
// stand-in pass whose dual has a ridge: the stopping rule for steps below the multipliers'
// resolution, which real grasps meet only rarely and in a build-dependent way.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/solve/solve_constrained.hpp>

#include "support/fixtures.hpp"

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

namespace {

// solve_constrained's own passes over a grasp, recording how many passes repeat the previous
// pass's input (to a few of its last places): such a pass gives the same forces and sums
// again and tells the iteration nothing.
template <class GraspT>
struct RecordingPasses {
  using Inner = detail::ConstrainedPasses<GraspT>;
  using Scalar = typename Inner::Scalar;
  using Forces = typename Inner::Forces;
  explicit RecordingPasses(const GraspT& grasp) : inner(grasp) {}
  Inner inner;
  mutable Wrench<Scalar> last{Wrench<Scalar>::Constant(std::numeric_limits<Scalar>::quiet_NaN())};
  mutable int repeats{0};
  Forces make_forces() const { return inner.make_forces(); }
  detail::ConstrainedPass<Scalar> pass(const Wrench<Scalar>& w_ext, const Wrench<Scalar>& input, Forces& x,
                                       Matrix6<Scalar>& hessian) const {
    if ((input - last).norm() <= 64 * std::numeric_limits<Scalar>::epsilon() * input.norm()) ++repeats;
    last = input;
    return inner.pass(w_ext, input, x, hessian);
  }
  Scalar first_break(const Wrench<Scalar>& input, const Wrench<Scalar>& input_dir) const {
    return inner.first_break(input, input_dir);
  }
};

}  // namespace

TEST_CASE("least_residual: a stage solved to its tolerance hands its pass to the next stage") {
  // Three hard fingers near the top of a 4 cm sphere (mu 0.5, squeeze 0.3 N), pushing down
  // within 27 degrees of the vertical, under a weight of 20 N: a slip.
  // The continuation takes delta from delta / least_residual_weight down 100-fold per stage and
  // scales l with it, so the pass's input -T l / delta, hence the forces and every sum, stay
  // those of the stage just solved: a pass there would repeat the last one (one per stage, about
  // six per slip, before this was seen).
  using GraspT = Grasp<3, HardFinger, double>;
  GraspT g;
  const double theta[3] = {0.3, 0.4, 0.5}, phi[3] = {0.0, 2.1, 4.2};
  for (int i = 0; i < 3; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<double>(theta[i], phi[i], 0.04, 0.5, 0.3)) == Status::Ok);
  Wrench<double> w;
  w << 0, 0, -20, 0, 0, 0;
  REQUIRE(solve_constrained(g, w).status == Status::Infeasible);
  const RecordingPasses<GraspT> passes(g);
  const ConstrainedSettings<double> settings;
  const auto norm = detail::EquilibriumNorm<double>::of(g);
  const double delta = settings.least_residual_weight;  // seven stages: delta 1, 1e-2, ..., 1e-12
  detail::PassBudget budget{std::numeric_limits<int>::max()};
  auto x = passes.make_forces(), xt = passes.make_forces();
  Matrix6<double> trial_h;
  Wrench<double> y;
  double f2 = 0;
  detail::least_residual(passes, w, norm, norm(w) - w.norm(), delta, settings, settings.max_iterations, budget, x,
                         y, f2, xt, trial_h);
  CHECK(passes.repeats == 0);
  // Still the least residual: |y| is |G x + w|_L at the solve's end (to delta's share).
  Eigen::Matrix<double, 9, 1> f;
  passes.inner.store(x, f);
  Wrench<double> r = w;
  for (int i = 0; i < 3; ++i) r += HardFinger::wrench(g.contact(i), Vector3<double>(f.segment<3>(3 * i)));
  CHECK(y.norm() > 1.0);
  CHECK(std::abs(norm(r) - y.norm()) <= 1e-6 * y.norm());
}
