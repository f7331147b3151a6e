// Force closure with exact cones: hand-derived cases, Nguyen's two-finger test, certificates.
#include <doctest/doctest.h>
#include <limits>

#include <grip/analysis/force_closure.hpp>
#include <grip/analysis/max_wrench.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/test_scale.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

using grip_test::pi;

// True if u is (to tol) a certificate: G_i^T u in the dual cone K_i^* for every contact,
// checked with the dual cone written out by hand: v_n >= sqrt(mu^2 |v_t|^2 + mu_t^2 v_m^2).
template <class GraspT>
bool dual_certificate(const GraspT& g, const Wrench<typename GraspT::ScalarType>& u, double tol) {
  using M = typename GraspT::ModelType;
  for (int i = 0; i < g.size(); ++i) {
    const auto& c = g.contact(i);
    const auto v = M::wrench_transpose(c, u).template cast<double>().eval();
    if constexpr (GraspT::dim == 1) {
      if (v(0) < -tol) return false;
    } else {
      const Vector3<double> a = c.normal.template cast<double>();
      const double vn = a.dot(v.template head<3>());
      const double vt = (v.template head<3>() - vn * a).norm();
      double q = double(c.friction) * double(c.friction) * vt * vt;
      if constexpr (GraspT::dim == 4) q += double(c.torsional_friction) * double(c.torsional_friction) * v(3) * v(3);
      if (vn < std::sqrt(q) - tol) return false;
    }
  }
  return double(u.norm()) > 0.5;
}

// True if x_i - t a_i lies in the exact cone (to tol) for all i: x_n - t >= sqrt(|x_t|^2/mu^2 + m^2/mu_t^2).
template <class GraspT>
bool inside_cones(const GraspT& g, const typename GraspT::ForceVector& x, double t, double tol) {
  for (int i = 0; i < g.size(); ++i) {
    const auto& c = g.contact(i);
    const auto xi = x.segment(i * GraspT::dim, GraspT::dim).template cast<double>().eval();
    const Vector3<double> a = c.normal.template cast<double>();
    const double xn = a.dot(xi.template head<3>());
    const double xt = (xi.template head<3>() - xn * a).norm();
    double q = xt * xt / (double(c.friction) * double(c.friction));
    if constexpr (GraspT::dim == 4) q += xi(3) * xi(3) / (double(c.torsional_friction) * double(c.torsional_friction));
    if (xn - t < std::sqrt(q) - tol) return false;
  }
  return true;
}

// The round-off of inside_cones() for hard fingers: each force component is rounded once to S
// (u of |x|) and the margin t once (u of t); the cone test divides the tangential part by mu, so
// its rounding counts 1/mu times: k = 2 (1 + 1/mu) for the smallest mu of the grasp, of |x| + t.
template <class GraspT>
double cone_roundoff(const GraspT& g, const typename GraspT::ForceVector& x, double t) {
  double mu = std::numeric_limits<double>::infinity();
  for (int i = 0; i < g.size(); ++i) mu = std::min(mu, double(g.contact(i).friction));
  return grip_test::roundoff<typename GraspT::ScalarType>(2 * (1 + 1 / mu), 1, double(x.norm()) + std::abs(t));
}

// How far an unresisted direction u may leave the dual cones: the interior-point method stops
// with its dual residual below settings.tolerance relative to the iterate (of size about 1 here),
// and G_i^T u + margin e_i lies in K_i^* to that residual, the margin being <= 0 in the grasps
// checked with it: 2 * stop, plus u's rounding to S and G_i^T u's (|v| <= 1 + |r| ~ 1): k = 8
// of 1.
template <class S>
double certificate_tolerance() {
  return 2 * double(ConicAnalysisSettings<S>{}.tolerance) + grip_test::roundoff<S>(8, 1, 1);
}

template <class S>
Contact<S> on_sphere(double theta, double phi, double mu, double mut = 0.0) {
  Contact<S> c = grip_test::sphere_contact<S>(theta, phi, 0.05, mu);
  c.torsional_friction = S(mut);
  return c;
}

}  // namespace

