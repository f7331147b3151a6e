#pragma once
/// \file
/// The hand's collision model (paper section 3): a hierarchy of bounding spheres, hand ->
/// digit (and the palm) -> phalanx -> sphere tree of each phalanx, built per frame from the
/// posed hand (hand/hand_kinematics.hpp) without heap. Every body of the hand has its tree:
/// the 14 phalanges and the palm's five metacarpals (hand_model.hpp), which form group 5.
///
/// Phalanx sphere tree. Phalanx k (a capsule of radius r around [base, tip]) is sampled by
/// Samples points x_j = base + j / (Samples - 1) (tip - base), j = 0 .. Samples - 1; leaf j
/// is the sphere (x_j, r), the capsule's own cross-section there, so the capsule is the
/// union of the leaves swept along the axis: depths between samples are those of the
/// samples (exact for planar surfaces; for a surface of radius R the sampling misses at most
/// (L / (Samples - 1))^2 / (8 (R + r)) of depth for a phalanx of length L lying tangent).
/// The tree is a complete binary tree in the implicit layout: node i has children 2 i + 1
/// and 2 i + 2, parent (i - 1) / 2; nodes Samples - 1 .. 2 Samples - 2 are the leaves,
/// sample j being node Samples - 1 + j. Each inner node bounds its two children.

#include <array>
#include <cmath>
#include <cstdint>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_kinematics.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {

/// A bounding sphere (centre in metres, radius in metres).
template <class Scalar>
struct BoundingSphere {
  Vector3<Scalar> center{Vector3<Scalar>::Zero()};  ///< Centre (m).
  Scalar radius{0};                                 ///< Radius (m), >= 0.
};

/// The smallest sphere containing spheres a and b.
template <class Scalar>
BoundingSphere<Scalar> enclose(const BoundingSphere<Scalar>& a, const BoundingSphere<Scalar>& b) {
  const Vector3<Scalar> d = b.center - a.center;
  const Scalar dist = d.norm();
  if (dist + b.radius <= a.radius) return a;
  if (dist + a.radius <= b.radius) return b;
  BoundingSphere<Scalar> s;
  s.radius = (dist + a.radius + b.radius) / Scalar(2);
  s.center = a.center + d * ((s.radius - a.radius) / dist);
  return s;
}

/// True if the two spheres overlap or touch.
template <class Scalar>
bool overlap(const BoundingSphere<Scalar>& a, const BoundingSphere<Scalar>& b) {
  const Scalar r = a.radius + b.radius;
  return (a.center - b.center).squaredNorm() <= r * r;
}

/// The posed hand's sphere hierarchy, world frame. Samples per phalanx: a power of two >= 2.
template <class Scalar, int Samples = 8>
class HandCollisionModel {
  static_assert(Samples >= 2 && (Samples & (Samples - 1)) == 0, "Samples must be a power of two >= 2");

 public:
  static constexpr int samples_per_phalanx = Samples;        ///< Leaves of each phalanx tree.
  static constexpr int nodes_per_phalanx = 2 * Samples - 1;  ///< Nodes of each phalanx tree.
  static constexpr int first_leaf = Samples - 1;             ///< Node index of sample 0.

  /// Builds every sphere of the hierarchy from a posed hand: the trees of the bodies the
  /// posture has (HandPosture::bodies; the others are left out of every sphere). InvalidInput
  /// (model unchanged) if one of those capsules holds a non-finite number or a radius <= 0, or
  /// the posture has no body; Ok otherwise.
  Status set_posture(const HandPosture<Scalar>& posture) {
    const std::uint32_t present = posture.bodies & ((1u << hand_body_count) - 1u);
    if (present == 0) return Status::InvalidInput;
    for (int k = 0; k < hand_body_count; ++k) {
      const PhalanxCapsule<Scalar>& c = posture.phalanges[detail::idx(k)];
      if ((present >> k & 1u) &&
          (!c.base.allFinite() || !c.tip.allFinite() || !std::isfinite(c.radius) || !(c.radius > Scalar(0))))
        return Status::InvalidInput;
    }
    for (int k = 0; k < hand_body_count; ++k) {
      if (!(present >> k & 1u)) continue;
      const PhalanxCapsule<Scalar>& c = posture.phalanges[detail::idx(k)];
      capsules_[detail::idx(k)] = c;
      // Node i covers the samples of its subtree, all on the axis with one radius: the smallest
      // sphere around them is centred halfway, its radius r plus half their spread (what
      // enclose() gives, without a square root per node).
      auto& nodes = nodes_[detail::idx(k)];
      const Vector3<Scalar> axis = c.tip - c.base;
      const Scalar length = axis.norm();
      for (int i = 0; i < nodes_per_phalanx; ++i)
        nodes[detail::idx(i)] = BoundingSphere<Scalar>{c.base + Scalar(spans.middle[i]) * axis,
                                                       c.radius + Scalar(spans.half_spread[i]) * length};
    }
    bool any = false;
    for (int f = 0; f < group_count; ++f) {
      // A group without a body of the posture keeps a sphere of radius 0 at its first body's
      // place; detect_contacts skips its bodies by the mask.
      bool has = false;
      BoundingSphere<Scalar> s{};
      for (int k = first_phalanx(f); k < first_phalanx(f) + phalanges_of(f); ++k) {
        if (!(present >> k & 1u)) continue;
        s = has ? enclose(s, phalanx_node(k, 0)) : phalanx_node(k, 0);
        has = true;
      }
      fingers_[detail::idx(f)] = s;
      if (has) hand_ = any ? enclose(hand_, s) : s;
      any = any || has;
    }
    bodies_ = present;
    posed_ = true;
    return Status::Ok;
  }

