// solve_constrained's hard-finger pass over columns (solve/detail/coulomb_pass.hpp) against the
// contact-by-contact pass (detail::constrained_pass through coulomb_project_accumulate, itself
// checked against CoulombCone::project and projection_jacobian in solve_constrained.test.cpp):
// forces, every sum, and the Hessian, for every size from 1 to 40 (block tails), compile-time
// sizes, multipliers of every scale (all three regions), mu = 0, and overflowing v. CMake
// builds this file again with -march=native and with AVX2 (see tests/CMakeLists.txt), so each
// SIMD pack runs against the same reference.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include <grip/solve/detail/coulomb_pass.hpp>
#include <grip/solve/projection_jacobian.hpp>
#include <grip/solve/solve_constrained.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

// The tolerances of one pass from round-off (support/tolerance.hpp), in double from the grasp,
// lambda and the reference's forces. They bound the difference of any two evaluations of the
// pass in one scalar type that round differently (the order of the sums, SIMD lanes, FMAs):
// condition 1 throughout, as the projection onto a cone is 1-Lipschitz and every other value is
// a sum whose terms are bounded below. Observed at most 0.13 of them in both types.
struct PassTolerance {
  std::vector<double> x;  // per contact, N
  double residual = 0, f2 = 0, scale = 0, dual = 0, hessian = 0;
};

template <class GraspT, class Vec>
PassTolerance pass_tolerance(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w_ext,
                             const Wrench<typename GraspT::ScalarType>& lambda, const Vec& x_ref) {
  using S = typename GraspT::ScalarType;
  const int n = g.size();
  // 1-norms, which bound the 2-norms and stay finite for a lambda near the largest double.
  const Wrench<double> l = lambda.template cast<double>();
  const double lf = l.template head<3>().template lpNorm<1>(), lm = l.template tail<3>().template lpNorm<1>();
  PassTolerance t;
  // The sums of |terms| of the residual w_ext + sum G_i x_i, of F2 = 1/2 sum w_i |x_i - t_i|^2,
  // of |x|, and of the Hessian sum k_i G_i J_i G_i^T (|J_i| <= 1, |G_i|^2 <= 1 + |r_i|^2, and a
  // 6 x 6 Frobenius norm within sqrt(6) of the 2-norm); then what each force's difference
  // carries into them.
  double res_terms = double(w_ext.norm()), f2_terms = 0, x2 = 0, h_terms = 0, res_prop = 0, f2_prop = 0, x_prop = 0;
  for (int i = 0; i < n; ++i) {
    const auto& c = g.contact(i);
    const Vector3<S> v = HardFinger::target(c) + g.inverse_weight(i) * HardFinger::wrench_transpose(c, lambda);
    if (!detail::cone_input_valid(v)) {  // v beyond max_magnitude: x_i = 0 exactly in both, no term
      t.x.push_back(0);
      continue;
    }
    const double r = double(c.position.norm()), k = double(g.inverse_weight(i));
    const Vector3<double> xi = x_ref.template segment<3>(3 * i).template cast<double>();
    const Vector3<double> ti = HardFinger::target(c).template cast<double>();
    // x_i: v = s a + k (l_f - r x l_m) takes 4 roundings of its terms, of size
    // |s| + k (|l_f| + |r| |l_m|); the projection (n = v.a, t = v - n a, |t|, sn = (n + mu |t|)
    // ku, beta = sn mu / |t| <= 1, x = sn a + beta t) about 10 of |v|; each pass as many: k = 32.
    t.x.push_back(grip_test::roundoff<S>(32, 1, std::abs(double(c.squeeze)) + k * (lf + r * lm)));
    res_terms += (1 + r) * xi.norm();
    f2_terms += 0.5 * double(c.weight) * (xi - ti).squaredNorm();
    x2 += xi.squaredNorm();
    h_terms += k * (1 + r * r);
    res_prop += (1 + r) * t.x.back();
    f2_prop += double(c.weight) * ((xi - ti).norm() + t.x.back()) * t.x.back();
    x_prop += t.x.back();
  }
  // Each sum: n + 4 roundings of its terms (the reference adds contact by contact, recursive
  // summation's (n - 1) u bound; the table by lanes, then across them; the terms' own few).
  const double ks = n + 4;
  t.residual = grip_test::roundoff<S>(ks, 1, res_terms) + res_prop;
  t.f2 = grip_test::roundoff<S>(ks, 1, f2_terms) + f2_prop;
  t.scale = grip_test::roundoff<S>(ks, 1, double(w_ext.norm()) + std::sqrt(x2)) + x_prop;
  // dual = F2 - lambda . residual: both errors, and the dot product's 6 roundings of |l| |res|.
  const double ln = l.template lpNorm<1>();
  t.dual = t.f2 + ln * t.residual + grip_test::roundoff<S>(8, 1, ln * res_terms);
  // The Hessian's terms take about 16 roundings each (g_b, g_d, and e = t / |t| within a few u
  // times 1 + 1 / mu, mu >= 0.2 here, or 0 where mu = 0), then the sum's n + 4.
  t.hessian = grip_test::roundoff<S>(ks + 16, 1, std::sqrt(6.0) * h_terms);
  return t;
}

