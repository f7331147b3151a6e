// Invariances: the solvers, the monitor and the analysis answer a transformed grasp with the
// transformed answer, as the physics says, at seeded random grasps of every model:
// - units: lengths x L and forces x F (L, F in {1e-3, 1e3}): forces x F, moments x F L,
//   margins x F;
// - a rotation R of the whole grasp: contact forces R f (the soft finger's moment about its
//   normal and a frictionless point's magnitude unchanged), margins unchanged;
// - the multipliers lambda (W (x - t) = G^T lambda): force part x F c, moment part x F c / L,
//   rotated;
// - a permutation of the contacts: the answer permuted;
// - every weight x c: the forces unchanged, the multipliers x c.
// F2 weighs a soft finger's moment (N m) against its force (N), so its optimum depends on the
// unit of length: for soft fingers the length scale is left out (L = 1).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <grip/analysis/epsilon.hpp>
#include <grip/analysis/force_closure.hpp>
#include <grip/monitor/stability_monitor.hpp>
#include <grip/solve/solve_constrained.hpp>
#include <grip/solve/solve_kkt.hpp>
#include <grip/solve/solve_range_space.hpp>

#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/test_scale.hpp"
#include "support/tolerance.hpp"

namespace invariance_test {

using namespace grip;

/// A change of units, frame, order and weights.
struct Change {
  double length{1}, force{1}, weight{1};
  Matrix3<double> rotation{Matrix3<double>::Identity()};
  std::vector<int> order;  // new contact j is old contact order[j]
};

template <class GraspT>
GraspT apply(const GraspT& g, const Change& ch) {
  using S = typename GraspT::ScalarType;
  GraspT out;
  for (int j = 0; j < g.size(); ++j) {
    Contact<S> c = g.contact(ch.order[static_cast<std::size_t>(j)]);
    c.position = (ch.rotation * c.position.template cast<double>() * ch.length).template cast<S>();
    c.normal = (ch.rotation * c.normal.template cast<double>()).normalized().template cast<S>();
    c.torsional_friction = S(double(c.torsional_friction) * ch.length);
    c.squeeze = S(double(c.squeeze) * ch.force);
    c.weight = S(double(c.weight) * ch.weight);
    if constexpr (GraspT::fixed_size == Dynamic)
      REQUIRE(out.add(c) == Status::Ok);
    else
      REQUIRE(out.set(j, c) == Status::Ok);
  }
  return out;
}

template <class S>
Wrench<S> apply(const Wrench<S>& w, const Change& ch) {
  Wrench<double> o;
  o.head<3>() = ch.rotation * w.template head<3>().template cast<double>() * ch.force;
  o.tail<3>() = ch.rotation * w.template tail<3>().template cast<double>() * (ch.force * ch.length);
  return o.cast<S>();
}

/// The forces of g (old order) as the changed grasp's solution should give them, in double.
template <class GraspT>
Eigen::VectorXd apply_forces(const typename GraspT::ForceVector& x, const Change& ch) {
  constexpr int d = GraspT::dim;
  const int n = static_cast<int>(x.size()) / d;
  Eigen::VectorXd out(x.size());
  for (int j = 0; j < n; ++j) {
    const Eigen::VectorXd xi = x.template segment<d>(ch.order[static_cast<std::size_t>(j)] * d).template cast<double>();
    Eigen::VectorXd yi = xi * ch.force;
    if constexpr (d >= 3) yi.head<3>() = ch.rotation * yi.head<3>();
    if constexpr (d == 4) yi(3) *= ch.length;  // a moment
    out.segment(j * d, d) = yi;
  }
  return out;
}

/// Random changes: each of units, rotation, permutation, weights alone, then all together.
std::vector<Change> changes(std::mt19937& rng, int n, bool lengths) {
  std::vector<Change> out;
  const grip_test::Normal n01(0, 1);
  std::vector<int> identity(static_cast<std::size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  for (const double s : {1e-3, 1e3}) {
    Change c;
    c.order = identity;
    c.force = s;
    c.length = lengths ? 1 / s : 1.0;  // forces up, lengths down, and the other way
    out.push_back(c);
    if (lengths) {
      c.force = 1.0;
      c.length = s;
      out.push_back(c);
    }
  }
  Change r;
  r.order = identity;
  const double qw = n01(rng), qx = n01(rng), qy = n01(rng), qz = n01(rng);
  r.rotation = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
  out.push_back(r);
  Change p;
  p.order = identity;
  for (int i = n - 1; i > 0; --i)  // Fisher-Yates (std::shuffle's draws differ between libraries)
    std::swap(p.order[static_cast<std::size_t>(i)],
              p.order[static_cast<std::size_t>(grip_test::UniformInt(0, i)(rng))]);
  out.push_back(p);
  Change w;
  w.order = identity;
  w.weight = 7.5;
  out.push_back(w);
  Change all = r;
  all.order = p.order;
  all.weight = 0.25;
  all.force = 1e3;
  all.length = lengths ? 1e-3 : 1.0;
  out.push_back(all);
  return out;
}

/// |a - b| <= tol (1 + |b|), reported.
void check_close(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double tol) {
  CAPTURE(a.transpose());
  CAPTURE(b.transpose());
  CHECK((a - b).norm() <= tol * (1 + b.norm()));
}

template <class GraspT>
void solvers_and_monitor(std::mt19937& rng, int n, bool lengths) {
  using S = typename GraspT::ScalarType;
  int checked = 0, constrained = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, n, true, 0.3);
    const Wrench<S> w = grip_test::random_wrench<S>(rng);
    const auto rs = solve_range_space(g, w);
    const auto kkt = solve_kkt(g, w);
    const auto con = solve_constrained(g, w);
    REQUIRE(rs.status == Status::Ok);
    REQUIRE(kkt.status == Status::Ok);
    const StabilityMonitor<GraspT> monitor;
    const auto state = monitor.evaluate(g, rs.forces);
    REQUIRE(state.ok());
    for (const Change& ch : changes(rng, g.size(), lengths)) {
      CAPTURE(ch.length);
      CAPTURE(ch.force);
      CAPTURE(ch.weight);
      const GraspT h = apply(g, ch);
      const Wrench<S> v = apply(w, ch);
      const auto rs2 = solve_range_space(h, v);
      const auto kkt2 = solve_kkt(h, v);
      REQUIRE(rs2.status == Status::Ok);
      REQUIRE(kkt2.status == Status::Ok);
      const Eigen::VectorXd expect = apply_forces<GraspT>(rs.forces, ch);
      const double fs = ch.force;
      // Tolerances from round-off (support/tolerance.hpp), relative to 1 + |forces|: each solve's
      // forces carry about u kappa of error, kappa the larger condition of the two grasps (a
      // change of units changes it); k = 8 for the forces and 16 for the multipliers (which
      // add one more solve), observed at most 1.2 and 2.0 in both scalar types.
      const double kappa = std::max(grip_test::grasp_condition(g), grip_test::grasp_condition(h));
      const double tol = grip_test::roundoff<S>(8, kappa, 1);
      check_close(rs2.forces.template cast<double>() / fs, expect / fs, tol);
      check_close(kkt2.forces.template cast<double>() / fs, apply_forces<GraspT>(kkt.forces, ch) / fs, tol);
      // Multipliers: W (x - t) = G^T lambda, and G^T lambda = (lambda_f + lambda_m x r_i, ...),
      // so lambda_f scales as x c (a force times the weight factor), lambda_m as x c / L; both
      // rotate.
      const double sf = fs * ch.weight, sm = fs * ch.weight / ch.length;
      Wrench<double> lambda, got;
      lambda.head<3>() = ch.rotation * rs.multipliers.template head<3>().template cast<double>();
      lambda.tail<3>() = ch.rotation * rs.multipliers.template tail<3>().template cast<double>();
      got.head<3>() = rs2.multipliers.template head<3>().template cast<double>() / sf;
      got.tail<3>() = rs2.multipliers.template tail<3>().template cast<double>() / sm;
      check_close(got, lambda, grip_test::roundoff<S>(16, kappa, 1));
      // The constrained optimum, when there is one, in both types and every unit of length:
      // its tests measure moments per lever arm (the equilibrium norm |.|_L), so a grasp 1000
      // times smaller stops where the original does.
      if (con.status == Status::Ok) {
        const auto con2 = solve_constrained(h, v);
        CHECK(con2.status == Status::Ok);
        if (con2.status == Status::Ok) {
          // Not round-off: both answers stop at a tolerance on the optimality conditions (Newton's
          // constrained_tolerance when refined, the interior-point method's interior_tolerance
          // otherwise), which leaves the forces within about its square root.
          const double stop = con.refined && con2.refined ? double(ScalarTraits<S>::constrained_tolerance)
                                                          : double(ScalarTraits<S>::interior_tolerance);
          check_close(con2.forces.template cast<double>() / fs, apply_forces<GraspT>(con.forces, ch) / fs,
                      std::sqrt(stop));
          ++constrained;
        }
      }
      // The monitor on the transformed forces: margins x F, modes the same where a margin is
      // clear of zero; contact j is old contact order[j]. The forces are the same forces
      // transformed and rounded once to S, so no condition enters: the margins' own arithmetic
      // (a rotation, dot products, norms, a square root) gives k = 128 units of u times the
      // force's size, observed at most 27; modes are compared beyond 4 times that.
      const double margin_tol = grip_test::roundoff<S>(128, 1, 1);
      const typename GraspT::ForceVector y = expect.cast<S>();
      const auto state2 = monitor.evaluate(h, y);
      REQUIRE(state2.ok());
      for (int j = 0; j < h.size(); ++j) {
        const auto& a = state.contact(ch.order[static_cast<std::size_t>(j)]);
        const auto& b = state2.contact(j);
        const double scale = 1 + std::abs(double(a.normal_force)) + double(a.tangential_force.norm());
        CHECK(std::abs(double(b.margin) / fs - double(a.margin)) <= margin_tol * scale);
        if (std::abs(double(a.margin)) > 4 * margin_tol * scale) CHECK(b.mode == a.mode);
      }
      ++checked;
    }
  }
  CHECK(checked >= 12 * 6);
  CHECK(constrained >= 12);  // the cone-constrained optimum compared in enough cases
}

