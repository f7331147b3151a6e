// The pipeline's free phase: an object nobody holds tumbles and falls without gaining energy.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "pipeline/pipeline_fixture.hpp"
#include "support/test_scale.hpp"

using namespace grip;

TEST_CASE_TEMPLATE("energy does not grow in free flight over 10 s of pipeline frames", S, double, float) {
  grip_test::HeldCylinder<S> h;
  RigidBody<S> b = h.object;
  b.position << S(3), S(0), S(0);  // far from the hand: no contacts
  b.linear_velocity << S(0.5), S(0), S(6);
  b.angular_velocity = b.orientation * Vector3<S>(S(0.1), S(12), S(0.1));  // about a transverse axis
  auto p = h.pipeline();
  REQUIRE(p.set_object(b) == Status::Ok);
  const Vector3<S> g = h.settings.gravity;
  auto energy = [&](const RigidBody<S>& x) { return x.kinetic_energy() - x.mass * g.dot(x.position); };
  const S e0 = energy(b);
  S worst = S(0), scale = e0;
  HapticFrame<S> f;
  const JointAngles<S> open = JointAngles<S>::Zero();
  const int frames = grip_test::scaled(10000, 1000);  // 10 s at 1 kHz (at least 1 s)
  for (int i = 0; i < frames; ++i) {
    REQUIRE(p.step(h.wrist, open, f) == Status::Ok);
    REQUIRE(f.contacts == 0);
    scale = std::max(scale, p.object().kinetic_energy());
    worst = std::max(worst, (energy(p.object()) - e0) / scale);
  }
  // Never above the start by more than the integrator's bounded rotational error or round-off,
  // relative to the size of the energy terms (the object falls ~430 m: ~1.7 kJ).
  CHECK(worst <= (std::is_same<S, float>::value ? S(1e-3) : S(1e-6)));
  // And it did fall: z(t) = 6 t - 9.81 t^2 / 2, exact for the integrator; -430.5 m at 10 s.
  const double t = frames * 1e-3, z = 6 * t - 9.81 * t * t / 2;
  CHECK(std::abs(double(p.object().position.z()) - z) <= (std::is_same<S, float>::value ? 0.05 : 1e-6));
}