// The regions of the reference: 0 interior, 1 boundary part, 2 polar (or invalid v).
template <class S>
int region_of(const Contact<S>& c, S k, const Wrench<S>& lambda) {
  const Vector3<S> v = HardFinger::target(c) + k * HardFinger::wrench_transpose(c, lambda);
  if (!detail::cone_input_valid(v)) return 2;
  const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
  const auto j = projection_jacobian(cone, v, detail::project_onto(cone, v));
  return j.region == ProjectionRegion::Interior ? 0 : j.region == ProjectionRegion::Boundary ? 1 : 2;
}

// Compares one pass of the table with the reference at lambda; counts the reference's regions.
template <class GraspT>
void compare_pass(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w_ext,
                  const Wrench<typename GraspT::ScalarType>& lambda, int* regions) {
  using S = typename GraspT::ScalarType;
  const detail::CoulombPassTable<GraspT> table(g);
  REQUIRE(table.rows() % detail::CoulombPassTable<GraspT>::block == 0);
  REQUIRE(table.rows() >= g.size());
  REQUIRE(table.rows() < g.size() + detail::CoulombPassTable<GraspT>::block);
  auto cols = table.make_forces();
  Matrix6<S> h;
  GramAccumulator<S> h_ref;
  const detail::ConstrainedPass<S> p = table.pass(w_ext, lambda, cols, h);
  typename GraspT::ForceVector x(g.unknowns()), x_ref(g.unknowns());
  table.store(cols, x);
  const detail::ConstrainedPass<S> q = detail::constrained_pass(g, w_ext, lambda, x_ref, &h_ref);
  // The padding rows stay inert: zero forces.
  for (int i = g.size(); i < table.rows(); ++i) CHECK((cols.x(i) == S(0) && cols.y(i) == S(0) && cols.z(i) == S(0)));
  const PassTolerance tol = pass_tolerance(g, w_ext, lambda, x_ref);
  for (int i = 0; i < g.size(); ++i) {
    ++regions[region_of(g.contact(i), g.inverse_weight(i), lambda)];
    CAPTURE(i);
    CHECK(double((x.template segment<3>(3 * i) - x_ref.template segment<3>(3 * i)).norm()) <= tol.x[std::size_t(i)]);
  }
  CHECK(double((p.residual - q.residual).norm()) <= tol.residual);
  CHECK(std::abs(double(p.f2 - q.f2)) <= tol.f2);
  CHECK(std::abs(double(p.scale - q.scale)) <= tol.scale);
  CHECK(std::abs(double(p.dual - q.dual)) <= tol.dual);
  const Matrix6<S> m = h, m_ref = h_ref.matrix();
  CHECK(double((m - m_ref).norm()) <= tol.hessian);
  CHECK(double((m - m.transpose()).norm()) == 0.0);
}

template <class S>
Wrench<S> random_lambda(std::mt19937& rng, double scale) {
  grip_test::Normal n01(0.0, 1.0);
  Wrench<S> l;
  for (int r = 0; r < 6; ++r) l(r) = S(scale * n01(rng) * (r < 3 ? 1.0 : 20.0));
  return l;
}

}  // namespace

