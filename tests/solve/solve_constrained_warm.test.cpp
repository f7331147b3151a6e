// solve_constrained from the previous frame's certificate (ConstrainedWarmStart): pairs of
// frames of a slipping grasp, the second with its contacts moved by about 1 mm and its load
// changed by 2 %. Where the old certificate still holds, the answer is Infeasible with a
// certificate that meets its definition (checked from the dual cones, not through the solver's
// test) and least-residual forces as good as the cold solve's (by the least-residual objective
// P); where it does not, the answer is the cold solve's, bit for bit. A frame that slips just
// beyond a hold, solved from the hold's multipliers, is decided likewise from Newton's
// multipliers, reversed. And ConstrainedFrameSolver carries the certificate from frame to frame.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <utility>

#include <grip/pipeline/frame_solver.hpp>
#include <grip/solve/detail/certificate.hpp>
#include <grip/solve/solve_constrained.hpp>

#include "solve/constrained_support.hpp"
#include "solve/slip_checks.hpp"
#include "support/equilibrium_norm.hpp"
#include "support/fixtures.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

// Two frames of one grasp: `now` (3 hard fingers on a 4 cm sphere, mu 0.3 to 1, a load of 0.5 to
// 200 N with moments) and `before`, its contacts 0.025 rad (1 mm) away and its load 2 % larger.
template <class S>
void frame_pair(std::mt19937& rng, Grasp<3, HardFinger, S>& now, Wrench<S>& w_now, Grasp<3, HardFinger, S>& before,
                Wrench<S>& w_before) {
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> n01(0, 1);
  for (int i = 0; i < 3; ++i) {
    const double th = std::acos(1 - 2 * u01(rng)), ph = 6.283185307179586 * u01(rng), mu = 0.3 + 0.7 * u01(rng);
    REQUIRE(now.set(i, grip_test::sphere_contact<S>(th, ph, 0.04, mu, 0.3)) == Status::Ok);
    REQUIRE(before.set(i, grip_test::sphere_contact<S>(th + 0.025 * n01(rng), ph + 0.025 * n01(rng), 0.04, mu, 0.3)) ==
            Status::Ok);
  }
  Wrench<double> wd;
  for (int j = 0; j < 6; ++j) wd(j) = (j < 3 ? 1.0 : 0.03) * n01(rng);
  const double size = 0.5 * std::pow(400.0, u01(rng));
  wd.head<3>() *= size / wd.head<3>().norm();
  wd.tail<3>() *= size;
  w_now = wd.cast<S>();
  w_before = (1.02 * wd).cast<S>();
}

}  // namespace

TEST_CASE_TEMPLATE("solve_constrained: the previous frame's certificate decides a slip, checked by definition", S,
                   double, float) {
  std::mt19937 rng(4242);
  const ConstrainedSettings<S> st;
  int pairs = 0, reused = 0, fewer_passes = 0, held_cold = 0;
  for (int k = 0; k < 600; ++k) {
    Grasp<3, HardFinger, S> now, before;
    Wrench<S> w, w_before;
    frame_pair(rng, now, w, before, w_before);
    const auto previous = solve_constrained(before, w_before);
    if (previous.status != Status::Infeasible) continue;
    ++pairs;
    ConstrainedWarmStart<S> start;
    start.certificate = previous.certificate;
    start.has_certificate = true;
    const auto warm = solve_constrained(now, w, st, start);
    const auto cold = solve_constrained(now, w, st);
    Wrench<S> unit;
    // Which branch the solver takes (its own test); the checks below are independent of it.
    if (!detail::is_infeasibility_certificate(now, w, previous.certificate, st.certificate_tolerance, unit)) {
      CHECK(warm.status == cold.status);
      CHECK(warm.forces == cold.forces);
      CHECK(warm.certificate == cold.certificate);
      CHECK(warm.passes == cold.passes);
      continue;
    }
    ++reused;
    REQUIRE(warm.status == Status::Infeasible);
    grip_test::check_certificate(now, w, warm.certificate);
    fewer_passes += warm.passes < cold.passes ? 1 : 0;
    if (cold.status != Status::Infeasible) {
      ++held_cold;  // held by forces of about |w_ext| / certificate_tolerance: the contract allows either
      continue;
    }
    // Both solve the same least-residual problem, each to the interior-point method's tolerance.
    const double delta = grip_test::least_residual_delta(now);
    const Wrench<double> wd = w.template cast<double>();
    const double p_warm = grip_test::least_residual_objective(now, wd, warm.forces, delta),
                 p_cold = grip_test::least_residual_objective(now, wd, cold.forces, delta);
    const double slack =
        2 * double(ScalarTraits<S>::interior_tolerance) * std::max(p_warm, p_cold) +
        grip_test::roundoff<S>(
            16, 1, w.template cast<double>().squaredNorm() + cold.forces.template cast<double>().squaredNorm());
    CHECK(std::abs(p_warm - p_cold) <= slack);
  }
  MESSAGE(pairs, " slipping pairs; the old certificate held in ", reused, ", with fewer passes in ", fewer_passes);
  CHECK(pairs >= 100);
  CHECK(reused >= pairs / 2);
  CHECK(fewer_passes == reused);
  CHECK(held_cold <= reused / 100 + 1);
}

