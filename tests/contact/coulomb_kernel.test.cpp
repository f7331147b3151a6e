// The vectorised Coulomb pass (contact/coulomb_kernel.hpp) behind StabilityMonitor::classify()
// and solve_constrained's fast path: the pass this translation unit dispatches to (CMake builds
// this file again as grip_tests_native with -march=native for AVX-512, and as grip_tests_avx2
// for the AVX2 pass) against the portable loop and against an independent per-contact rule
// written from the cone's own interface. Block tails (every size from 1 to the capacity), the
// compile-time-size path, invalid values at every position.
#include <doctest/doctest.h>

#include <array>
#include <limits>
#include <random>

#include <grip/contact/coulomb_cone.hpp>
#include <grip/contact/coulomb_kernel.hpp>
#include <grip/monitor/stability_monitor.hpp>

#include "support/allocation_counter.hpp"
#include "support/cone_sampling.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using namespace grip;

namespace {

// The rule the kernel implements, from CoulombCone's interface and the monitor's slack.
template <class S>
ContactMode rule_mode(const Contact<S>& c, const Vector3<S>& x, S abs_tol, S rel_tol) {
  const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
  const S fn = cone.normal_part(x);
  if (!(fn > S(0))) return ContactMode::Separating;
  return cone.slips(x, abs_tol + rel_tol * fn) ? ContactMode::Sliding : ContactMode::Sticking;
}

// True when x lies within round-off of the slip boundary |t| = mu f_n + slack, where two
// correct evaluations may round to different modes.
template <class S>
bool near_boundary(const Contact<S>& c, const Vector3<S>& x, S abs_tol, S rel_tol) {
  const Vector3<double> xd = x.template cast<double>(), a = c.normal.template cast<double>();
  const double fn = xd.dot(a), t = (xd - fn * a).norm();
  const double lim = double(c.friction) * fn + double(abs_tol) + double(rel_tol) * fn;
  return std::abs(t - lim) <= 1e3 * double(std::numeric_limits<S>::epsilon()) * (1.0 + xd.norm()) ||
         std::abs(fn) <= 1e3 * double(std::numeric_limits<S>::epsilon()) * xd.norm();
}

// A force of one of several kinds around contact c's cone, in double.
Vector3<double> mixed_force(std::mt19937& rng, const Vector3<double>& a, double mu, int kind) {
  grip_test::Uniform u01(0.0, 1.0);
  const Vector3<double> t = grip_test::random_tangent(rng, a);
  const double fn = 0.1 + 5.0 * u01(rng);
  switch (kind) {
    case 0: return grip_test::random_force(rng, a, -2.0, 5.0, 5.0);         // anything
    case 1: return fn * a + 0.5 * mu * fn * t;                              // well inside
    case 2: return fn * a + (1.5 * mu * fn + 0.1) * t;                      // well outside
    case 3: return fn * a;                                                  // on the axis (mu = 0 too)
    case 4: return Vector3<double>::Zero();                                 // separating: zero force
    case 5: return -fn * a + 0.3 * t;                                       // pulling
    default: return 1e6 * grip_test::random_force(rng, a, -1.0, 1.0, 1.0);  // large
  }
}

template <class G>
void check_pass(std::mt19937& rng, int n, int trials, typename G::ScalarType abs_tol = typename G::ScalarType(1e-6),
                typename G::ScalarType rel_tol = ScalarTraits<typename G::ScalarType>::default_tolerance) {
  using S = typename G::ScalarType;
  constexpr int fixed = G::fixed_size > 0 ? G::fixed_size : 0;
  int compared = 0, kinds[3] = {0, 0, 0};
  for (int trial = 0; trial < trials; ++trial) {
    G g = grip_test::random_grasp<G>(rng, n);
    if (trial % 4 == 0) {  // some frictionless contacts: the ray mu = 0
      Contact<S> c = g.contact(0);
      c.friction = S(0);
      REQUIRE(g.set(0, c) == Status::Ok);
    }
    typename G::ForceVector x(g.unknowns());
    for (int i = 0; i < n; ++i)
      x.template segment<3>(3 * i) =
          mixed_force(rng, g.contact(i).normal.template cast<double>(), double(g.contact(i).friction), (trial + i) % 7)
              .template cast<S>();
    std::array<ContactMode, G::capacity> fast{}, portable{};
    grip_test::NoHeapScope scope;
    const detail::CoulombCounts cf = detail::classify_coulomb<fixed>(detail::cone_rows(g.contacts()),
                                                                     detail::cone_row_stride<typename G::ScalarType>,
                                                                     x.data(), n, abs_tol, rel_tol, fast.data());
    const detail::CoulombCounts cp = detail::classify_coulomb_portable(detail::cone_rows(g.contacts()),
                                                                       detail::cone_row_stride<typename G::ScalarType>,
                                                                       x.data(), n, abs_tol, rel_tol, portable.data());
    CHECK(scope.allocations() == 0);
    CHECK(cf.invalid == 0);
    CHECK(cp.invalid == 0);
    int sliding = 0, separating = 0, skipped = 0;
    for (int i = 0; i < n; ++i) {
      const Vector3<S> xi = x.template segment<3>(3 * i);
      const ContactMode want = rule_mode(g.contact(i), xi, abs_tol, rel_tol);
      sliding += want == ContactMode::Sliding;
      separating += want == ContactMode::Separating;
      if (near_boundary(g.contact(i), xi, abs_tol, rel_tol)) {
        ++skipped;
        continue;
      }
      ++compared;
      ++kinds[static_cast<int>(want)];
      CHECK(fast[static_cast<std::size_t>(i)] == want);
      CHECK(portable[static_cast<std::size_t>(i)] == want);
    }
    if (skipped == 0) {
      CHECK(cf.sliding == sliding);
      CHECK(cf.separating == separating);
      CHECK(cp.sliding == sliding);
      CHECK(cp.separating == separating);
    }
    // The monitor on top of the same pass: its modes, counts and verdict.
    const GraspModes<G> modes = StabilityMonitor<G>(MonitorSettings<S>{abs_tol, rel_tol}).classify(g, x);
    REQUIRE(modes.ok());
    CHECK(modes.size() == n);
    for (int i = 0; i < n; ++i) CHECK(modes.mode(i) == fast[static_cast<std::size_t>(i)]);
    CHECK(modes.sliding_count == cf.sliding);
    CHECK(modes.separating_count == cf.separating);
    CHECK(modes.sticking_count == n - cf.sliding - cf.separating);
    CHECK(modes.stable == (cf.sliding + cf.separating == 0));
  }
  CHECK(compared > trials * n * 3 / 4);
  CHECK(kinds[0] > 0);
  CHECK(kinds[1] > 0);
  CHECK(kinds[2] > 0);
}

}  // namespace

