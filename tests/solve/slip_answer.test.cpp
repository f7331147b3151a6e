// The least-residual forces of a slip (include/grip/solve/detail/slip_answer.hpp) where the load
// pulls the object off every contact: zero forces, exactly, when the least-residual objective's
// gradient at zero lies in every contact's dual cone; checked against a hand derivation, the
// objective evaluated in double from the contacts' data, and random grasps.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

#include <grip/grip.hpp>

#include "solve/constrained_support.hpp"
#include "solve/slip_checks.hpp"
#include "support/equilibrium_norm.hpp"

using namespace grip;

namespace {

// The least-residual objective's gradient at x = 0 for contact i, in double:
// G_i^T T^2 w - delta w_i t_i, T = diag(1, 1, 1, 1/L, 1/L, 1/L) (hard fingers).
template <class GraspT>
Vector3<double> gradient_at_zero(const GraspT& g, int i, const Wrench<double>& w, double delta) {
  const double len = grip_test::grasp_lever_length(g);
  Wrench<double> t2w = w;
  t2w.tail<3>() /= len * len;
  const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
  return HardFinger::wrench_transpose(c, t2w) - delta * c.weight * HardFinger::target(c);
}

// A hard finger at a random point of the upper half of a 4 cm sphere (z above 0.2 of the
// radius), pressing toward the centre: mu in [0.3, 1], squeeze in [squeeze_min, 2] N, weight in
// [0.5, 1.5].
template <class S>
Contact<S> upper_sphere_contact(std::mt19937& rng, double squeeze_min) {
  std::uniform_real_distribution<double> u01(0, 1);
  const double z = 0.2 + 0.8 * u01(rng), phi = 6.283185307179586 * u01(rng), r = std::sqrt(1 - z * z);
  const Vector3<double> p = 0.04 * Vector3<double>(r * std::cos(phi), r * std::sin(phi), z);
  Contact<S> c;
  c.position = p.template cast<S>();
  c.normal = (-p.normalized()).template cast<S>();
  c.friction = S(0.3 + 0.7 * u01(rng));
  c.squeeze = S(squeeze_min + (2 - squeeze_min) * u01(rng));
  c.weight = S(0.5 + u01(rng));
  return c;
}

// A load of 0.1 N over 10^decades (log-uniform) in a random direction, with moments of a few
// centimetres times it.
Wrench<double> light_load(std::mt19937& rng, double decades) {
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  Wrench<double> w;
  for (int j = 0; j < 6; ++j) w(j) = sym(rng) * (j < 3 ? 1.0 : 0.04);
  return w * (0.1 * std::pow(10.0, -decades * u01(rng)) / w.head<3>().norm());
}

}  // namespace

TEST_CASE_TEMPLATE("least-residual forces: three fingers on top, a load pulling down (hand derivation)", S, double,
                   float) {
  // Three fingers press down (normal -z) on the top of an object; the load pulls it down too, so
  // no force in the cones balances it (the grasp slips). The gradient of
  // P(x) = |G x + w|_L^2 / 2 + delta F2(x) at x = 0 is, per contact, (0, 0, -F) - delta w_i s_i (0, 0, -1)
  // (the moments of a force along z through the contact do not enter the force rows), whose
  // normal component F - delta w_i s_i is >= 0, with no tangential part, iff F >= delta w_i s_i:
  // then zero forces minimise P. Below, the fingers press a little.
  Grasp<3, HardFinger, S> g;
  const double xy[3][2] = {{0.02, 0.0}, {-0.01, 0.017}, {-0.01, -0.017}};
  for (int i = 0; i < 3; ++i) {
    Contact<S> c;
    c.position = Vector3<S>(S(xy[i][0]), S(xy[i][1]), S(0.03));
    c.normal = Vector3<S>(0, 0, -1);
    c.friction = S(0.5);
    c.squeeze = S(1 + i);
    c.weight = S(1);
    REQUIRE(g.set(i, c) == Status::Ok);
  }
  const double delta = grip_test::least_residual_delta(g);
  const double edge = delta * 3.0;  // the largest delta w_i s_i
  for (const double factor : {4.0, 1e3, 0.25}) {
    CAPTURE(factor);
    const double f = factor * edge;
    Wrench<S> w = Wrench<S>::Zero();
    w(2) = S(-f);
    const auto sol = solve_constrained(g, w);
    REQUIRE(sol.status == Status::Infeasible);
    grip_test::check_certificate(g, w, sol.certificate);
    const Wrench<double> wd = w.template cast<double>();
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(9);
    const double p0 = grip_test::least_residual_objective(g, wd, zero, delta);
    if (factor > 1) {
      CHECK(sol.forces.isZero(0));  // exactly: the closed form, not an iterate
      CHECK(sol.residual == doctest::Approx(f).epsilon(1e-6));
    } else {
      // Pressing lowers P: the answer is not zero, and its P lies below P(0) (in float, to within
      // the interior-point method's tolerance of P: the decrease is below float's resolution).
      CHECK(sol.forces.template cast<double>().norm() > 0.1 * f);
      const double slack = std::is_same<S, float>::value ? double(ScalarTraits<S>::interior_tolerance) * p0 : 0.0;
      CHECK(grip_test::least_residual_objective(g, wd, sol.forces, delta) < p0 + slack);
    }
  }
}