TEST_CASE_TEMPLATE("three hard fingers at 120 degrees, mu = 0.5: closure with margin 1/3", S, double, float) {
  // Hand derivation: t <= x_n,i for every i and sum x_n,i = 1, so t <= 1/3; the equal
  // squeeze x_i = a_i / 3 is internal (sum a_i = 0, r_i x a_i = 0) and has margin 1/3.
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i) REQUIRE(g.set(i, on_sphere<S>(pi / 2, 2 * pi / 3 * i, 0.5)) == Status::Ok);
  ForceClosure<Grasp<3, HardFinger, S>> fc;
  {
    grip_test::NoHeapScope scope;
    fc = force_closure(g);
    CHECK(scope.allocations() == 0);
  }
  REQUIRE(fc.status == Status::Ok);
  CHECK(fc.closure);
  CHECK(fc.rank == 6);
  // The margin: Ok when an internal force achieves it and the multipliers bound it from above
  // within stop (1 + margin) (ConicAnalysisSettings), plus its rounding to S and the data's
  // (contacts rounded to S move the optimum by a few u): k = 4 of 1. Observed at most 1.1e-16
  // (double) and 9.9e-9 (float) of 1.3e-6 and 1.3e-4 (the method converges far below its
  // tolerance here).
  const double stop = double(ConicAnalysisSettings<S>{}.tolerance);
  CHECK(std::abs(double(fc.margin) - 1.0 / 3.0) <= stop * (1 + 1.0 / 3.0) + grip_test::roundoff<S>(4, 1, 1));
  // G x = 0 to round-off: x (normal forces summing to 1 N) corrected onto G's null space and
  // rounded to S, then G x summed in S over 3 contacts of lever arm 5 cm: k = 4 of 1 N.
  // Observed at most 0.25 u (double) and 0 (float).
  CHECK(double(fc.residual) <= grip_test::roundoff<S>(4, 1, 1));
  // x achieves the margin (x_i - margin a_i inside K_i) to round-off (cone_roundoff, k = 6 of
  // |x| + t here). Observed 0.2 u (double) and 0.6 u (float) outside, 1/10 of the bound.
  CHECK(inside_cones(g, fc.internal_force, double(fc.margin), cone_roundoff(g, fc.internal_force, double(fc.margin))));
  CHECK(fc.unresisted.norm() == S(0));
}