TEST_CASE_TEMPLATE("Coulomb kernel: every size and block tail agrees with the cone's own rule", S, double, float) {
  MESSAGE("contacts per step of the double pass: " << coulomb_kernel_lanes);
  std::mt19937 rng(2024);
  for (int n = 1; n <= 19; ++n) check_pass<Grasp<Dynamic, HardFinger, S, 19>>(rng, n, 20);
  check_pass<Grasp<20, HardFinger, S>>(rng, 20, 200);  // compile-time size: unrolled blocks
  check_pass<Grasp<8, HardFinger, S>>(rng, 8, 100);    // exactly one block
  check_pass<Grasp<1, HardFinger, S>>(rng, 1, 100);
  for (int n : {21, 29, 32, 37, 40}) check_pass<Grasp<Dynamic, HardFinger, S, 40>>(rng, n, 10);
}

TEST_CASE_TEMPLATE("Coulomb kernel: negative tolerances (a stricter monitor) follow the same rule", S, double, float) {
  // The limit (mu + relative_tolerance) f_n + absolute_tolerance can then be negative while
  // f_n > 0, which the SIMD pass tests by its sign (t^2 > lim |lim|) instead of lim^2.
  std::mt19937 rng(2025);
  for (int n : {3, 8, 13, 20}) {
    check_pass<Grasp<Dynamic, HardFinger, S, 20>>(rng, n, 40, S(-0.05), S(0));
    check_pass<Grasp<Dynamic, HardFinger, S, 20>>(rng, n, 40, S(0), S(-0.05));
    check_pass<Grasp<Dynamic, HardFinger, S, 20>>(rng, n, 40, S(0.05), S(-0.02));
  }
}