TEST_CASE_TEMPLATE("least-residual forces: zero exactly where the gradient at zero lies in the dual cones", S, double,
                   float) {
  // Random grasps of four hard fingers on the upper half of a 4 cm sphere and loads of random
  // direction and size: of those that slip, the answer is exactly zero iff every contact's
  // gradient at zero (computed here in double) lies in its dual cone, away from the cone's edge by
  // more than the rounding; where it is zero, no small force in the cones lowers P.
  std::mt19937 rng(907);
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  int slips = 0, zero = 0, pressed = 0;
  for (int k = 0; k < 800; ++k) {
    Grasp<4, HardFinger, S> g;
    for (int i = 0; i < 4; ++i) REQUIRE(g.set(i, upper_sphere_contact<S>(rng, 0.0)) == Status::Ok);
    Wrench<double> wd;
    for (int j = 0; j < 6; ++j) wd(j) = sym(rng) * (j < 3 ? 1.0 : 0.04);
    wd(2) -= 1.5;  // mostly downward: away from fingers that press down and in
    wd *= std::pow(10.0, -6 + 7 * u01(rng));
    const Wrench<S> w = wd.template cast<S>();
    const auto sol = solve_constrained(g, w);
    if (sol.status != Status::Infeasible) continue;
    ++slips;
    const double delta = grip_test::least_residual_delta(g);
    double least = 1e300, scale = 0;
    for (int i = 0; i < 4; ++i) {
      const Vector3<double> v = gradient_at_zero(g, i, wd, delta);
      least = std::min(least, grip_test::dual_margin(grip_test::cast_contact<double>(g.contact(i)), v));
      scale = std::max(scale, v.norm());
    }
    const double rounding = 1e3 * double(std::numeric_limits<S>::epsilon()) * scale;
    if (std::abs(least) <= rounding) continue;  // at the edge: either answer is within rounding
    CAPTURE(k);
    CHECK(sol.forces.isZero(0) == (least > 0));
    if (least > 0) {
      ++zero;
      const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(12);
      const double p0 = grip_test::least_residual_objective(g, wd, x0, delta);
      for (int trial = 0; trial < 8; ++trial) {  // small forces inside the cones
        Eigen::VectorXd x = x0;
        const int i = trial % 4;
        const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
        const Vector3<double> t = (Vector3<double>(sym(rng), sym(rng), sym(rng)).cross(c.normal)).normalized();
        x.segment<3>(3 * i) = 1e-3 * wd.norm() * (c.normal + c.friction * u01(rng) * t);
        CHECK(grip_test::least_residual_objective(g, wd, x, delta) >= p0);
      }
    } else {
      ++pressed;
    }
  }
  MESSAGE(slips, " slips: ", zero, " with zero forces, ", pressed, " pressed");
  CHECK(zero >= 20);
  CHECK(pressed >= 20);
}