TEST_CASE_TEMPLATE("not in closure: frictionless antipodal, mu = 0 on a sphere, two hard fingers", S, double, float) {
  // Certificates within certificate_tolerance<S>() (2 stop + 8 u): observed at most 1.3e-17
  // (double) and 2e-9 (float) out of the dual cones, against 2e-6 and 2e-4.
  const double tol = certificate_tolerance<S>();
  // Two frictionless antipodal contacts: G has rank 1 (only the force along the line).
  Grasp<2, FrictionlessPoint, S> p;
  REQUIRE(p.set(0, on_sphere<S>(pi / 2, 0, 0)) == Status::Ok);
  REQUIRE(p.set(1, on_sphere<S>(pi / 2, pi, 0)) == Status::Ok);
  const auto fp = force_closure(p);
  CHECK(fp.status == Status::Ok);
  CHECK_FALSE(fp.closure);
  CHECK(fp.rank == 1);
  CHECK(dual_certificate(p, fp.unresisted, tol));
  // mu = 0, any number of hard fingers on a sphere: every normal passes through the centre,
  // so no moment can be produced: rank <= 3 and the certificate is a pure moment.
  std::mt19937 rng(23);
  grip_test::Uniform u01(0.0, 1.0);
  for (int n = 3; n <= 10; ++n) {
    Grasp<Dynamic, HardFinger, S, 10> h;
    for (int i = 0; i < n; ++i) {
      const double theta = std::acos(1 - 2 * u01(rng)), phi = 2 * pi * u01(rng);
      REQUIRE(h.add(on_sphere<S>(theta, phi, 0.0)) == Status::Ok);
    }
    const auto f = force_closure(h);
    CHECK(f.status == Status::Ok);
    CHECK_FALSE(f.closure);
    CHECK(f.rank <= 3);
    // The normals' span is R^3 and every moment is unresisted: u's force part is orthogonal to
    // 3+ unit normals, a null-space vector of the rank test's eigen decomposition of the Gram
    // matrix sum_i b_i P_i b_i^T (|u| = 1), whose entries carry up to about 2 n roundings each
    // (n contacts, 3-term products): k = 4 n. Observed at most 5.6 u (double).
    CHECK(double(f.unresisted.template head<3>().norm()) <= grip_test::roundoff<S>(4 * n, 1, 1));
    CHECK(dual_certificate(h, f.unresisted, tol));
  }
  // Two hard fingers (any mu): no moment about the line through them; rank 5.
  Grasp<2, HardFinger, S> two;
  REQUIRE(two.set(0, on_sphere<S>(pi / 3, 0.4, 1.5)) == Status::Ok);
  REQUIRE(two.set(1, on_sphere<S>(2 * pi / 3, 0.4 + pi, 1.5)) == Status::Ok);
  const auto ft = force_closure(two);
  CHECK_FALSE(ft.closure);
  CHECK(ft.rank == 5);
  const Vector3<S> line = (two.contact(1).position - two.contact(0).position).normalized();
  // |u| = 1 and |line| = 1 each to 2 roundings, their product and the dot's 3: k = 8 of 1.
  // Observed 0 in both types.
  CHECK(std::abs(double(std::abs(ft.unresisted.template tail<3>().dot(line))) - 1.0) <=
        grip_test::roundoff<S>(8, 1, 1));
}

TEST_CASE_TEMPLATE("two soft fingers: closure iff the line lies in both cones (Nguyen)", S, double, float) {
  // Contacts at polar angles 0 and alpha on a sphere: the line between them makes the angle
  // beta = pi/2 - alpha/2 with each inward normal (isosceles triangle with the centre), so
  // closure holds iff mu > tan(beta) = cot(alpha/2). alpha = 120 deg: mu* = 1/sqrt(3).
  const double alpha = 2 * pi / 3, mu_star = 1.0 / std::tan(alpha / 2);
  auto closure_at = [&](double mu) {
    Grasp<2, SoftFinger, S> g;
    REQUIRE(g.set(0, on_sphere<S>(0.0, 0.0, mu, 0.01)) == Status::Ok);
    REQUIRE(g.set(1, on_sphere<S>(alpha, 0.3, mu, 0.01)) == Status::Ok);
    return force_closure(g);
  };
  const double tol = certificate_tolerance<S>();  // observed at most -0.15: deep inside
  const auto yes = closure_at(0.8);
  CHECK(yes.status == Status::Ok);
  CHECK(yes.closure);
  CHECK(yes.rank == 6);
  const auto no = closure_at(0.4);
  CHECK(no.status == Status::Ok);
  CHECK_FALSE(no.closure);
  Grasp<2, SoftFinger, S> gno;
  REQUIRE(gno.set(0, on_sphere<S>(0.0, 0.0, 0.4, 0.01)) == Status::Ok);
  REQUIRE(gno.set(1, on_sphere<S>(alpha, 0.3, 0.4, 0.01)) == Status::Ok);
  CHECK(dual_certificate(gno, no.unresisted, tol));
  // The boundary in mu by bisection, to tolerance.
  double lo = 0.3, hi = 1.0;
  for (int k = 0; k < 16; ++k) {
    const double mid = 0.5 * (lo + hi);
    (closure_at(mid).closure ? hi : lo) = mid;
  }
  // Not round-off: the bisection's half width, and the decision threshold (closure only when
  // margin > 10 * settings.tolerance), which moves the boundary up by 10 stop / the margin's
  // slope in mu. The margin is 0 at mu* and concave in mu, so its secant over [mu*, mu* + 0.05]
  // bounds that slope from below, and the shift from above (the contacts' rounding to S moves
  // mu* by a few u: k = 8 of 1). Observed: 0.70 (double) and 0.92 (float) of the upper bound,
  // the offsets being that shift (1.3e-5 and 1.2e-3), which the bound predicts, not noise.
  const double stop = double(ConicAnalysisSettings<S>{}.tolerance);
  const double slope = double(closure_at(mu_star + 0.05).margin) / 0.05;
  const double mid = 0.5 * (lo + hi), ro = grip_test::roundoff<S>(8, 1, 1);
  CHECK(mid >= mu_star - (hi - lo) / 2 - ro);
  CHECK(mid <= mu_star + (hi - lo) / 2 + 10 * stop / slope + ro);
}