TEST_CASE_TEMPLATE("Coulomb kernel: NaN, Inf and huge components are found at every position", S, double, float) {
  using G = Grasp<Dynamic, HardFinger, S, 19>;
  std::mt19937 rng(7);
  const S big = ScalarTraits<S>::max_magnitude;
  const S bad_values[] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                          -std::numeric_limits<S>::infinity(), S(2) * big, -S(2) * big};
  const StabilityMonitor<G> monitor;
  for (int n : {1, 7, 8, 9, 16, 17, 19}) {
    const G g = grip_test::random_grasp<G>(rng, n);
    typename G::ForceVector x(g.unknowns());
    for (int i = 0; i < n; ++i)
      x.template segment<3>(3 * i) =
          grip_test::random_force(rng, g.contact(i).normal.template cast<double>(), -1.0, 5.0, 3.0).template cast<S>();
    GraspModes<G> modes;
    monitor.classify(g, x, modes);
    REQUIRE(modes.ok());
    // A force longer than max_magnitude whose components all lie within it is valid: the
    // SIMD pass's cheap test on |x|^2 must hand it to the exact check, in every position.
    for (int i = 0; i < n; ++i) {
      const Vector3<S> keep = x.template segment<3>(3 * i);
      x.template segment<3>(3 * i) = Vector3<S>(S(0.9) * big, -S(0.9) * big, S(0.9) * big);
      std::array<ContactMode, G::capacity> m{};
      CHECK(detail::classify_coulomb<0>(detail::cone_rows(g.contacts()),
                                        detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                        ScalarTraits<S>::default_tolerance, m.data())
                .invalid == 0);
      monitor.classify(g, x, modes);
      CHECK(modes.ok());
      x.template segment<3>(3 * i) = keep;
    }
    // Exactly max_magnitude is still valid, in every position.
    for (int k = 0; k < 3 * n; ++k) {
      const S keep = x(k);
      x(k) = -big;
      monitor.classify(g, x, modes);
      CHECK(modes.ok());
      CHECK(modes.size() == n);
      x(k) = keep;
    }
    for (S bad : bad_values) {
      for (int k = 0; k < 3 * n; ++k) {
        const S keep = x(k);
        x(k) = bad;
        std::array<ContactMode, G::capacity> m{};
        CHECK(detail::classify_coulomb<0>(detail::cone_rows(g.contacts()),
                                          detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                          ScalarTraits<S>::default_tolerance, m.data())
                  .invalid > 0);
        CHECK(detail::classify_coulomb_portable(detail::cone_rows(g.contacts()),
                                                detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                                ScalarTraits<S>::default_tolerance, m.data())
                  .invalid > 0);
        monitor.classify(g, x, modes);
        CHECK(modes.status == Status::InvalidInput);
        CHECK(modes.size() == 0);
        CHECK_FALSE(modes.stable);
        x(k) = keep;
      }
    }
  }
}

TEST_CASE("Coulomb kernel: values past the last contact are never read as forces") {
  // The forces vector of a Dynamic grasp is followed by storage the kernel must mask out:
  // fill it with NaN and check that a valid prefix stays valid.
  using G = Grasp<Dynamic, HardFinger, double, 24>;
  std::mt19937 rng(11);
  for (int n = 1; n <= 23; ++n) {
    const G g = grip_test::random_grasp<G>(rng, n);
    std::array<double, 3 * 24> buffer;
    buffer.fill(std::numeric_limits<double>::quiet_NaN());
    for (int i = 0; i < n; ++i) {
      const Vector3<double> f = grip_test::random_force(rng, g.contact(i).normal, 0.5, 5.0, 1.0);
      for (int k = 0; k < 3; ++k) buffer[static_cast<std::size_t>(3 * i + k)] = f(k);
    }
    std::array<ContactMode, 24> m{};
    m.fill(ContactMode::Sliding);
    const detail::CoulombCounts c =
        detail::classify_coulomb<0>(detail::cone_rows(g.contacts()), detail::cone_row_stride<typename G::ScalarType>,
                                    buffer.data(), n, 0.0, 1e-9, m.data());
    CHECK(c.invalid == 0);
    for (int i = n; i < 24; ++i) CHECK(m[static_cast<std::size_t>(i)] == ContactMode::Sliding);  // untouched
  }
}

