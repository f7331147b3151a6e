// DeviceChannelModel: the finger's free motion against the damped oscillator's closed form, the
// delay and the hold to the device update, steps and limits, the channel's energy against the
// work of a constant force, bad input and no heap.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <grip/pipeline/device_model.hpp>

#include "support/allocation_counter.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace device_model_tests {
using namespace grip;

TEST_CASE("the free finger follows the damped oscillator's closed form") {
  FingerImpedance<double> f;  // 10 g, 100 N/m
  f.damping = 0.5;            // zeta = 0.25: underdamped
  f.rest = 0.003;
  DeviceChannelModel<double> m(f, {}, 0.0, 0.05);
  const double w0 = std::sqrt(f.stiffness / f.mass), zeta = f.damping / (2 * std::sqrt(f.stiffness * f.mass));
  const double wd = w0 * std::sqrt(1 - zeta * zeta), s = zeta * w0;
  // x - rest = e^{-s t} (A cos wd t + B sin wd t), A = x0 - rest, B = (v0 + s A) / wd.
  const double a = 0.0 - f.rest, bb = (0.05 + s * a) / wd;
  for (int k = 1; k <= 200; ++k) {
    const double t = k * 1e-3;
    REQUIRE(m.advance(t) == Status::Ok);
    const double exact = f.rest + std::exp(-s * t) * (a * std::cos(wd * t) + bb * std::sin(wd * t));
    CHECK(std::abs(m.position() - exact) < 1e-3 * 0.003);  // semi-implicit Euler at 1e-5 s
  }
  CHECK(m.applied() == 0.0);
  CHECK(m.energy() == 0.0);
}

TEST_CASE("a command arrives after the delay and is held from the next device update") {
  DeviceChannelSettings<double> c;
  c.delay = 2e-3;
  c.update_rate = 200;  // updates at 0, 5, 10 ms
  DeviceChannelModel<double> m(FingerImpedance<double>{}, c);
  REQUIRE(m.send(0.0023, 1.5) == Status::Ok);  // arrives at 4.3 ms: rendered from 5 ms
  REQUIRE(m.advance(0.00499) == Status::Ok);
  CHECK(m.applied() == 0.0);
  REQUIRE(m.advance(0.00501) == Status::Ok);
  CHECK(m.applied() == 1.5);
  REQUIRE(m.send(0.0031, -0.5) == Status::Ok);  // arrives at 5.1 ms: rendered from 10 ms
  REQUIRE(m.advance(0.00999) == Status::Ok);
  CHECK(m.applied() == 1.5);
  REQUIRE(m.advance(0.01001) == Status::Ok);
  CHECK(m.applied() == -0.5);
}

TEST_CASE("the device rounds to its step and clips to its limits") {
  DeviceChannelSettings<double> c;
  c.step = 0.2;
  c.min_force = 0;  // a cable
  c.max_force = 20;
  DeviceChannelModel<double> m(FingerImpedance<double>{}, c);
  const double sent[] = {1.234, 1.31, 50.0, -3.0};
  const double held[] = {1.2, 1.4, 20.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    REQUIRE(m.send(k * 1e-3, sent[k]) == Status::Ok);
    REQUIRE(m.advance((k + 0.5) * 1e-3) == Status::Ok);
    CHECK(m.applied() == doctest::Approx(held[k]).epsilon(1e-12));
  }
}

TEST_CASE("the channel's energy is the work a constant force did on the finger") {
  FingerImpedance<double> f;
  DeviceChannelModel<double> m(f, {}, 0.001, 0.0);
  REQUIRE(m.send(0.0, 0.7) == Status::Ok);
  REQUIRE(m.advance(0.3) == Status::Ok);
  // Held from t = 0: the work taken from the finger is -F (x(t) - x(0)).
  CHECK(m.energy() == doctest::Approx(-0.7 * (m.position() - 0.001)).epsilon(1e-9));
}

TEST_CASE("bad input is refused, nothing moves") {
  DeviceChannelModel<double> m(FingerImpedance<double>{}, {});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(m.send(0.0, nan) == Status::InvalidInput);
  CHECK(m.send(nan, 1.0) == Status::InvalidInput);
  REQUIRE(m.send(0.002, 1.0) == Status::Ok);
  CHECK(m.send(0.001, 1.0) == Status::InvalidInput);  // time goes back
  REQUIRE(m.advance(0.01) == Status::Ok);
  CHECK(m.advance(0.005) == Status::InvalidInput);
  CHECK(m.advance(nan) == Status::InvalidInput);
  // A full queue refuses the next command.
  DeviceChannelSettings<double> slow;
  slow.delay = 1.0;
  DeviceChannelModel<double, 4> q(FingerImpedance<double>{}, slow);
  for (int k = 0; k < 4; ++k) CHECK(q.send(k * 1e-3, 1.0) == Status::Ok);
  CHECK(q.send(0.005, 1.0) == Status::InvalidInput);
  // Out-of-range models.
  FingerImpedance<double> massless;
  massless.mass = 0;
  DeviceChannelModel<double> bad(massless, {});
  CHECK_FALSE(bad.valid());
  CHECK(bad.advance(0.01) == Status::InvalidInput);
  CHECK(bad.position() == 0.0);
}

TEST_CASE("the device model makes no heap allocation") {
  DeviceChannelSettings<double> c;
  c.passivity = true;
  c.delay = 3e-3;
  DeviceChannelModel<double> m(FingerImpedance<double>{}, c);
  const grip_test::NoHeapScope scope;
  for (int k = 0; k < 100; ++k) {
    (void)m.send(k * 1e-3, 1.0);
    (void)m.advance((k + 1) * 1e-3);
  }
  CHECK(scope.allocations() == 0);
}

}  // namespace device_model_tests