TEST_CASE_TEMPLATE("random grasps: the returned internal force or certificate checks out", S, double, float) {
  std::mt19937 rng(29);
  const double tol = certificate_tolerance<S>();
  int yes = 0, no = 0;
  const int reps = grip_test::scaled(30, 8);
  for (int rep = 0; rep < reps; ++rep) {
    const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 6>>(rng, 2 + rep % 4);
    const auto f = force_closure(g);
    REQUIRE(f.status == Status::Ok);
    if (f.closure) {
      ++yes;
      // Internal to round-off: the cone multipliers are corrected onto the null space of G.
      // As in the 120-degree case (k = 4 of 1 N): observed at most 0.7 u (double), 0.4 u (float).
      CHECK(double(f.residual) <= grip_test::roundoff<S>(4, 1, 1));
      // cone_roundoff: observed at most 0.5 u (double), 0.13 u (float) outside, k >= 4.4 here.
      CHECK(inside_cones(g, f.internal_force, double(f.margin), cone_roundoff(g, f.internal_force, double(f.margin))));
    } else {
      ++no;
      // Observed at most 2.1e-9 (double) and 2.1e-7 (float) against 2e-6 and 2e-4.
      CHECK(dual_certificate(g, f.unresisted, tol));
    }
  }
  CHECK(yes > 0);
  CHECK(no > 0);
}

