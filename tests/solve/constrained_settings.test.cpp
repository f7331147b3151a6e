// ConstrainedSettings::max_iterations and newton_passes, the bounds of solve_constrained: never
// exceeded (iterations <= max_iterations, passes <= 2 newton_passes + 3 max_iterations + 2), the
// answer unchanged when the solve fits in them, and otherwise IterationLimit with forces in their
// cones (residual their own) or a certified Infeasible; with Newton on, a run cut short may still
// end Ok through the refinement, at its own tolerance. Instances: random grasps of every model
// with loads from 0.5 to 200 N, many of them slipping.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include <grip/solve/solve_constrained.hpp>

#include "solve/constrained_support.hpp"
#include "support/equilibrium_norm.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/test_scale.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace constrained_settings_test {

// A load of 0.5 to 200 N (log-uniform) in a random direction, with moments of a few cm times it.
template <class S>
Wrench<S> random_load(std::mt19937& rng) {
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  const double size = 0.5 * std::pow(400.0, grip_test::canonical(rng));
  return w * S(size / std::max(double(w.template head<3>().norm()), 1e-3));
}

// G x + w in double from the forces alone, and its round-off scale |w| + sum (1 + |r_i|) |x_i|.
template <class GraspT>
Wrench<double> residual_vector_in_double(const GraspT& g, const typename GraspT::ForceVector& x,
                                         const Wrench<typename GraspT::ScalarType>& w, double& scale) {
  using M = typename GraspT::ModelType;
  constexpr int d = M::dim;
  Wrench<double> r = w.template cast<double>();
  scale = r.norm();
  for (int i = 0; i < g.size(); ++i) {
    const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
    const Eigen::Matrix<double, d, 1> xi = x.template segment<d>(i * d).template cast<double>();
    r += M::wrench(c, xi);
    scale += (1.0 + c.position.norm()) * xi.norm();
  }
  return r;
}

/// |G x + w|, in double.
template <class GraspT>
double residual_in_double(const GraspT& g, const typename GraspT::ForceVector& x,
                          const Wrench<typename GraspT::ScalarType>& w, double& scale) {
  return residual_vector_in_double(g, x, w, scale).norm();
}

// What an answer cut by the bound promises: finite, forces in their cones (the interior-point
// iterate's, strictly inside but for the rounding of the map back to forces, 16 u |x_i|), and the
// residual reported is that of the forces (summed in S: 8 n u times the scale).
template <class GraspT>
void check_cut(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w, const ConstrainedSolution<GraspT>& cut) {
  using M = typename GraspT::ModelType;
  using S = typename GraspT::ScalarType;
  constexpr int d = M::dim;
  REQUIRE(cut.forces.allFinite());
  REQUIRE(cut.multipliers.allFinite());
  for (int i = 0; i < g.size(); ++i) {
    const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
    const Eigen::Matrix<double, d, 1> xi = cut.forces.template segment<d>(i * d).template cast<double>();
    CHECK(grip_test::cone_violation<M>(c, xi) <= grip_test::roundoff<S>(16, 1, 1e-30 + xi.norm()));
  }
  double scale = 0;
  const double r = residual_in_double(g, cut.forces, w, scale);
  CHECK(std::abs(double(cut.residual) - r) <= grip_test::roundoff<S>(8.0 * g.size(), 1, scale));
}

/// The bound on passes (solve_constrained.hpp): Newton's warm start and refinement, three per
/// interior-point iteration and one per run.
template <class S>
int pass_bound(const ConstrainedSettings<S>& st) {
  return 2 * st.newton_passes + 3 * st.max_iterations + 2;
}

