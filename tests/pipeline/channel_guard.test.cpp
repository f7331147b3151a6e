// ChannelGuard: hold between device updates, slew, onset ramp, stale-input watchdog, bad input
// and rounding to steps with the error carried, each against its bound or a hand-solved value.
#include <doctest/doctest.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

#include <grip/pipeline/channel_guard.hpp>

#include "support/allocation_counter.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace channel_guard_tests {
using namespace grip;
using Guard = ChannelGuard<double, 3>;
using Commands = Guard::Commands;

constexpr double dt = 1e-3;  // the haptic loop's 1 kHz

TEST_CASE("the command changes only at the device's updates and follows its target") {
  ChannelGuardSettings<double> s;
  s.update_rate = 200;  // every 5 ms
  Guard g(s);
  const Commands want{1.0, -2.0, 0.5};
  int changes = 0;
  Commands last{};
  for (int k = 0; k <= 100; ++k) {
    REQUIRE(g.update(k * dt, want, true) == Status::Ok);
    if (g.command() != last) {
      ++changes;
      CHECK(k % 5 == 0);  // a change only at t = 0, 5, 10, ... ms
    }
    last = g.command();
  }
  CHECK(changes == 1);  // no slew limit, no onset: the first update already renders the target
  CHECK(g.command() == want);
}

TEST_CASE("the slew bound holds exactly between updates, and the target is reached") {
  std::mt19937 rng(71);
  std::uniform_real_distribution<double> u(-20, 20);
  ChannelGuardSettings<double> s;
  s.update_rate = 500;
  s.slew_rate = 400;  // N/s
  Guard g(s);
  Commands want{};
  Commands prev{};  // the command at the last change, and its time
  double t_prev = 0;
  for (int k = 0; k < 3000; ++k) {
    if (k % 37 == 0) want = {u(rng), u(rng), u(rng)};
    const double t = k * dt;
    REQUIRE(g.update(t, want, true) == Status::Ok);
    const Commands& c = g.command_exact();
    for (std::size_t i = 0; i < 3; ++i) CHECK(std::abs(c[i] - prev[i]) <= s.slew_rate * (t - t_prev) * (1 + 1e-12));
    if (c != prev) {
      prev = c;
      t_prev = t;
    }
  }
  // Held at one target long enough (|20 + 20| N at 400 N/s: 0.1 s): reached exactly.
  for (int k = 0; k < 200; ++k) g.update(3.0 + k * dt, want, true);
  CHECK(g.command_exact() == want);
}

TEST_CASE("an onset ramps a channel in from rest: |c| <= |target| (t - t0) / onset_time") {
  ChannelGuardSettings<double> s;
  s.update_rate = 1000;
  s.onset_time = 0.05;
  Guard g(s);
  for (int k = 0; k < 10; ++k) g.update(k * dt, Commands{}, true);  // at rest
  const double t0 = 10 * dt;
  const Commands want{8.0, -4.0, 0.0};
  for (int k = 10; k < 100; ++k) {
    const double t = k * dt;
    REQUIRE(g.update(t, want, true) == Status::Ok);
    const double ramp = std::min(1.0, (t - t0) / s.onset_time);
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(std::abs(g.command_exact()[i]) <= std::abs(want[i]) * ramp * (1 + 1e-12));
      CHECK(g.command_exact()[i] * want[i] >= 0.0);  // never against the target's sign
    }
  }
  CHECK(g.command_exact() == want);  // after the onset, the target itself
}

TEST_CASE("stale input: the command falls to zero at the slew rate, without a jump") {
  ChannelGuardSettings<double> s;
  s.update_rate = 1000;
  s.slew_rate = 100;
  s.stale_after = 0.02;
  Guard g(s);
  const Commands want{5.0, -3.0, 1.0};
  for (int k = 0; k < 200; ++k) g.update(k * dt, want, true);  // settled at the target
  REQUIRE(g.command_exact() == want);
  double last_fresh = 199 * dt;
  Commands prev = g.command_exact();
  bool seen_stale = false;
  for (int k = 200; k < 400; ++k) {
    const double t = k * dt;
    REQUIRE(g.update(t, Commands{100.0, 100.0, 100.0}, false) == Status::Ok);  // not fresh: ignored
    const bool expect_stale = t - last_fresh > s.stale_after;
    CHECK(g.stale() == expect_stale);
    seen_stale = seen_stale || expect_stale;
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(std::abs(g.command_exact()[i] - prev[i]) <= s.slew_rate * dt * (1 + 1e-12));
      if (!expect_stale) CHECK(g.command_exact()[i] == want[i]);   // the last good target held
      CHECK(std::abs(g.command_exact()[i]) <= std::abs(prev[i]));  // only down once stale
    }
    prev = g.command_exact();
  }
  REQUIRE(seen_stale);
  // 5 N at 100 N/s: 50 ms after going stale (at 220 ms) every channel is at rest.
  CHECK(g.command_exact() == Commands{});
  // Fresh input again: the command comes back.
  for (int k = 400; k < 600; ++k) g.update(k * dt, want, true);
  CHECK(g.command_exact() == want);
}