TEST_CASE_TEMPLATE("largest resistible wrench along a direction, by hand", S, double, float) {
  // Three equatorial hard fingers, mu = 0.5, budget B on the sum of normal forces, load along
  // z: |sum f_z| <= sum mu f_n <= mu B, attained by f_n = B/3, f_z = mu B / 3 each (normals
  // cancel; moments sum to (sum r_i) x f_z z = 0). So s* = mu B = 5 for B = 10.
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i) REQUIRE(g.set(i, on_sphere<S>(pi / 2, 2 * pi / 3 * i, 0.5)) == Status::Ok);
  Wrench<S> d = Wrench<S>::Zero();
  d(2) = S(-1);
  ResistibleWrench<Grasp<3, HardFinger, S>> r;
  {
    grip_test::NoHeapScope scope;
    r = max_resistible_wrench(g, d, S(10));
    CHECK(scope.allocations() == 0);
  }
  REQUIRE(r.status == Status::Ok);
  // The scale is B / (|T d| c) for the method's primal cost c = sum e.x, whose gap and rows'
  // residual are each below settings.tolerance relative to c: 2 stop s* = 10 stop, within
  // stop * (B + s*), plus 4 u of s* for its rounding. Observed 1.6e-7 (double) and 1.6e-5
  // (float), against 1.5e-5 and 1.5e-3.
  const double stop = double(ConicAnalysisSettings<S>{}.tolerance);
  CHECK(std::abs(double(r.scale) - 5.0) <= stop * (10 + 5) + grip_test::roundoff<S>(4, 1, 5));
  // The forces are the method's cone variables scaled to the budget: they balance the scaled
  // load to its rows' residual (below the tolerance relative to the load and the forces, each
  // of about the budget B = 10 N), plus float's rounding of forces of about B. Observed 3.3e-7
  // (double) and 3.2e-5 (float), against 2e-5 and 2e-3.
  CHECK(double(r.residual) <= 10.0 * (2 * stop + grip_test::roundoff<S>(16, 1, 1)));
  // The cone variables are interior points, the forces them scaled and rounded to S:
  // cone_roundoff. Observed inside by 1.1e-7 (double) and 1.1e-5 (float).
  CHECK(inside_cones(g, r.forces, 0.0, cone_roundoff(g, r.forces, 0.0)));
  // Two frictionless antipodal contacts, force along the line: s* = B (one finger pushes B).
  Grasp<2, FrictionlessPoint, S> p;
  REQUIRE(p.set(0, on_sphere<S>(pi / 2, 0, 0)) == Status::Ok);
  REQUIRE(p.set(1, on_sphere<S>(pi / 2, pi, 0)) == Status::Ok);
  Wrench<S> dx = Wrench<S>::Zero();
  dx(0) = S(1);
  // As above with B = 4, s* = 4: stop * (4 + 4) + 4 u of s*. Observed 3.4e-7 (double) and
  // 3.4e-5 (float), against 8e-6 and 8e-4.
  CHECK(std::abs(double(max_resistible_wrench(p, dx, S(4)).scale) - 4.0) <=
        stop * (4 + 4) + grip_test::roundoff<S>(4, 1, 4));
  // ... and nothing along y.
  Wrench<S> dy = Wrench<S>::Zero();
  dy(1) = S(1);
  // s* = 0: no forces along the normals make a force along y at all (G x = -s d has no
  // solution for s > 0), so the method returns a certificate and the scale is 0 exactly.
  const auto ry = max_resistible_wrench(p, dy, S(4));
  CHECK(ry.status == Status::Ok);
  CHECK(ry.scale == S(0));
  CHECK(ry.forces.norm() == S(0));
  // Bad input.
  CHECK(max_resistible_wrench(g, Wrench<S>(Wrench<S>::Zero()), S(1)).status == Status::InvalidInput);
  CHECK(max_resistible_wrench(g, d, S(-1)).status == Status::InvalidInput);
  // Settings that cannot be used, refused alike by both analyses (valid_settings).
  for (const S tol : {S(0), S(-1), std::numeric_limits<S>::infinity(), std::numeric_limits<S>::quiet_NaN()}) {
    ConicAnalysisSettings<S> bad;
    bad.tolerance = tol;
    CHECK_FALSE(valid_settings(bad));
    CHECK(max_resistible_wrench(g, d, S(4), bad).status == Status::InvalidInput);
    CHECK(force_closure(g, bad).status == Status::InvalidInput);
  }
  ConicAnalysisSettings<S> no_steps;
  no_steps.max_iterations = 0;
  CHECK(max_resistible_wrench(g, d, S(4), no_steps).status == Status::InvalidInput);
  CHECK(force_closure(g, no_steps).status == Status::InvalidInput);
  CHECK(valid_settings(ConicAnalysisSettings<S>{}));
  Grasp<3, HardFinger, S> empty;
  CHECK(force_closure(empty).status == Status::InvalidInput);
}