TEST_CASE_TEMPLATE("coulomb pass: columns against the contact-by-contact pass, sizes 1 to 40", S, double, float) {
  std::mt19937 rng(71);
  int regions[3] = {0, 0, 0};
  const double scales[4] = {0.1, 1.0, 10.0, 100.0};
  for (int n = 1; n <= 40; ++n) {
    auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 40>>(rng, n);
    // A few frictionless-like (mu = 0: the ray) and squeeze-free contacts.
    for (int i = 0; i < n; i += 5) {
      Contact<S> c = g.contact(i);
      c.friction = S(0);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    for (int i = 2; i < n; i += 7) {
      Contact<S> c = g.contact(i);
      c.squeeze = S(0);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    for (double sc : scales) {
      CAPTURE(n);
      CAPTURE(sc);
      compare_pass(g, grip_test::random_wrench<S>(rng), random_lambda<S>(rng, sc), regions);
    }
  }
  MESSAGE("regions (interior, boundary, polar): " << regions[0] << ", " << regions[1] << ", " << regions[2]);
  CHECK(regions[0] > 200);
  CHECK(regions[1] > 200);
  CHECK(regions[2] > 200);
}

TEST_CASE_TEMPLATE("coulomb pass: compile-time sizes 1, 8 and 20", S, double, float) {
  std::mt19937 rng(72);
  int regions[3] = {0, 0, 0};
  for (int rep = 0; rep < 20; ++rep) {
    const double sc = rep % 2 == 0 ? 1.0 : 30.0;
    compare_pass(grip_test::random_grasp<Grasp<1, HardFinger, S>>(rng, 1), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
    compare_pass(grip_test::random_grasp<Grasp<8, HardFinger, S>>(rng, 8), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
    compare_pass(grip_test::random_grasp<Grasp<20, HardFinger, S>>(rng, 20), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
  }
  CHECK(regions[0] > 20);
  CHECK(regions[1] > 20);
}

TEST_CASE_TEMPLATE("coulomb pass: v beyond max_magnitude projects to zero with no Hessian term", S, double, float) {
  // One multiplier component near the largest finite value: v overflows (or exceeds
  // max_magnitude) for every contact, as in the reference; the sums stay finite.
  std::mt19937 rng(73);
  const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 24>>(rng, 13);
  for (int r = 0; r < 6; ++r) {
    Wrench<S> l = Wrench<S>::Zero();
    l(r) = std::numeric_limits<S>::max() / S(4);
    const detail::CoulombPassTable<decltype(g)> table(g);
    auto cols = table.make_forces();
    Matrix6<S> h;
    const auto p = table.pass(Wrench<S>::Zero(), l, cols, h);
    typename decltype(g)::ForceVector x_ref(g.unknowns());
    GramAccumulator<S> h_ref;
    const auto q = detail::constrained_pass(g, Wrench<S>::Zero(), l, x_ref, &h_ref);
    CAPTURE(r);
    // Contacts whose lever arm has no component across the moment axis may keep a valid v, and
    // take pass_tolerance's round-off bounds; the others project to 0 exactly in both passes
    // and add nothing to the sums (a tolerance of 0). Here every v is beyond max_magnitude.
    const PassTolerance tol = pass_tolerance(g, Wrench<S>::Zero(), l, x_ref);
    for (int i = 0; i < g.size(); ++i) {
      const Vector3<S> xi(cols.x(i), cols.y(i), cols.z(i));
      CHECK(double((xi - x_ref.template segment<3>(3 * i)).norm()) <= tol.x[std::size_t(i)]);
    }
    CHECK(p.residual.allFinite());
    CHECK(std::isfinite(p.f2));
    CHECK(h.allFinite());
    CHECK(double((h - h_ref.matrix()).norm()) <= tol.hessian);
    CHECK(double((p.residual - q.residual).norm()) <= tol.residual);
  }
}

TEST_CASE("coulomb pass: first_break is where the first projection changes region") {
  // Independently of first_break's quadratics: each contact's region (projection_jacobian's,
  // from CoulombCone) sampled along lambda + alpha d. Before the break no contact changes
  // region; just past it (when it is before 1) one does. Random grasps, multipliers and
  // directions of every scale; mu = 0 contacts (no break of their own) among them.
  using S = double;
  std::mt19937 rng(72);
  int breaks = 0, none = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 12;
    auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 12>>(rng, n);
    if (trial % 3 == 0) {
      Contact<S> c = g.contact(0);
      c.friction = S(0);
      REQUIRE(g.set(0, c) == Status::Ok);
    }
    const detail::CoulombPassTable<decltype(g)> table(g);
    const Wrench<S> lambda = random_lambda<S>(rng, trial % 2 == 0 ? 1.0 : 10.0);
    const Wrench<S> d = random_lambda<S>(rng, trial % 4 < 2 ? 1.0 : 30.0);
    const S brk = table.first_break(lambda, d);
    REQUIRE(brk > S(0));
    REQUIRE(brk <= S(1));
    const auto regions = [&](S alpha) {
      std::vector<int> r;
      const Wrench<S> l = lambda + alpha * d;
      for (int i = 0; i < n; ++i) {
        const Contact<S>& c = g.contact(i);
        if (!(c.friction > S(0))) continue;  // the ray: no break of its own
        const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
        const Vector3<S> v = HardFinger::target(c) + g.inverse_weight(i) * HardFinger::wrench_transpose(c, l);
        r.push_back(static_cast<int>(projection_jacobian(cone, v, cone.project(v)).region));
      }
      return r;
    };
    // From just after the start to just before the break: one region per contact.
    const std::vector<int> start = regions(brk * S(1e-6));
    for (int k = 1; k <= 64; ++k) {
      CAPTURE(trial);
      CHECK(regions(brk * (S(1e-6) + (S(1) - S(2e-6)) * S(k) / S(64))) == start);
    }
    if (brk < S(1)) {
      ++breaks;
      CHECK(regions(brk * (S(1) + S(1e-6))) != regions(brk * (S(1) - S(1e-6))));
    } else {
      ++none;
    }
  }
  MESSAGE("breaks before 1: " << breaks << ", none: " << none);
  CHECK(breaks > 100);
  CHECK(none > 20);
}

TEST_CASE("second_trial: Newton's trial lands past the first kink, in the region entered") {
  // The kink itself is first_break's (checked above); here the trial point: some contact's
  // region at the trial differs from its region just before the kink, and the trial is within a
  // relative 2 sqrt(eps) of the kink. Beyond the halved step: the step.
  using S = double;
  std::mt19937 rng(73);
  const S root_eps = std::sqrt(std::numeric_limits<S>::epsilon());
  int kinks = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 12;
    const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 12>>(rng, n);
    const detail::CoulombPassTable<decltype(g)> table(g);
    const Wrench<S> lambda = random_lambda<S>(rng, trial % 2 == 0 ? 1.0 : 10.0);
    const Wrench<S> d = random_lambda<S>(rng, trial % 4 < 2 ? 1.0 : 30.0);
    const S brk = table.first_break(lambda, d);
    const S half = S(0.5);
    const S newton = detail::second_trial(table, lambda, d, half);
    CAPTURE(trial);
    if (!(brk < half)) {
      CHECK(newton == half);
      continue;
    }
    ++kinks;
    CHECK(newton > brk);
    CHECK(newton <= brk * (1 + 2 * root_eps));
    const auto regions = [&](S alpha) {
      std::vector<int> r;
      const Wrench<S> l = lambda + alpha * d;
      for (int i = 0; i < n; ++i) {
        const Contact<S>& c = g.contact(i);
        const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
        const Vector3<S> v = HardFinger::target(c) + g.inverse_weight(i) * HardFinger::wrench_transpose(c, l);
        r.push_back(static_cast<int>(projection_jacobian(cone, v, cone.project(v)).region));
      }
      return r;
    };
    CHECK(regions(newton) != regions(brk * (1 - 1e-6)));
  }
  CHECK(kinks > 100);
}

TEST_CASE("coulomb pass: no heap") {
  std::mt19937 rng(74);
  const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, double, 32>>(rng, 19);
  const Wrench<double> w = grip_test::random_wrench<double>(rng), l = random_lambda<double>(rng, 1.0);
  grip_test::NoHeapScope guard;
  const detail::CoulombPassTable<decltype(g)> table(g);
  auto cols = table.make_forces();
  Matrix6<double> h;
  const auto p = table.pass(w, l, cols, h);
  CHECK(guard.allocations() == 0);
  CHECK(std::isfinite(p.f2));
}