TEST_CASE("bad input gives InvalidInput and takes every command to zero at the slew rate") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (int kind = 0; kind < 4; ++kind) {
    CAPTURE(kind);
    ChannelGuardSettings<double> s;
    s.update_rate = 1000;
    s.slew_rate = 200;
    s.max_command = 10;
    Guard g(s);
    const Commands want{4.0, -4.0, 2.0};
    for (int k = 0; k < 100; ++k) g.update(k * dt, want, true);
    REQUIRE(g.command_exact() == want);
    Commands prev = g.command_exact();
    for (int k = 100; k < 200; ++k) {
      Commands bad = want;
      double t = k * dt;
      if (kind == 0) bad[1] = nan;
      if (kind == 1) bad[2] = inf;
      if (kind == 2) bad[0] = 11.0;  // beyond max_command
      if (kind == 3) t = nan;        // a bad clock: time stands at the last good one
      CHECK(g.update(t, bad, true) == Status::InvalidInput);
      for (std::size_t i = 0; i < 3; ++i) {
        CHECK(std::isfinite(g.command()[i]));
        CHECK(std::abs(g.command_exact()[i] - prev[i]) <= s.slew_rate * dt * (1 + 1e-12));
      }
      prev = g.command_exact();
    }
    if (kind < 3) CHECK(g.command_exact() == Commands{});  // 4 N at 200 N/s: 20 ms
  }
}

TEST_CASE("time going back is bad input, and bad settings zero the command") {
  Guard g;
  REQUIRE(g.update(1.0, Commands{1, 1, 1}, true) == Status::Ok);
  CHECK(g.update(0.5, Commands{1, 1, 1}, true) == Status::InvalidInput);
  ChannelGuardSettings<double> s;
  s.update_rate = 0;
  Guard b(s);
  CHECK(b.update(0.0, Commands{1, 1, 1}, true) == Status::InvalidInput);
  CHECK(b.command() == Commands{});
  s = {};
  s.step = -1;
  Guard c(s);
  CHECK(c.update(0.0, Commands{1, 1, 1}, true) == Status::InvalidInput);
}

TEST_CASE("steps: every rendered value a multiple of the step, within it of c, the mean right") {
  ChannelGuardSettings<double> s;
  s.update_rate = 200;
  s.step = 0.2;  // 100 steps of a 20 N channel
  Guard g(s);
  const Commands want{0.37, -1.13, 7.0};
  Commands sum{};
  int updates = 0;
  Commands last{};
  for (int k = 0; k < 10000; ++k) {
    REQUIRE(g.update(k * dt, want, true) == Status::Ok);
    if (k % 5 != 0) {
      CHECK(g.command() == last);  // held between updates
      continue;
    }
    ++updates;
    for (std::size_t i = 0; i < 3; ++i) {
      const double q = g.command()[i] / s.step;
      CHECK(std::abs(q - std::round(q)) <= 1e-9);
      CHECK(std::abs(g.command()[i] - g.command_exact()[i]) <= s.step * (1 + 1e-9));
      sum[i] += g.command()[i];
    }
    last = g.command();
  }
  // The carried error stays within half a step, so the mean is off by at most step / (2 N).
  for (std::size_t i = 0; i < 3; ++i) CHECK(std::abs(sum[i] / updates - want[i]) <= s.step / (2.0 * updates) + 1e-12);
}

TEST_CASE("a guard's update allocates nothing") {
  ChannelGuardSettings<double> s;
  s.slew_rate = 50;
  s.step = 0.1;
  s.onset_time = 0.01;
  s.stale_after = 0.05;
  ChannelGuard<double, 14> g(s);
  ChannelGuard<double, 14>::Commands want{};
  want.fill(3.0);
  ChannelGuardSettings<float> sf;
  sf.slew_rate = 50;
  sf.step = 0.1f;
  ChannelGuard<float, 14> gf(sf);
  ChannelGuard<float, 14>::Commands wf{};
  wf.fill(3.0f);
  grip_test::NoHeapScope scope;
  for (int k = 0; k < 1000; ++k) {
    (void)g.update(k * dt, want, k % 3 == 0);
    (void)gf.update(float(k) * 1e-3f, wf, true);
  }
  CHECK(scope.allocations() == 0);
  // float keeps the same contract: the command reaches its target and stays a multiple of step.
  for (std::size_t i = 0; i < 14; ++i) {
    CHECK(gf.command_exact()[i] == 3.0f);
    CHECK(std::abs(gf.command()[i] - 3.0f) <= 0.1f * 1.0001f);
  }
}

}  // namespace channel_guard_tests