TEST_CASE_TEMPLATE("IterationLimit: an iteration bound that bites still bounds the optimum", S, double, float) {
  // The symmetric grasps above converge in a few iterations, so a lopsided grasp and load
  // direction, each cut answer against the same method's converged one.
  Grasp<3, HardFinger, S> h;
  REQUIRE(h.set(0, on_sphere<S>(pi / 2, 0.0, 0.5)) == Status::Ok);
  REQUIRE(h.set(1, on_sphere<S>(pi / 2 + 0.3, 2.1, 0.4)) == Status::Ok);
  REQUIRE(h.set(2, on_sphere<S>(pi / 2 - 0.2, 4.0, 0.6)) == Status::Ok);
  const double stop = double(ConicAnalysisSettings<S>{}.tolerance);
  ConicAnalysisSettings<S> few;
  few.max_iterations = 2;
  // Closure: the default needs more than 2 steps, so the bound must bite.
  const auto full = force_closure(h);
  REQUIRE(full.status == Status::Ok);
  REQUIRE(full.closure);
  REQUIRE(full.iterations > few.max_iterations);
  const auto cut = force_closure(h, few);
  CHECK(cut.status == Status::IterationLimit);
  CHECK(cut.iterations <= few.max_iterations);
  CHECK_FALSE(cut.closure);  // undecided is not closure
  // An upper bound: the cut's margin is the bound its multipliers give (>= the optimum), the
  // converged one a witnessed lower bound (<= the optimum), so only their roundings to S part
  // them: k = 4 of
  // 1 + margin. Observed 4.8e-3 above the converged margin in both types.
  CHECK(double(cut.margin) >= double(full.margin) - grip_test::roundoff<S>(4, 1, 1 + double(full.margin)));
  // The largest resistible wrench along d with a budget of 10 N: an upper bound, forces in
  // the cones.
  Wrench<S> d = Wrench<S>::Zero();
  d << S(0.3), S(-0.2), S(-1), S(0.01), S(0), S(-0.02);
  const auto wfull = max_resistible_wrench(h, d, S(10));
  REQUIRE(wfull.status == Status::Ok);
  REQUIRE(wfull.iterations > few.max_iterations);
  const auto wcut = max_resistible_wrench(h, d, S(10), few);
  CHECK(wcut.status == Status::IterationLimit);
  // An upper bound (from the multipliers' direction), the converged scale within
  // stop * (B + s*) of the optimum (as above). Observed 0.024 above the converged scale in both
  // types.
  CHECK(double(wcut.scale) >=
        double(wfull.scale) - stop * (10 + double(wfull.scale)) - grip_test::roundoff<S>(4, 1, double(wfull.scale)));
  CHECK(wcut.forces.allFinite());
  CHECK(inside_cones(h, wcut.forces, 0.0, cone_roundoff(h, wcut.forces, 0.0)));  // observed inside by 0.017
}

TEST_CASE_TEMPLATE("out of closure with internal forces: the unresisted direction meets its definition", S, double,
                   float) {
  // Four hard fingers, mu = 0.3, on the lower cap of a sphere (30 degrees from the bottom pole,
  // 90 degrees apart): every inward normal points 60 degrees above the horizontal and every cone
  // (half-angle atan 0.3 = 16.7 degrees) lies above it, so the fingers cannot pull the object
  // down: no closure. Internal forces exist (12 unknowns, rank 6), e.g. a squeeze along a chord,
  // with normal forces summing to 1, but the chord leaves the cones: the margin is negative and
  // finite, and the dual's u must have G_i^T u in every dual cone.
  Grasp<4, HardFinger, S> g;
  for (int i = 0; i < 4; ++i) REQUIRE(g.set(i, on_sphere<S>(5 * pi / 6, pi / 2 * i + 0.2, 0.3)) == Status::Ok);
  const auto f = force_closure(g);
  REQUIRE(f.status == Status::Ok);
  CHECK_FALSE(f.closure);
  CHECK(f.rank == 6);
  CHECK(f.margin < S(0));
  CHECK(f.margin > cone_margin_floor<S>());
  CHECK(double(f.unresisted.norm()) == doctest::Approx(1.0).epsilon(grip_test::roundoff<S>(8, 1, 1)));
  CHECK(dual_certificate(g, f.unresisted, certificate_tolerance<S>()));
  // The internal force achieves the margin: x_i - margin a_i in K_i, G x = 0 (as in closure).
  CHECK(double(f.residual) <= grip_test::roundoff<S>(4, 1, 1));
  CHECK(inside_cones(g, f.internal_force, double(f.margin), cone_roundoff(g, f.internal_force, double(f.margin))));
}

