// StabilityMonitor: per-contact modes against an independent classification, grasp summary,
// interchangeable cone policies, statuses, no heap.
#include <doctest/doctest.h>

#include <limits>
#include <random>

#include <grip/contact/pyramid_cone.hpp>
#include <grip/monitor/stability_monitor.hpp>
#include <grip/solve/solve_range_space.hpp>

#include "support/allocation_counter.hpp"
#include "support/cone_sampling.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using grip_test::pi;

using namespace grip;

template class grip::StabilityMonitor<Grasp<5, HardFinger, double>>;
template class grip::StabilityMonitor<Grasp<Dynamic, SoftFinger, float, 6>>;
template class grip::StabilityMonitor<Grasp<4, FrictionlessPoint, double>>;
template class grip::StabilityMonitor<Grasp<Dynamic, HardFinger, float, 8>, PyramidCone<4, float>>;

namespace {

// Independent classification straight from eq. 4-5 (hard finger): separating if f.a <= 0,
// sticking if f.a / |f| >= 1/sqrt(1 + mu^2), sliding otherwise.
template <class S>
ContactMode paper_mode(const Vector3<S>& f, const Contact<S>& c) {
  const S fa = f.dot(c.normal);
  if (!(fa > S(0))) return ContactMode::Separating;
  return fa / f.norm() >= S(1) / std::sqrt(S(1) + c.friction * c.friction) ? ContactMode::Sticking
                                                                           : ContactMode::Sliding;
}

}  // namespace

TEST_CASE_TEMPLATE("Monitor: modes agree with eq. 4-5 on seeded random forces", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 20>;
  std::mt19937 rng(71);
  grip_test::Uniform u01(0.0, 1.0);
  MonitorSettings<S> exact;
  exact.relative_tolerance = S(0);
  const StabilityMonitor<G> monitor(exact);
  int seen[3] = {0, 0, 0};
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + trial % 20;
    const G g = grip_test::random_grasp<G>(rng, n);
    typename G::ForceVector x(g.unknowns());
    for (int i = 0; i < n; ++i)
      x.template segment<3>(3 * i) =
          grip_test::random_force(rng, g.contact(i).normal.template cast<double>(), -2.0, 5.0, 5.0).template cast<S>();
    grip_test::NoHeapScope scope;
    const auto st = monitor.evaluate(g, x);
    CHECK(scope.allocations() == 0);
    REQUIRE(st.ok());
    REQUIRE(st.size() == n);
    int counts[3] = {0, 0, 0};
    S min_margin = std::numeric_limits<S>::max();
    for (int i = 0; i < n; ++i) {
      const Vector3<S> f = x.template segment<3>(3 * i);
      const auto& cs = st.contact(i);
      const auto cone = CoulombCone<S>::from_contact(g.contact(i));
      // Off the boundary the mode is the paper's.
      if (std::abs(cs.margin) > S(10) * grip_test::rel_tol<S>() * (S(1) + f.norm()) &&
          std::abs(cs.normal_force) > grip_test::rel_tol<S>())
        CHECK(cs.mode == paper_mode(f, g.contact(i)));
      const S tol = S(10) * grip_test::rel_tol<S>() * (S(1) + f.norm());
      CHECK(std::abs(cs.margin - cone.margin(f)) <= tol);
      CHECK(std::abs(cs.relative_margin - cone.relative_margin(f)) <= tol * std::abs(cone.relative_margin(f)));
      CHECK(std::abs(cs.normal_force - f.dot(g.contact(i).normal)) <= tol);
      CHECK((cs.tangential_force + cs.normal_force * g.contact(i).normal - f).norm() <=
            grip_test::rel_tol<S>() * S(10) * (S(1) + f.norm()));
      CHECK(cs.moment == S(0));
      CHECK(st.is_sliding(i) == (cs.mode == ContactMode::Sliding));
      CHECK(st.is_separating(i) == (cs.mode == ContactMode::Separating));
      ++counts[static_cast<int>(cs.mode)];
      ++seen[static_cast<int>(cs.mode)];
      min_margin = std::min(min_margin, cs.margin);
    }
    CHECK(st.sticking_count == counts[0]);
    CHECK(st.sliding_count == counts[1]);
    CHECK(st.separating_count == counts[2]);
    CHECK(st.min_margin == min_margin);
    CHECK(st.contact(st.min_margin_index).margin == min_margin);
    CHECK(st.stable == (counts[0] == n));
  }
  CHECK(seen[0] > 200);
  CHECK(seen[1] > 200);
  CHECK(seen[2] > 200);
}