template <class Model, class S, int N>
void deadline_on_random_instances(std::uint32_t seed, int full_count) {
  using GraspT = Grasp<N, Model, S>;
  const int count = grip_test::scaled(full_count, 30);  // GRIP_TEST_SCALE (sanitizers: a quarter)
  std::mt19937 rng(seed);
  const int deadlines[] = {1, 2, 3, 5, 8, 13};
  int cut_count = 0, infeasible_count = 0, unchanged_count = 0;
  for (int k = 0; k < count; ++k) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, N, true, 0.5);
    const Wrench<S> w = random_load<S>(rng);
    ConstrainedSettings<S> defaults;
    defaults.newton_passes = 0;  // the interior-point method's bound alone (Newton's: below)
    const auto full = solve_constrained(g, w, defaults);
    REQUIRE(full.status != Status::InvalidInput);
    CHECK(full.status != Status::IterationLimit);  // the default bound suffices
    CHECK(full.iterations <= defaults.max_iterations);
    CHECK(full.passes <= pass_bound(defaults));
    if (full.fast_path) {
      CHECK(full.passes == 0);
      continue;
    }
    for (int p : deadlines) {
      ConstrainedSettings<S> st = defaults;
      st.max_iterations = p;
      const auto cut = solve_constrained(g, w, st);
      // The bound is never exceeded, and a solve that fits in it is untouched.
      CHECK(cut.iterations <= p);
      CHECK(cut.passes <= pass_bound(st));
      if (full.iterations < p) {
        CHECK(cut.status == full.status);
        CHECK(cut.passes == full.passes);
        CHECK(cut.forces == full.forces);
        CHECK(cut.multipliers == full.multipliers);
        ++unchanged_count;
        continue;
      }
      // Exactly p: the interior-point method's first run keeps one iteration for the
      // least-residual problem, so a solve that needs all p may still fit, or be cut.
      if (full.iterations == p) continue;
      // Cut short: IterationLimit with forces in the cones, or Infeasible with a certificate
      // (the least-residual problem cut short).
      check_cut(g, w, cut);
      if (cut.status == Status::Infeasible) {
        ++infeasible_count;
        const Wrench<double> y = cut.certificate.template cast<double>();
        CHECK(grip_test::dual_norm_l(y, grip_test::grasp_lever_length(g)) == doctest::Approx(1.0).epsilon(1e-4));
        CHECK(y.dot(w.template cast<double>()) > 0.0);
        continue;
      }
      REQUIRE(cut.status == Status::IterationLimit);
      ++cut_count;
    }
  }
  // Coverage: each branch was reached many times (a misread bound would leave one empty).
  CHECK(cut_count >= count / 8);
  CHECK(unchanged_count >= count / 4);
  MESSAGE("cut " << cut_count << ", infeasible " << infeasible_count << ", unchanged " << unchanged_count);
}

}  // namespace constrained_settings_test

TEST_CASE_TEMPLATE("max_iterations: the bound is honoured on random grasps (hard fingers)", S, double, float) {
  constrained_settings_test::deadline_on_random_instances<HardFinger, S, 3>(101, 200);
  constrained_settings_test::deadline_on_random_instances<HardFinger, S, 5>(102, 200);
  constrained_settings_test::deadline_on_random_instances<HardFinger, S, 20>(103, 60);
}

TEST_CASE_TEMPLATE("max_iterations: the bound is honoured on random grasps (soft, frictionless)", S, double, float) {
  constrained_settings_test::deadline_on_random_instances<SoftFinger, S, 5>(104, 150);
  constrained_settings_test::deadline_on_random_instances<FrictionlessPoint, S, 8>(105, 150);
}

