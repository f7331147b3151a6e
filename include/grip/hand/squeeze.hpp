#pragma once
/// \file
/// The squeezing coefficient of eq. 8, s_i = d_i K_i dr_i, and the paper's Table 1.

#include <cmath>

namespace grip {

/// Fingers of the human hand, thumb first.
enum class Finger { Thumb = 0, Index = 1, Long = 2, Ring = 3, Little = 4 };
/// Phalanges of a finger, from the palm outwards (the thumb's "middle" is its distal
/// phalanx's neighbour; see the hand model for the thumb's two-phalanx convention).
enum class Phalanx { Proximal = 0, Middle = 1, Distal = 2 };

/// Share d of each phalanx in the total grip force of one grasp type (eq. 8), indexed by
/// finger and phalanx. Shares the source does not give are 0.
template <class Scalar>
struct ContributionTable {
  Scalar share[5][3];  ///< [finger][phalanx], dimensionless

  /// d for a finger and phalanx.
  constexpr Scalar operator()(Finger f, Phalanx p) const {
    return share[static_cast<int>(f)][static_cast<int>(p)];
  }
  /// Sum of d over the phalanges of a finger (Table 1's "Total Contribution" row).
  constexpr Scalar finger_total(Finger f) const {
    const int i = static_cast<int>(f);
    return share[i][0] + share[i][1] + share[i][2];
  }
};

/// The paper's Table 1: phalanx contributions for a cylindrical power grip (from Lee and
/// Rim's pressure measurements), index to little finger. The table gives no thumb row;
/// it is 0 here (the thumb and palm oppose the fingers; their squeeze is set by the user).
template <class Scalar = double>
constexpr ContributionTable<Scalar> cylindrical_power_grip() {
  return ContributionTable<Scalar>{{
      {Scalar(0), Scalar(0), Scalar(0)},                   // thumb: not in Table 1
      {Scalar(0.115), Scalar(0.021), Scalar(0.159)},       // index: proximal, middle, distal
      {Scalar(0.126), Scalar(0.023), Scalar(0.176)},       // long
      {Scalar(0.088), Scalar(0.016), Scalar(0.122)},       // ring
      {Scalar(0.060), Scalar(0.011), Scalar(0.083)},       // little
  }};
}

/// Eq. 8: s = d K dr, the squeezing force (N) for contribution d (dimensionless), contact
/// stiffness K (N/m) and interpenetration depth dr (m). A depth <= 0 (not touching) gives 0;
/// a NaN input gives NaN, which Contact validation then rejects.
template <class Scalar>
constexpr Scalar squeeze(Scalar d, Scalar stiffness, Scalar depth) {
  return depth > Scalar(0) ? d * stiffness * depth : (depth == depth ? Scalar(0) : depth);
}

}  // namespace grip