TEST_CASE_TEMPLATE("Monitor: a squeezed grasp holds, the same grasp with little friction slips", S, double, float) {
  // Four fingers around a sphere (radius 4 cm) hold 1 N of weight: with squeeze 5 N and mu = 0.8
  // the range-space forces (squeeze + share of the load) stay in the cones.
  using G = Grasp<4, HardFinger, S>;
  G g;
  for (int i = 0; i < 4; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(pi / 2, i * pi / 2, 0.04, 0.8, 5.0)) == Status::Ok);
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-1);  // gravity on a 0.1 kg object
  const auto sol = solve_range_space(g, w);
  REQUIRE(sol.ok());
  const auto st = monitor_grasp(g, sol.forces);
  CHECK(st.ok());
  CHECK(st.stable);
  CHECK(st.sticking_count == 4);
  // Each finger: f_n = 5 N, |f_t| = 0.25 N: margin 0.8 * 5 - 0.25 = 3.75 N.
  CHECK(st.min_margin == doctest::Approx(3.75).epsilon(1e-4));
  // mu = 0.04: capacity 0.2 N per finger < 0.25 N: all four slide.
  for (int i = 0; i < 4; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(pi / 2, i * pi / 2, 0.04, 0.04, 5.0)) == Status::Ok);
  const auto slip = monitor_grasp(g, solve_range_space(g, w).forces);
  CHECK_FALSE(slip.stable);
  CHECK(slip.sliding_count == 4);
  CHECK(slip.min_margin == doctest::Approx(0.2 - 0.25).epsilon(1e-3));
  // The monitor as a function object: the same hand-derived verdict.
  const StabilityMonitor<G> monitor;
  const auto called = monitor(g, solve_range_space(g, w).forces);
  CHECK_FALSE(called.stable);
  CHECK(called.sliding_count == 4);
  CHECK(called.min_margin == doctest::Approx(0.2 - 0.25).epsilon(1e-3));
}

TEST_CASE_TEMPLATE("Monitor: cone policies are interchangeable and nest", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 12>;
  std::mt19937 rng(72);
  for (int trial = 0; trial < 200; ++trial) {
    const G g = grip_test::random_grasp<G>(rng, 12);
    typename G::ForceVector x(g.unknowns());
    for (int i = 0; i < 12; ++i)
      x.template segment<3>(3 * i) =
          grip_test::random_force(rng, g.contact(i).normal.template cast<double>(), 0.5, 5.0, 5.0).template cast<S>();
    MonitorSettings<S> exact;
    exact.relative_tolerance = S(0);
    const auto coulomb = monitor_grasp<CoulombCone<S>>(g, x, exact);
    const auto inscribed = monitor_grasp<PyramidCone<6, S, PyramidFit::Inscribed>>(g, x, exact);
    const auto circumscribed = monitor_grasp<PyramidCone<6, S, PyramidFit::Circumscribed>>(g, x, exact);
    // Inscribed pyramid is conservative: whatever slides in the exact cone slides in it too;
    // the circumscribed one is optimistic.
    for (int i = 0; i < 12; ++i) {
      if (coulomb.is_sliding(i) && coulomb.contact(i).margin < -S(1e-3)) CHECK(inscribed.is_sliding(i));
      if (circumscribed.is_sliding(i)) CHECK(coulomb.is_sliding(i));
    }
    CHECK(inscribed.sliding_count >= coulomb.sliding_count);
  }
}