TEST_CASE_TEMPLATE("invariance: solvers and monitor, hard fingers and frictionless points", S, double, float) {
  std::mt19937 rng(2024);
  solvers_and_monitor<Grasp<Dynamic, HardFinger, S, 8>>(rng, 5, true);
  solvers_and_monitor<Grasp<4, HardFinger, S>>(rng, 4, true);
  solvers_and_monitor<Grasp<Dynamic, FrictionlessPoint, S, 12>>(rng, 9, true);
}

TEST_CASE_TEMPLATE("invariance: solvers and monitor, soft fingers (forces scaled, lengths not)", S, double, float) {
  std::mt19937 rng(2025);
  solvers_and_monitor<Grasp<Dynamic, SoftFinger, S, 6>>(rng, 4, false);
}

TEST_CASE_TEMPLATE("invariance: force closure and epsilon", S, double, float) {
  // Closure is a property of the geometry: the same under every change. Epsilon (L1, over
  // 6-sided pyramids) with the torque scale in the new unit of length is the same number
  // under units, permutation and weights; not under rotation, which turns the grasp but not
  // the pyramids' facets about their normals (their tangent basis comes from fixed axes).
  std::mt19937 rng(2026);
  using GraspT = Grasp<Dynamic, HardFinger, S, 8>;
  auto ws = std::make_unique<EpsilonWorkspace<S>>();
  const double tol = std::is_same<S, float>::value ? 5e-3 : 1e-7;
  int closures = 0, epsilons = 0;
  const int trials = grip_test::scaled(10, 3);
  for (int trial = 0; trial < trials; ++trial) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, 5, true, 0.3);
    const auto fc = force_closure(g);
    REQUIRE(fc.status == Status::Ok);
    const double rho = 0.05;
    const auto eps = ferrari_canny_epsilon<6>(g, EpsilonNorm::L1, S(rho), *ws);
    REQUIRE(eps.status == Status::Ok);
    closures += fc.closure ? 1 : 0;
    for (const Change& ch : changes(rng, g.size(), true)) {
      CAPTURE(ch.length);
      CAPTURE(ch.force);
      const GraspT h = apply(g, ch);
      const auto fc2 = force_closure(h);
      REQUIRE(fc2.status == Status::Ok);
      // (margins are decided well clear of the threshold here, so the verdicts must agree)
      if (std::abs(double(fc.margin)) > 100 * tol) CHECK(fc2.closure == fc.closure);
      if (!ch.rotation.isIdentity(0)) continue;
      const auto eps2 = ferrari_canny_epsilon<6>(h, EpsilonNorm::L1, S(rho * ch.length), *ws);
      REQUIRE(eps2.status == Status::Ok);
      CHECK(double(eps2.epsilon) == doctest::Approx(double(eps.epsilon)).scale(1).epsilon(tol));
      ++epsilons;
    }
  }
  CHECK(closures > grip_test::scaled_bound(2, trials, 10));  // at least 3 in 10
  CHECK(epsilons >= 4 * trials);
}

}  // namespace invariance_test