TEST_CASE_TEMPLATE("solve_constrained: a slip just beyond a hold is decided from Newton's multipliers, reversed", S,
                   double, float) {
  // A grasp, a load it holds and one under which it slips (loads that hold form a cone, so only
  // their directions matter); on the segment between them, the last load held, found by
  // bisection on cold solves. Its multipliers are large along a certificate; a load a quarter of
  // the segment beyond it slips, solved from them. Where Newton's passes end short on that slip
  // and their multipliers, reversed, prove it, the solve is the least-residual problem alone:
  // the iterations of a solve given the answer's own certificate (which step 0 accepts), and
  // Newton's passes besides. Either way the certificate meets its definition (checked from the
  // dual cones) and the forces are as good as the cold solve's.
  std::mt19937 rng(5151);
  const ConstrainedSettings<S> st;
  int pairs = 0, reversed = 0;
  for (int k = 0; k < 1500; ++k) {
    Grasp<3, HardFinger, S> g, unused;
    Wrench<S> w0, w1, w_unused;
    frame_pair(rng, g, w0, unused, w_unused);
    frame_pair(rng, unused, w1, unused, w_unused);
    if (solve_constrained(g, w0).status == Status::Infeasible) std::swap(w0, w1);
    if (solve_constrained(g, w0).status != Status::Ok || solve_constrained(g, w1).status != Status::Infeasible)
      continue;
    const Wrench<double> a = w0.template cast<double>(), b = w1.template cast<double>();
    const auto load = [&](double t) { return Wrench<S>(((1 - t) * a + t * b).cast<S>()); };
    double lo = 0, hi = 1;
    for (int step = 0; step < 30; ++step) {
      const double mid = 0.5 * (lo + hi);
      (solve_constrained(g, load(mid)).status == Status::Ok ? lo : hi) = mid;
    }
    const auto held = solve_constrained(g, load(lo));
    const Wrench<S> beyond = load(std::min(1.0, hi + 0.25));
    const auto cold = solve_constrained(g, beyond);
    // (Multipliers beyond ScalarTraits::max_magnitude are no warm start: ConstrainedFrameSolver
    // drops them.)
    if (held.status != Status::Ok || cold.status != Status::Infeasible || !detail::all_in_range(held.multipliers))
      continue;
    ++pairs;
    CAPTURE(k);
    const auto warm = solve_constrained(g, beyond, st, held.multipliers);
    REQUIRE(warm.status == Status::Infeasible);
    grip_test::check_certificate(g, beyond, warm.certificate);
    ConstrainedWarmStart<S> proven;
    proven.certificate = warm.certificate;
    proven.has_certificate = true;
    const auto alone = solve_constrained(g, beyond, st, proven);
    REQUIRE(alone.status == Status::Infeasible);
    CHECK(warm.iterations >= alone.iterations);
    if (warm.iterations == alone.iterations) {
      ++reversed;
      CHECK(warm.passes == st.newton_passes + alone.passes);
      CHECK(warm.forces == alone.forces);  // the same least-residual run, from the same start
    }
    const double delta = grip_test::least_residual_delta(g);
    const Wrench<double> wd = beyond.template cast<double>();
    const double p_warm = grip_test::least_residual_objective(g, wd, warm.forces, delta),
                 p_cold = grip_test::least_residual_objective(g, wd, cold.forces, delta);
    CHECK(std::abs(p_warm - p_cold) <=
          2 * double(ScalarTraits<S>::interior_tolerance) * std::max(p_warm, p_cold) +
              grip_test::roundoff<S>(16, 1, wd.squaredNorm() + cold.forces.template cast<double>().squaredNorm()));
  }
  MESSAGE(pairs, " holds with a slip beyond; decided from Newton's multipliers, reversed, in ", reversed);
  CHECK(pairs >= 40);
  // In float the multipliers near the boundary carry float's rounding, and fewer prove the slip.
  CHECK(reversed >= (std::is_same<S, double>::value ? pairs / 2 : 1));
}

