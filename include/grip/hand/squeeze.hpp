#pragma once
/// \file
/// The squeezing coefficient of eq. 8, s_i = d_i K_i dr_i, and the paper's Table 1 (the other
/// grasp types are in grasp_type.hpp).

#include <cmath>

#include "grip/core/assert.hpp"
#include "grip/hand/phalanx.hpp"

namespace grip {

/// Share d of each phalanx, and of the palm, in the grip force of one grasp type (eq. 8),
/// indexed by finger and phalanx. Every share is a normal force as a fraction of the summed
/// normal force of the four fingers, index to little (Table 1's reference), so that the
/// fingers' shares sum to 1 and the thumb and palm, which oppose them, are in the same unit
/// (docs/hand.md, "Grasp types"). The thumb has no middle phalanx: its [0][1] is 0. The palm's
/// share is its whole; each of its five bodies (the metacarpals, the thenar's included) takes
/// a fifth of it.
template <class Scalar>
struct ContributionTable {
  Scalar share[5][3];  ///< [finger][phalanx], dimensionless
  Scalar palm{0};      ///< the palm's share, dimensionless

  /// d for a finger and phalanx; for Phalanx::Metacarpal, palm / 5.
  constexpr Scalar operator()(Finger f, Phalanx p) const {
    return p == Phalanx::Metacarpal ? palm / Scalar(5) : share[static_cast<int>(f)][static_cast<int>(p)];
  }
  /// d for a finger and phalanx, to set it. Precondition (GRIP_ASSERT): p is not
  /// Phalanx::Metacarpal (set `palm`).
  constexpr Scalar& operator()(Finger f, Phalanx p) {
    GRIP_ASSERT(p != Phalanx::Metacarpal);
    return share[static_cast<int>(f)][static_cast<int>(p)];
  }
  /// Sum of d over the phalanges of a finger (Table 1's "Total Contribution" row).
  constexpr Scalar finger_total(Finger f) const {
    const int i = static_cast<int>(f);
    return share[i][0] + share[i][1] + share[i][2];
  }
  /// Sum of d over the four fingers, index to little: 1 in every table grip provides.
  constexpr Scalar four_finger_total() const {
    return finger_total(Finger::Index) + finger_total(Finger::Long) + finger_total(Finger::Ring) +
           finger_total(Finger::Little);
  }
  /// Sum of every share: the four fingers, the thumb and the palm.
  constexpr Scalar total() const { return four_finger_total() + finger_total(Finger::Thumb) + palm; }
};

/// The cylindrical power grip: the paper's Table 1 for the fingers (from Lee and Rim's
/// pressure measurements), and grip's own choice for the thumb (proximal 0.15, distal 0.25)
/// and the palm (0.40), which Table 1 does not give; they oppose the fingers (docs/hand.md).
/// contribution_table(GraspType::CylindricalPower) returns this table.
template <class Scalar = double>
constexpr ContributionTable<Scalar> cylindrical_power_grip() {
  return ContributionTable<Scalar>{
      {
          {Scalar(0.150), Scalar(0), Scalar(0.250)},      // thumb: proximal, -, distal (grip's choice)
          {Scalar(0.115), Scalar(0.021), Scalar(0.159)},  // index: proximal, middle, distal
          {Scalar(0.126), Scalar(0.023), Scalar(0.176)},  // long
          {Scalar(0.088), Scalar(0.016), Scalar(0.122)},  // ring
          {Scalar(0.060), Scalar(0.011), Scalar(0.083)},  // little
      },
      Scalar(0.400)};  // palm (grip's choice)
}

/// Eq. 8: s = d K dr, the squeezing force (N) for contribution d (dimensionless), contact
/// stiffness K (N/m) and interpenetration depth dr (m). A depth <= 0 (not touching) gives 0;
/// a NaN input gives NaN, which Contact validation then rejects.
template <class Scalar>
constexpr Scalar squeeze(Scalar d, Scalar stiffness, Scalar depth) {
  return depth > Scalar(0) ? d * stiffness * depth : (depth == depth ? Scalar(0) : depth);
}

}  // namespace grip
