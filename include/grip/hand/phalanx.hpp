#pragma once
/// \file
/// The hand's vocabulary (paper section 3): its digits (Finger), the kinds of body a digit has
/// (Phalanx), how many phalanges, bodies and measured joints the hand has, and each body's index.
/// The hand model itself: hand_model.hpp.
///
/// Phalanx (and joint) order, the same for both: index k in [0, 14)
///   0 thumb proximal, 1 thumb distal,
///   2 index proximal, 3 index middle, 4 index distal,
///   5 long  proximal, 6 long  middle, 7 long  distal,
///   8 ring  proximal, 9 ring  middle, 10 ring  distal,
///   11 little proximal, 12 little middle, 13 little distal.
/// Joint k is the flexion joint at the proximal end of phalanx k: for a finger MCP, PIP, DIP;
/// for the thumb MCP, IP (the glove's 14 joints; the thumb's CMC is a fixed posture).
/// The thumb has no Phalanx::Middle.
///
/// Bodies: the 14 phalanges, then the palm as the five metacarpals (flesh included), index
/// k = 14 + f for digit f: 14 the thumb's (the thenar eminence, moved by the CMC), 15 .. 18
/// index to little (fixed in the hand). A body is a capsule like a phalanx.

namespace grip {

/// Fingers of the human hand, thumb first.
enum class Finger { Thumb = 0, Index = 1, Long = 2, Ring = 3, Little = 4 };
/// Phalanges of a finger, from the palm outwards (the thumb's "middle" is its distal
/// phalanx's neighbour; see the hand model for the thumb's two-phalanx convention), and the
/// digit's metacarpal: a body of the palm (the thumb's, the thenar eminence; hand_model.hpp).
enum class Phalanx { Proximal = 0, Middle = 1, Distal = 2, Metacarpal = 3 };

/// Number of phalanges of the hand model (and of measured joints).
constexpr int hand_phalanx_count = 14;
/// Number of bodies: the phalanges and the five metacarpals (the palm and the thenar).
constexpr int hand_body_count = 19;
/// Number of measured joint angles (three per finger, two for the thumb).
constexpr int hand_joint_count = 14;

/// Index in [0, 19) of a digit's body in the order above, or -1 for the thumb's
/// (absent) middle phalanx.
constexpr int phalanx_index(Finger f, Phalanx p) {
  const int fi = static_cast<int>(f);
  const int pi = static_cast<int>(p);
  if (p == Phalanx::Metacarpal) return hand_phalanx_count + fi;
  if (fi == 0) return pi == 0 ? 0 : (pi == 2 ? 1 : -1);
  return 2 + 3 * (fi - 1) + pi;
}

/// The digit of body index k in [0, 19).
constexpr Finger phalanx_finger(int k) {
  return k >= hand_phalanx_count ? static_cast<Finger>(k - hand_phalanx_count)
                                 : (k < 2 ? Finger::Thumb : static_cast<Finger>(1 + (k - 2) / 3));
}

/// The kind of body index k in [0, 19).
constexpr Phalanx phalanx_kind(int k) {
  return k >= hand_phalanx_count ? Phalanx::Metacarpal
         : k < 2                 ? (k == 0 ? Phalanx::Proximal : Phalanx::Distal)
                                 : static_cast<Phalanx>((k - 2) % 3);
}

}  // namespace grip