TEST_CASE_TEMPLATE("no internal force at all: the infeasible margin problem's certificate is unresisted", S, double,
                   float) {
  const ConicAnalysisSettings<S> settings;
  const double tol = certificate_tolerance<S>();
  // Six frictionless points of generic position: G is 6 x 6 of rank 6, so G x = 0 only for
  // x = 0 and no internal force has normal forces summing to 1: the margin problem has no
  // feasible point. Force closure must say no, with the margin cone_margin_floor(), no internal
  // force, and an unresisted wrench u: a_i . u_f + (r_i x a_i) . u_m >= 0 for every contact.
  std::mt19937 rng(11);
  grip_test::Uniform u(0.0, 1.0);
  int certified = 0;
  for (int rep = 0; rep < 20; ++rep) {
    Grasp<6, FrictionlessPoint, S> g;
    for (int i = 0; i < 6; ++i) {
      const double th = std::acos(1 - 2 * u(rng)), ph = 2 * pi * u(rng);
      const Vector3<double> r(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const Vector3<double> t(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      Contact<S> c;
      c.position = (0.05 * r).cast<S>();
      c.normal = (-r + 0.4 * t).normalized().cast<S>();
      c.squeeze = S(1);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    const auto f = force_closure(g, settings);
    REQUIRE(f.status == Status::Ok);
    CHECK_FALSE(f.closure);
    if (f.rank < 6) continue;
    ++certified;
    CHECK(f.margin == cone_margin_floor<S>());
    CHECK(f.internal_force.norm() == S(0));
    CHECK(f.iterations < settings.max_iterations);
    CHECK(double(f.unresisted.norm()) == doctest::Approx(1.0).epsilon(grip_test::roundoff<S>(8, 1, 1)));
    CHECK(dual_certificate(g, f.unresisted, tol));
  }
  CHECK(certified > 0);
  // Two soft fingers whose inward normals make the same angle with the line d through them
  // (a_1 . d = a_2 . d = 1/2, mu = 0.5, mu_t = 1 cm): rank 6 (the torsions' moments have parts
  // along d), but an internal force has f_2 = -f_1, so sum e.x = (a_1 - a_2) . f_1; its moments
  // (r_1 - r_2) x f_1 + m_1 a_1 + m_2 a_2 = 0 along d give m_2 = -m_1, then
  // l d x f_1 = m_1 (a_1 - a_2) (l = |r_2 - r_1|), so f_1 = s d + (m_1 / l)(a_1 - a_2) x d, and
  // both parts are orthogonal to a_1 - a_2 (which is orthogonal to d): sum e.x = 0 for every
  // internal force.
  Grasp<2, SoftFinger, S> two;
  const double c60 = 0.5, s60 = std::sqrt(3.0) / 2;
  Contact<S> c1, c2;
  c1.position = Vector3<double>(-0.03, 0.01, 0.0).cast<S>();
  c2.position = Vector3<double>(0.03, 0.01, 0.0).cast<S>();
  c1.normal = Vector3<double>(c60, s60, 0.0).cast<S>();
  c2.normal = Vector3<double>(c60, -s60, 0.0).cast<S>();
  for (Contact<S>* c : {&c1, &c2}) {
    c->friction = S(0.5);
    c->torsional_friction = S(0.01);
  }
  REQUIRE(two.set(0, c1) == Status::Ok);
  REQUIRE(two.set(1, c2) == Status::Ok);
  const auto ft = force_closure(two, settings);
  REQUIRE(ft.status == Status::Ok);
  CHECK_FALSE(ft.closure);
  CHECK(ft.rank == 6);
  CHECK(ft.margin == cone_margin_floor<S>());
  CHECK(ft.internal_force.norm() == S(0));
  CHECK(double(ft.unresisted.norm()) == doctest::Approx(1.0).epsilon(grip_test::roundoff<S>(8, 1, 1)));
  CHECK(dual_certificate(two, ft.unresisted, tol));
  // Settings: tolerance finite and > 0, at least one iteration.
  ConicAnalysisSettings<S> bad;
  bad.max_iterations = -1;
  CHECK_FALSE(valid_settings(bad));
}

template struct grip::ForceClosure<Grasp<Dynamic, SoftFinger, float, 5>>;
template struct grip::ResistibleWrench<Grasp<4, FrictionlessPoint, double>>;
template struct grip::ConicAnalysisSettings<float>;