TEST_CASE_TEMPLATE("solve_constrained: a warm certificate that is not finite is InvalidInput", S, double, float) {
  std::mt19937 rng(7);
  Grasp<3, HardFinger, S> now, before;
  Wrench<S> w, w_before;
  frame_pair(rng, now, w, before, w_before);
  ConstrainedWarmStart<S> start;
  start.certificate(2) = std::numeric_limits<S>::quiet_NaN();
  start.has_certificate = true;
  const auto sol = solve_constrained(now, w, ConstrainedSettings<S>{}, start);
  CHECK(sol.status == Status::InvalidInput);
  CHECK(sol.forces.isZero());
  start.has_certificate = false;  // not given: not read
  CHECK(solve_constrained(now, w, ConstrainedSettings<S>{}, start).status != Status::InvalidInput);
}

TEST_CASE("ConstrainedFrameSolver carries a slip's certificate to the next frame, and multipliers after it holds") {
  // A grasp that slips for 20 frames while its contacts creep, then holds (no load).
  std::mt19937 rng(99);
  Grasp<3, HardFinger, double> g, unused;
  Wrench<double> w, w_unused;
  ConstrainedSolution<Grasp<3, HardFinger, double>> first;
  do {
    frame_pair(rng, g, w, unused, w_unused);
    first = solve_constrained(g, w);
  } while (first.status != Status::Infeasible);
  ConstrainedFrameSolver<double> solver;
  int faster = 0;
  for (int frame = 0; frame < 20; ++frame) {
    Grasp<3, HardFinger, double> moved;
    for (int i = 0; i < 3; ++i) {
      Contact<double> c = g.contact(i);
      c.position = Eigen::AngleAxisd(0.0005 * frame, Vector3<double>::UnitZ()) * c.position;
      c.normal = Eigen::AngleAxisd(0.0005 * frame, Vector3<double>::UnitZ()) * c.normal;
      REQUIRE(moved.set(i, c) == Status::Ok);
    }
    const auto sol = solver(moved, w);
    const auto cold = solve_constrained(moved, w);
    REQUIRE(sol.status == Status::Infeasible);
    CHECK(solver.warm.has_certificate);
    CHECK_FALSE(solver.warm.has_multipliers);
    grip_test::check_certificate(moved, w, solver.warm.certificate);
    if (frame > 0) faster += solver.passes < cold.passes ? 1 : 0;
  }
  CHECK(faster == 19);
  // Held (no load: zero forces balance it): the certificate no longer holds; multipliers are
  // kept instead.
  const auto held = solver(g, Wrench<double>(Wrench<double>::Zero()));
  REQUIRE(held.status == Status::Ok);
  CHECK(solver.warm.has_multipliers);
  CHECK_FALSE(solver.warm.has_certificate);
}