TEST_CASE_TEMPLATE("Monitor: soft and frictionless grasps", S, double, float) {
  // Soft finger: the moment enters the margin and is reported.
  Grasp<Dynamic, SoftFinger, S, 4> soft;
  Contact<S> c = grip_test::sphere_contact<S>(0.0, 0.0, 0.03, 0.5, 1.0);
  c.torsional_friction = S(0.01);
  REQUIRE(soft.add(c) == Status::Ok);
  typename Grasp<Dynamic, SoftFinger, S, 4>::ForceVector xs(4);
  xs << S(0), S(0), S(-2), S(0.015);  // f_n = 2 (normal -z), |m| = 0.015 <= 0.01 * 2
  auto st = monitor_grasp(soft, xs);
  CHECK(st.stable);
  CHECK(st.contact(0).moment == S(0.015));
  xs(3) = S(0.025);  // > 0.02: torsional slip
  st = monitor_grasp(soft, xs);
  CHECK(st.is_sliding(0));
  // Frictionless: only separation can happen.
  Grasp<2, FrictionlessPoint, S> point;
  REQUIRE(point.set(0, c) == Status::Ok);
  REQUIRE(point.set(1, c) == Status::Ok);
  typename Grasp<2, FrictionlessPoint, S>::ForceVector xp(S(3), S(-1));
  const auto sp = monitor_grasp(point, xp);
  CHECK(sp.is_sticking(0));
  CHECK(sp.is_separating(1));
  CHECK(sp.min_margin == S(-1));
  CHECK(sp.min_margin_index == 1);
}

TEST_CASE_TEMPLATE("Monitor: bad input is InvalidInput with a finite reset state", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 5>;
  std::mt19937 rng(73);
  const G g = grip_test::random_grasp<G>(rng, 3);
  typename G::ForceVector x = G::ForceVector::Ones(9);
  grip_test::NoHeapScope scope;
  CHECK(monitor_grasp(g, x).ok());
  x(4) = std::numeric_limits<S>::quiet_NaN();
  auto st = monitor_grasp(g, x);
  CHECK(st.status == Status::InvalidInput);
  CHECK_FALSE(st.stable);
  CHECK(st.size() == 0);
  CHECK(st.min_margin == cone_margin_floor<S>());
  x(4) = std::numeric_limits<S>::infinity();
  CHECK(monitor_grasp(g, x).status == Status::InvalidInput);
  const typename G::ForceVector short_x = G::ForceVector::Ones(6);  // size mismatch
  CHECK(monitor_grasp(g, short_x).status == Status::InvalidInput);
  const Grasp<3, HardFinger, S> incomplete;  // no slot set
  CHECK(monitor_grasp(incomplete, Grasp<3, HardFinger, S>::ForceVector::Ones()).status == Status::InvalidInput);
  // An empty grasp is Ok but not stable: it holds nothing.
  const G empty;
  const auto e = monitor_grasp(empty, typename G::ForceVector(0));
  CHECK(e.ok());
  CHECK_FALSE(e.stable);
  CHECK(e.min_margin_index == -1);
  CHECK(scope.allocations() == 0);
}