namespace {

// coulomb_all_inside (dispatched and portable) on a grasp of type G with n contacts: all forces
// well inside their cones -> true; then one contact at each position in turn made to slide,
// pull, separate at zero force, or carry a NaN -> false. Against the cone's own rule.
template <class G>
void check_all_inside(std::mt19937& rng, int n) {
  using S = typename G::ScalarType;
  constexpr int fixed = G::fixed_size > 0 ? G::fixed_size : 0;
  const G g = grip_test::random_grasp<G>(rng, n);
  typename G::ForceVector x(g.unknowns());
  for (int i = 0; i < n; ++i)
    x.template segment<3>(3 * i) =
        mixed_force(rng, g.contact(i).normal.template cast<double>(), double(g.contact(i).friction), 1)
            .template cast<S>();
  const auto rule = [&](const typename G::ForceVector& f) {
    bool all = true;
    // i < G::capacity, a bound g++ 12 -O3 sees: without it, it reports a read past the grasp
    // on a path it cannot rule out (-Warray-bounds, a false positive).
    for (int i = 0; i < n && i < G::capacity; ++i) {
      const CoulombCone<S> cone = CoulombCone<S>::from_contact(g.contact(i));
      const Vector3<S> xi = f.template segment<3>(3 * i);
      all = all && cone.normal_part(xi) > S(0) && !cone.slips(xi, S(0));
    }
    return all;
  };
  const auto fast = [&](const typename G::ForceVector& f) {
    return detail::coulomb_all_inside<fixed>(detail::cone_rows(g.contacts()),
                                             detail::cone_row_stride<typename G::ScalarType>, f.data(), n);
  };
  const auto portable = [&](const typename G::ForceVector& f) {
    return detail::coulomb_all_inside_portable(detail::cone_rows(g.contacts()),
                                               detail::cone_row_stride<typename G::ScalarType>, f.data(), n);
  };
  REQUIRE(rule(x));
  CHECK(fast(x));
  CHECK(portable(x));
  CHECK(detail::coulomb_all_inside_grasp(g, x));
  for (int i = 0; i < n; ++i) {
    const Vector3<S> keep = x.template segment<3>(3 * i);
    const Vector3<double> a = g.contact(i).normal.template cast<double>();
    const double mu = double(g.contact(i).friction);
    for (int kind : {2, 4, 5, 7}) {
      if (kind == 7)
        x.template segment<3>(3 * i) = Vector3<S>(S(1), std::numeric_limits<S>::quiet_NaN(), S(1));
      else
        x.template segment<3>(3 * i) = mixed_force(rng, a, mu, kind).template cast<S>();
      if (kind != 7) CHECK_FALSE(rule(x));
      CHECK_FALSE(fast(x));
      CHECK_FALSE(portable(x));
    }
    // Just inside the boundary (|t| = 0.999 mu f_n) stays inside; mu = 0 needs t = 0 exactly.
    const double fn = 2.0;
    const Vector3<double> t = grip_test::random_tangent(rng, a);
    x.template segment<3>(3 * i) = (fn * a + 0.999 * mu * fn * t).template cast<S>();
    if (mu > 0.01) {
      CHECK(rule(x));
      CHECK(fast(x));
      CHECK(portable(x));
    }
    x.template segment<3>(3 * i) = keep;
  }
  CHECK(fast(x));  // restored
}

}  // namespace

TEST_CASE_TEMPLATE("Coulomb kernel: the fast path's all-inside test finds one outside contact at any position", S,
                   double, float) {
  std::mt19937 rng(31);
  for (int n = 1; n <= 40; ++n) check_all_inside<Grasp<Dynamic, HardFinger, S, 40>>(rng, n);
  check_all_inside<Grasp<1, HardFinger, S>>(rng, 1);
  check_all_inside<Grasp<3, HardFinger, S>>(rng, 3);
  check_all_inside<Grasp<8, HardFinger, S>>(rng, 8);
  check_all_inside<Grasp<20, HardFinger, S>>(rng, 20);
  // No heap.
  using G = Grasp<20, HardFinger, S>;
  const G g = grip_test::random_grasp<G>(rng, 20);
  const typename G::ForceVector x = G::ForceVector::Zero();
  grip_test::NoHeapScope scope;
  CHECK_FALSE(detail::coulomb_all_inside_grasp(g, x));  // zero forces separate
  CHECK(scope.allocations() == 0);
}
