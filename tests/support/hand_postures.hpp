#pragma once
// Hand postures for the collision tests: one phalanx placed by hand, the others out of the way.
#include <grip/hand/hand_kinematics.hpp>

namespace grip_test {

/// A posture whose phalanges all lie 10 m away (short, 8 mm thick) but phalanx k, the capsule
/// of radius r around [a, b].
template <class S>
grip::HandPosture<S> single_phalanx(int k, const grip::Vector3<S>& a, const grip::Vector3<S>& b, S r) {
  grip::HandPosture<S> h;
  for (int i = 0; i < grip::hand_phalanx_count; ++i) {
    grip::PhalanxCapsule<S>& c = h.phalanges[static_cast<std::size_t>(i)];
    c.base = grip::Vector3<S>(S(10), S(0), S(i));
    c.tip = grip::Vector3<S>(S(10.01), S(0), S(i));
    c.radius = S(0.008);
  }
  grip::PhalanxCapsule<S>& c = h.phalanges[static_cast<std::size_t>(k)];
  c.base = a;
  c.tip = b;
  c.radius = r;
  return h;
}

}  // namespace grip_test