namespace {

// classify() must give exactly evaluate()'s modes and counts; evaluate() into reused storage
// must give exactly the by-value state. Modes are compared off the slack boundary only, where
// the square-root-free test and the margin test could round differently.
template <class Cone, class G>
void check_classify_matches(std::mt19937& rng, int trials, int n, double fn_low) {
  using S = typename G::ScalarType;
  const StabilityMonitor<G, Cone> monitor;
  GraspState<G> reused;
  GraspModes<G> modes;
  int disagreements = 0, checked = 0, kinds[3] = {0, 0, 0};
  for (int trial = 0; trial < trials; ++trial) {
    const G g = grip_test::random_grasp<G>(rng, n);
    typename G::ForceVector x(g.unknowns());
    grip_test::Uniform u01(0.0, 1.0);
    for (int i = 0; i < g.size(); ++i) {
      if constexpr (G::dim == 1) {
        x(i) = S(fn_low + (5.0 - fn_low) * u01(rng));
      } else {
        x.template segment<3>(G::dim * i) =
            grip_test::random_force(rng, g.contact(i).normal.template cast<double>(), fn_low, 5.0, 5.0)
                .template cast<S>();
        if constexpr (G::dim == 4) x(G::dim * i + 3) = S(0.02 * (u01(rng) - 0.5));
      }
    }
    grip_test::NoHeapScope scope;
    monitor.evaluate(g, x, reused);
    monitor.classify(g, x, modes);
    CHECK(scope.allocations() == 0);
    const auto fresh = monitor.evaluate(g, x);
    REQUIRE(modes.ok());
    REQUIRE(reused.ok());
    CHECK(modes.size() == fresh.size());
    CHECK(reused.min_margin == fresh.min_margin);
    CHECK(reused.min_margin_index == fresh.min_margin_index);
    for (int i = 0; i < g.size(); ++i) {
      CHECK(reused.mode(i) == fresh.mode(i));
      CHECK(reused.contact(i).mode == fresh.mode(i));
      CHECK(reused.contact(i).margin == fresh.contact(i).margin);
      ++kinds[static_cast<int>(fresh.mode(i))];
      const typename Cone::Vector xi = x.template segment<G::dim>(G::dim * i);
      const S slack = monitor.settings().relative_tolerance * fresh.contact(i).normal_force;
      if (std::abs(fresh.contact(i).margin + slack) <= S(100) * grip_test::rel_tol<S>() * (S(1) + xi.norm())) continue;
      ++checked;
      disagreements += modes.mode(i) != fresh.mode(i);
    }
    if (disagreements == 0) {
      CHECK(modes.sticking_count == fresh.sticking_count);
      CHECK(modes.sliding_count == fresh.sliding_count);
      CHECK(modes.separating_count == fresh.separating_count);
      CHECK(modes.stable == fresh.stable);
    }
  }
  CHECK(disagreements == 0);
  CHECK(checked > trials * n / 2);
  CHECK(kinds[0] > 0);
  CHECK((kinds[1] > 0) == (G::dim > 1));  // a frictionless contact cannot slide
  CHECK(kinds[2] > 0);
}

}  // namespace

TEST_CASE_TEMPLATE("Monitor: classify() gives evaluate()'s modes, evaluate() into reused storage", S, double, float) {
  std::mt19937 rng(73);
  check_classify_matches<CoulombCone<S>, Grasp<Dynamic, HardFinger, S, 20>>(rng, 200, 20, -2.0);
  check_classify_matches<PyramidCone<8, S>, Grasp<Dynamic, HardFinger, S, 20>>(rng, 100, 20, -2.0);
  check_classify_matches<SoftFingerCone<S>, Grasp<Dynamic, SoftFinger, S, 20>>(rng, 100, 20, -2.0);
  check_classify_matches<CompressionCone<S>, Grasp<Dynamic, FrictionlessPoint, S, 20>>(rng, 50, 20, -2.0);

  // Reuse after a valid call: invalid input resets the storage to the documented state.
  using G = Grasp<Dynamic, HardFinger, S, 20>;
  const G g = grip_test::random_grasp<G>(rng, 6);
  typename G::ForceVector x = solve_range_space(g, grip_test::random_wrench<S>(rng)).forces;
  const StabilityMonitor<G> monitor;
  GraspState<G> st;
  GraspModes<G> modes;
  monitor.evaluate(g, x, st);
  monitor.classify(g, x, modes);
  REQUIRE(st.ok());
  REQUIRE(modes.size() == 6);
  x(4) = std::numeric_limits<S>::quiet_NaN();
  monitor.evaluate(g, x, st);
  monitor.classify(g, x, modes);
  const GraspModes<G>* both[2] = {&st, &modes};
  for (const GraspModes<G>* m : both) {
    CHECK(m->status == Status::InvalidInput);
    CHECK(m->size() == 0);
    CHECK_FALSE(m->stable);
    CHECK(m->sticking_count + m->sliding_count + m->separating_count == 0);
  }
  CHECK(st.min_margin == cone_margin_floor<S>());
  CHECK(st.min_margin_index == -1);
  // The one-call forms.
  CHECK(classify_grasp(g, x).status == Status::InvalidInput);
  CHECK(classify_grasp<PyramidCone<4, S>>(g, x).status == Status::InvalidInput);
}
