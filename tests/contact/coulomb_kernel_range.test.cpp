// The range check of the Coulomb kernel (contact/coulomb_kernel.hpp) at its edge: every pass
// adds up f_n^2 + |t|^2 per contact and checks component by component only when that sum comes
// near max_magnitude^2. With a normal that is not quite unit (a Contact accepts |a|^2 within
// 2 normal_tolerance of 1) the sum falls short of |x|^2 by up to 2 normal_tolerance |x|^2, so a
// force along such a normal with a component just beyond max_magnitude must still be found, by
// every pass (dispatched, portable, monitor), at every position and block tail.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>

#include <grip/contact/coulomb_kernel.hpp>
#include <grip/monitor/stability_monitor.hpp>

#include "support/fixtures.hpp"

using namespace grip;

namespace {

template <class G>
void check_short_normal(std::mt19937& rng, int n) {
  using S = typename G::ScalarType;
  constexpr int fixed = G::fixed_size > 0 ? G::fixed_size : 0;
  const S big = ScalarTraits<S>::max_magnitude;
  const S tol = ScalarTraits<S>::normal_tolerance;
  const StabilityMonitor<G> monitor;
  for (int i = 0; i < n; ++i) {
    G g = grip_test::random_grasp<G>(rng, n);
    typename G::ForceVector x(g.unknowns());
    for (int j = 0; j < n; ++j) x.template segment<3>(3 * j) = S(2) * g.contact(j).normal;  // valid, pushing
    // Contact i: |a|^2 = 1 - 1.9 tol (accepted), and x_i = c big a/|a| with c = 1 + tol/2: its
    // first component is beyond max_magnitude, while f_n^2 + |t|^2 = c^2 |a|^2 big^2 < big^2.
    Contact<S> c = g.contact(i);
    c.normal = Vector3<S>(std::sqrt(S(1) - S(1.9) * tol), S(0), S(0));
    REQUIRE(g.set(i, c) == Status::Ok);
    x.template segment<3>(3 * i) = Vector3<S>((S(1) + S(0.5) * tol) * big, S(0), S(0));
    REQUIRE(x(3 * i) > big);
    std::array<ContactMode, G::capacity> m{};
    CHECK(detail::classify_coulomb<fixed>(detail::cone_rows(g.contacts()),
                                          detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                          ScalarTraits<S>::default_tolerance, m.data())
              .invalid == 1);
    CHECK(detail::classify_coulomb_portable(detail::cone_rows(g.contacts()),
                                            detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                            ScalarTraits<S>::default_tolerance, m.data())
              .invalid == 1);
    CHECK(monitor.classify(g, x).status == Status::InvalidInput);
    // Exactly max_magnitude along the same normal is valid.
    x(3 * i) = big;
    CHECK(detail::classify_coulomb<fixed>(detail::cone_rows(g.contacts()),
                                          detail::cone_row_stride<typename G::ScalarType>, x.data(), n, S(0),
                                          ScalarTraits<S>::default_tolerance, m.data())
              .invalid == 0);
    CHECK(monitor.classify(g, x).ok());
  }
}

}  // namespace

TEST_CASE_TEMPLATE("Coulomb kernel: a component beyond max_magnitude along a normal not quite unit is invalid", S,
                   double, float) {
  std::mt19937 rng(404);
  for (int n : {1, 3, 4, 5, 7, 8, 9, 12, 13, 16, 17, 19}) check_short_normal<Grasp<Dynamic, HardFinger, S, 19>>(rng, n);
  check_short_normal<Grasp<8, HardFinger, S>>(rng, 8);
  check_short_normal<Grasp<20, HardFinger, S>>(rng, 20);
}
