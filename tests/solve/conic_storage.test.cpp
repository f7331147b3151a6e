// The interior-point method's starting point (include/grip/solve/detail/conic_storage.hpp,
// ConicStorage::start): every cone variable and its dual at the scale times the cone's centre, and
// a bound's slack at what its row u_0 + s = c tau leaves at tau = 1, with the pair's product the
// scale squared, as for every cone pair; derived by hand from the row. A contact's set() leaves its
// bound where start(1) would: a fresh run at scale 1 starts there without a call to start().
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/solve/detail/conic_lanes.hpp>

using namespace grip;

TEST_CASE_TEMPLATE("interior-point start: a bound's slack closes its row, centred like the cones", S, double, float) {
  using Lanes = detail::ConicLanes<S, 3, 8>;
  Lanes k(3);
  const typename Lanes::Map a = Lanes::Map::Identity();
  const typename Lanes::ConeVector p = Lanes::ConeVector::Ones(), q = Lanes::ConeVector::Zero();
  const S inf = std::numeric_limits<S>::infinity();
  k.set(0, a, p, q, S(5), p);    // a bound far above the scales below
  k.set(1, a, p, q, S(0.5), p);  // one below twice the scale of the second start
  k.set(2, a, p, q, inf, p);     // none
  const S tol = S(8) * std::numeric_limits<S>::epsilon();
  for (const S scale : {S(1e-3), S(1)}) {
    CAPTURE(scale);
    k.start(scale);
    for (int i = 0; i < 3; ++i) {
      CHECK(k.u(i)(0) == scale);
      CHECK(k.z(i)(0) == scale);
      CHECK(k.u(i).template tail<2>().isZero(0));
    }
    // Contact 0: u_0 + s = c at tau = 1, so s = 5 - scale; s t = scale^2.
    CHECK(std::abs(k.bound_slack(0) - (S(5) - scale)) <= tol * S(5));
    CHECK(std::abs(k.bound_slack(0) * k.bound_dual(0) - scale * scale) <= tol * scale * scale);
    // Contact 1: c - scale is below the scale at scale 1 (0.5 - 1 < 0): the slack stays at the
    // scale, positive, with its dual.
    if (scale == S(1)) {
      CHECK(k.bound_slack(1) == scale);
      CHECK(k.bound_dual(1) == scale);
    } else {
      CHECK(std::abs(k.bound_slack(1) - (S(0.5) - scale)) <= tol);
      CHECK(std::abs(k.bound_slack(1) * k.bound_dual(1) - scale * scale) <= tol * scale * scale);
    }
    // Contact 2 has no bound: its (unused) pair at the scale.
    CHECK(k.bound_slack(2) == scale);
    CHECK(k.bound_dual(2) == scale);
  }
}

TEST_CASE_TEMPLATE("interior-point start: set() places a bound where start(1) would", S, double, float) {
  using Lanes = detail::ConicLanes<S, 3, 8>;
  Lanes k(3);
  const typename Lanes::Map a = Lanes::Map::Identity();
  const typename Lanes::ConeVector p = Lanes::ConeVector::Ones(), q = Lanes::ConeVector::Zero();
  k.set(0, a, p, q, S(5), p);    // s = 5 - 1 = 4 closes u_0 + s = c at u_0 = tau = 1; t = 1 / 4
  k.set(1, a, p, q, S(0.5), p);  // 0.5 - 1 < 1: s stays at 1, t = 1
  k.set(2, a, p, q, std::numeric_limits<S>::infinity(), p);
  CHECK(k.bound_slack(0) == S(4));
  CHECK(k.bound_dual(0) == S(0.25));
  CHECK(k.bound_slack(1) == S(1));
  CHECK(k.bound_dual(1) == S(1));
  CHECK(k.bound_slack(2) == S(1));
  CHECK(k.bound_dual(2) == S(1));
  for (int i = 0; i < 3; ++i) CHECK(k.u(i)(0) == S(1));
}