  /// True once set_posture() has succeeded.
  bool posed() const { return posed_; }
  /// The posture's bodies (HandPosture::bodies): bit k set if body k takes part in contacts.
  std::uint32_t bodies() const { return bodies_; }
  /// Sphere bounding the whole hand.
  const BoundingSphere<Scalar>& hand_sphere() const { return hand_; }
  /// Sphere bounding group f: digit f (0 thumb .. 4 little) or the palm (5); GRIP_ASSERT.
  const BoundingSphere<Scalar>& finger_sphere(int f) const {
    GRIP_ASSERT(f < group_count);
    return fingers_[detail::idx(f)];
  }
  /// Node i (0 .. nodes_per_phalanx - 1) of body k's tree (0 is its root); k in
  /// [0, hand_body_count) (GRIP_ASSERT, as i).
  const BoundingSphere<Scalar>& phalanx_node(int k, int i) const {
    GRIP_ASSERT(k < hand_body_count && i < nodes_per_phalanx);
    return nodes_[detail::idx(k)][detail::idx(i)];
  }
  /// The capsule of body k (0 <= k < hand_body_count, GRIP_ASSERT) as last posed.
  const PhalanxCapsule<Scalar>& capsule(int k) const {
    GRIP_ASSERT(k < hand_body_count);
    return capsules_[detail::idx(k)];
  }

  /// Groups of bodies: the five digits' phalanges, then the palm's metacarpals.
  static constexpr int group_count = 6;
  /// First body index of group f (0 thumb .. 4 little: its phalanges; 5: the palm).
  static constexpr int first_phalanx(int f) { return f == 5 ? hand_phalanx_count : f == 0 ? 0 : 2 + 3 * (f - 1); }
  /// Number of bodies of group f (2 for the thumb, 3 for a finger, 5 for the palm).
  static constexpr int phalanges_of(int f) { return f == 5 ? 5 : f == 0 ? 2 : 3; }

 private:
  /// Per node of a phalanx tree: the axis parameter of its samples' midpoint and half their
  /// spread (samples j0 .. j1 of the subtree: (t0 + t1) / 2 and (t1 - t0) / 2).
  struct Spans {
    double middle[nodes_per_phalanx];
    double half_spread[nodes_per_phalanx];
  };
  static constexpr Spans make_spans() {
    Spans t{};
    for (int i = 0; i < nodes_per_phalanx; ++i) {
      int first = i, width = 1;  // leftmost leaf below node i, and the leaves below it
      while (first < first_leaf) {
        first = 2 * first + 1;
        width *= 2;
      }
      const double t0 = double(first - first_leaf) / double(Samples - 1);
      const double t1 = double(first - first_leaf + width - 1) / double(Samples - 1);
      t.middle[i] = width == 1 ? t0 : 0.5 * (t0 + t1);
      t.half_spread[i] = 0.5 * (t1 - t0);
    }
    return t;
  }
  static constexpr Spans spans = make_spans();

  std::array<std::array<BoundingSphere<Scalar>, detail::idx(nodes_per_phalanx)>, hand_body_count> nodes_{};
  std::array<PhalanxCapsule<Scalar>, hand_body_count> capsules_{};
  std::array<BoundingSphere<Scalar>, group_count> fingers_{};
  BoundingSphere<Scalar> hand_{};
  std::uint32_t bodies_{0};
  bool posed_{false};
};

}  // namespace grip