TEST_CASE_TEMPLATE("least-residual forces under loads far below the squeezing forces: no move in the cones lowers P", S,
                   double, float) {
  // Three hard fingers on the upper half of a 4 cm sphere, squeezing with up to 2 N, under loads
  // 10 to 10^5 times smaller (float: 10 to 100), so that the least-residual problem's solution
  // lies far inside its normalised units (the interior-point method starts at the load's scale,
  // slip_answer.hpp). P is convex, so where the answer is optimal to within the method's
  // tolerance (the gap relative to P), no point of the cones lies below P(answer) by more than
  // that: checked at small moves of each contact's force that stay in its cone (scaled, pushed
  // inward, and blended with an interior force), P evaluated in double from the contacts' data.
  std::mt19937 rng(911);
  std::uniform_real_distribution<double> u01(0, 1), sym(-1, 1);
  const double decades = std::is_same<S, float>::value ? 1.0 : 4.0;
  const double tol = double(ScalarTraits<S>::interior_tolerance);
  int probed = 0;
  for (int k = 0; k < 600; ++k) {
    Grasp<3, HardFinger, S> g;
    for (int i = 0; i < 3; ++i) REQUIRE(g.set(i, upper_sphere_contact<S>(rng, 0.2)) == Status::Ok);
    const Wrench<double> wd = light_load(rng, decades);
    const Wrench<S> w = wd.template cast<S>();
    const auto sol = solve_constrained(g, w);
    if (sol.status != Status::Infeasible || sol.forces.isZero(0)) continue;
    CAPTURE(k);
    const double delta = grip_test::least_residual_delta(g);
    const Eigen::VectorXd x = sol.forces.template cast<double>();
    const double px = grip_test::least_residual_objective(g, wd, x, delta);
    const double slack = 2 * tol * px + 1e-12 * px;
    const double scale = x.norm() + wd.head<3>().norm();
    for (int i = 0; i < 3; ++i) {
      const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
      const Vector3<double> xi = x.segment<3>(3 * i);
      // In the cone to the method's tolerance.
      const double xn = xi.dot(c.normal);
      CHECK((xi - xn * c.normal).norm() <= c.friction * xn + 10 * tol * scale);
      for (const double eta : {1e-2, 1e-4}) {
        const Vector3<double> t = Vector3<double>(sym(rng), sym(rng), sym(rng)).cross(c.normal).normalized();
        const Vector3<double> inner = scale * (c.normal + 0.9 * c.friction * u01(rng) * t);
        for (const Vector3<double>& moved :
             {Vector3<double>((1 + eta) * xi), Vector3<double>((1 - eta) * xi), Vector3<double>(xi + eta * inner),
              Vector3<double>((1 - eta) * xi + eta * inner)}) {
          Eigen::VectorXd y = x;
          y.segment<3>(3 * i) = moved;
          CHECK(grip_test::least_residual_objective(g, wd, y, delta) >= px - slack);
        }
      }
    }
    ++probed;
  }
  MESSAGE(probed, " slips with forces probed");
  CHECK(probed >= 50);
}

TEST_CASE_TEMPLATE("least-residual forces under light loads: a device's bound far above them changes nothing", S,
                   double, float) {
  // Three hard fingers on the upper half of a 4 cm sphere, squeezing with up to 2 N, under loads
  // 10 to 10^5 times smaller (float: 10 to 100), solved with every normal force bounded by 20 N
  // (a haptic device's channel) and without bounds. No force of the least-residual answer comes
  // near the bound, so both solve the same problem: both slip, the bounded forces keep their
  // bound, and their objectives P (evaluated in double from the contacts' data) agree to the
  // interior-point method's tolerance.
  std::mt19937 rng(1207);
  const double decades = std::is_same<S, float>::value ? 1.0 : 4.0;
  const double tol = double(ScalarTraits<S>::interior_tolerance);
  int compared = 0;
  for (int k = 0; k < 400; ++k) {
    Grasp<3, HardFinger, S> free_grasp, bounded;
    for (int i = 0; i < 3; ++i) {
      Contact<S> c = upper_sphere_contact<S>(rng, 0.2);
      REQUIRE(free_grasp.set(i, c) == Status::Ok);
      c.max_normal_force = S(20);
      REQUIRE(bounded.set(i, c) == Status::Ok);
    }
    const Wrench<double> wd = light_load(rng, decades);
    const Wrench<S> w = wd.template cast<S>();
    const auto a = solve_constrained(free_grasp, w);
    if (a.status != Status::Infeasible || a.forces.isZero(0)) continue;
    CAPTURE(k);
    const auto b = solve_constrained(bounded, w);
    REQUIRE(b.status == Status::Infeasible);
    const double delta = grip_test::least_residual_delta(free_grasp);
    const double pa =
        grip_test::least_residual_objective(free_grasp, wd, a.forces.template cast<double>().eval(), delta);
    const double pb = grip_test::least_residual_objective(bounded, wd, b.forces.template cast<double>().eval(), delta);
    CHECK(std::abs(pa - pb) <= 4 * tol * std::max(pa, pb) + 1e-12 * pa);
    for (int i = 0; i < 3; ++i)
      CHECK(double(b.forces.template segment<3>(3 * i).dot(bounded.contact(i).normal)) <= 20.0);
    ++compared;
  }
  MESSAGE(compared, " slips compared");
  CHECK(compared >= 50);
}