TEST_CASE_TEMPLATE("max_iterations: a run cut short is refined by Newton from its last iterate", S, double, float) {
  // Hard fingers whose default solve needs more interior-point iterations than the bound p
  // allows and holds: the cut run never reaches the handover, yet Newton's refinement from its
  // last iterate may still converge. An Ok answer must then be the optimum: its residual, in
  // double and in the equilibrium norm, within the tolerance it claims (refined: `tolerance`;
  // not refined: ScalarTraits::interior_tolerance), and its F2 that of the uncut solve.
  using GraspT = Grasp<5, HardFinger, S>;
  std::mt19937 rng(108);
  const int count = grip_test::scaled(300, 60);
  int ok_count = 0, cut_count = 0;
  for (int k = 0; k < count; ++k) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, 5, true, 0.5);
    const Wrench<S> w = constrained_settings_test::random_load<S>(rng);
    const auto full = solve_constrained(g, w);
    if (full.status != Status::Ok || full.iterations < 4) continue;
    for (int p : {2, 3}) {
      ConstrainedSettings<S> st;
      st.max_iterations = p;
      const auto cut = solve_constrained(g, w, st);
      ++cut_count;
      CHECK(cut.iterations <= p);
      CHECK(cut.passes <= constrained_settings_test::pass_bound(st));
      constrained_settings_test::check_cut(g, w, cut);
      if (cut.status != Status::Ok) continue;
      ++ok_count;
      const double l = grip_test::grasp_lever_length(g);
      double squeeze = 0;
      for (int i = 0; i < g.size(); ++i) squeeze = std::max(squeeze, double(g.contact(i).squeeze));
      double sum_scale = 0;
      const Wrench<double> r = constrained_settings_test::residual_vector_in_double(g, cut.forces, w, sum_scale);
      const double tol = cut.refined ? double(st.tolerance) : double(ScalarTraits<S>::interior_tolerance);
      const double claim =
          tol * (grip_test::norm_l(w.template cast<double>(), l) + cut.forces.template cast<double>().norm() + squeeze);
      CHECK(grip_test::norm_l(r, l) <= claim + grip_test::roundoff<S>(8.0 * g.size(), 1, sum_scale));
      const double f_full = double(full.objective), f_cut = double(cut.objective);
      CHECK(std::abs(f_cut - f_full) <= (std::is_same<S, float>::value ? 1e-2 : 1e-6) * (1.0 + f_full));
    }
  }
  // Coverage. (Without refinement from a cut run, none of these would be Ok.)
  CHECK(cut_count >= count / 4);
  CHECK(ok_count >= cut_count / 4);
  MESSAGE("cut " << cut_count << ", refined to Ok " << ok_count);
}

TEST_CASE_TEMPLATE("max_iterations: bad values are refused, the fast path spends none", S, double, float) {
  std::mt19937 rng(106);
  const auto g = grip_test::random_grasp<Grasp<4, HardFinger, S>>(rng, 4);
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  ConstrainedSettings<S> st;
  for (int bad : {0, -1, std::numeric_limits<int>::min()}) {
    st.max_iterations = bad;
    CHECK(solve_constrained(g, w, st).status == Status::InvalidInput);
  }
  st = ConstrainedSettings<S>{};
  // The load that the squeeze targets t_i = s_i a_i balance (w = -G t): t is the optimum and
  // lies strictly inside every cone, so the fast path answers, with 0 passes even at 1.
  typename Grasp<4, HardFinger, S>::ForceVector t;
  for (int i = 0; i < g.size(); ++i) t.template segment<3>(3 * i) = g.contact(i).squeeze * g.contact(i).normal;
  const Wrench<S> inside = -g.wrench(t);
  st.max_iterations = 1;
  st.newton_passes = 0;
  const auto fast = solve_constrained(g, inside, st);
  REQUIRE(fast.fast_path);
  CHECK(fast.passes == 0);
  CHECK(fast.status == Status::Ok);
}

TEST_CASE("newton_passes: a warm start is bound by the same passes") {
  std::mt19937 rng(107);
  using GraspT = Grasp<6, HardFinger, double>;
  int cut = 0;
  for (int k = 0; k < 100; ++k) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, 6, true, 0.5);
    const Wrench<double> w = constrained_settings_test::random_load<double>(rng);
    const auto first = solve_constrained(g, w);
    if (first.fast_path) continue;
    const Wrench<double> w2 = w * 1.05;  // the next frame's load
    const auto warm = solve_constrained(g, w2, ConstrainedSettings<double>{}, first.multipliers);
    ConstrainedSettings<double> st;
    st.newton_passes = 2;
    st.max_iterations = 1;
    const auto warm_cut = solve_constrained(g, w2, st, first.multipliers);
    CHECK(warm_cut.passes <= constrained_settings_test::pass_bound(st));
    if (warm.passes <= 2 && warm.iterations == 0) {
      CHECK(warm_cut.forces == warm.forces);
    } else {
      constrained_settings_test::check_cut(g, w2, warm_cut);
      ++cut;
    }
  }
  CHECK(cut >= 10);
}
