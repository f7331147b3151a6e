#pragma once
/// \file
/// What collision detection (collision.hpp) reports: the contacts of the hand's phalanges
/// with an object, the settings of the exact narrow phase, and the per-sample view a user
/// inspects to diagnose a contact.

#include <array>
#include <cstdint>

#include "grip/core/index.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/types.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/squeeze.hpp"

namespace grip {

/// One contact of a phalanx with an object, in the world frame.
///
/// Invariants: `normal` is unit; depth > 0; point = x + (radius - depth) normal, where x =
/// base + axis_parameter (tip - base) is the axis point the depth is measured at and
/// radius - depth its signed distance (negative inside the object): the point is the surface
/// point nearest x. (For a union whose primitives overlap, inside two of them: the nearest
/// point of the primitive x is deepest in, which may lie inside another; see shape.hpp.)
template <class Scalar>
struct HandContact {
  Finger finger{Finger::Thumb};                      ///< Which digit.
  Phalanx phalanx{Phalanx::Proximal};                ///< Which phalanx.
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};    ///< Contact point on the object's surface (m), world.
  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};  ///< Unit normal INTO the object (the push direction), world.
  Scalar depth{0};                                   ///< Interpenetration dr_i (m), > 0.
  int samples{0};            ///< How many of the phalanx's sample spheres penetrate and belong to this contact.
  int sample{0};             ///< The sample the contact was found from (0 at the base .. Samples - 1 at the tip).
  Scalar axis_parameter{0};  ///< Where on the phalanx axis the contact's depth is measured, 0 base .. 1 tip.
};

/// The contacts of one frame: at most `PerPhalanx` per phalanx, in phalanx order (order of
/// hand_model.hpp), a phalanx's contacts by decreasing depth.
template <class Scalar, int PerPhalanx = 1>
struct HandContacts {
  static_assert(PerPhalanx >= 1 && PerPhalanx <= 8, "1 to 8 contacts per phalanx");
  static constexpr int per_phalanx = PerPhalanx;                   ///< Most contacts of one phalanx.
  static constexpr int capacity = hand_body_count * PerPhalanx;    ///< Most contacts of a frame.
  std::array<HandContact<Scalar>, detail::idx(capacity)> items{};  ///< items[0 .. count).
  int count{0};                                                    ///< Number of contacts.

  /// Contact i. Precondition (GRIP_ASSERT): 0 <= i < count.
  const HandContact<Scalar>& operator[](int i) const {
    GRIP_ASSERT(i < count);
    return items[detail::idx(i)];
  }
  /// The deepest contact of a finger's phalanx, or nullptr if it has none.
  const HandContact<Scalar>* find(Finger f, Phalanx p) const {
    for (int i = 0; i < count; ++i)
      if (items[detail::idx(i)].finger == f && items[detail::idx(i)].phalanx == p) return &items[detail::idx(i)];
    return nullptr;
  }
  /// Number of contacts of a finger's phalanx.
  int count_of(Finger f, Phalanx p) const {
    int n = 0;
    for (int i = 0; i < count; ++i)
      n += items[detail::idx(i)].finger == f && items[detail::idx(i)].phalanx == p ? 1 : 0;
    return n;
  }
};

/// The body mask of detect_contacts() selecting the 14 phalanges (bit k = body k): the
/// paper's hand, which has no palm.
constexpr std::uint32_t all_phalanges = (1u << hand_phalanx_count) - 1u;
/// The body mask selecting every body: the phalanges and the palm's metacarpals.
constexpr std::uint32_t all_hand_bodies = (1u << hand_body_count) - 1u;

/// Settings of the exact narrow phase (collision.hpp).
template <class Scalar>
struct ContactSettings {
  /// Most distance evaluations spent per locally deepest sample to find the deepest point of
  /// the capsule near it (collision.hpp); 0 measures depths at the samples only. A convex
  /// field needs 1 to 4 (the search is exact for piecewise-linear and quadratic distances);
  /// the bound caps the worst case.
  int refine_iterations{16};
  /// The search stops when the deepest point found is certified within this distance (m) of
  /// the capsule's deepest (for a convex field: the end tangents bound the minimum); what this
  /// certifies of the point and normal: collision.hpp. ScalarTraits::contact_tolerance by
  /// default (1e-12 m in double, 1e-7 m in float).
  Scalar refine_tolerance{ScalarTraits<Scalar>::contact_tolerance};
  /// Contacts of one phalanx (with PerPhalanx > 1): a penetrating sample whose outward
  /// normal is within this angle (rad) of a contact's joins it; one farther from every
  /// contact starts one more contact while there is room. Default 40 degrees: the two walls of
  /// a right-angled groove give two contacts, a phalanx pressed deep onto a box edge up to
  /// three (each face, and the edge 45 degrees from both), a smooth curved surface one.
  Scalar cluster_angle{Scalar(0.6981317007977318)};
};

/// What collision detection saw of one phalanx's samples (query_samples in collision.hpp):
/// for diagnosis, e.g. why a phalanx has or has not a contact.
template <class Scalar, int Samples>
struct PhalanxSamples {
  std::array<Vector3<Scalar>, Samples> center{};  ///< Sample centres (m), world.
  /// Exact signed distance (m) of each sample centre from the object's surface, negative
  /// inside: the sample sphere penetrates by radius - distance when that is > 0.
  std::array<Scalar, Samples> distance{};
  std::array<Vector3<Scalar>, Samples> normal{};  ///< Unit OUTWARD normal of the nearest surface, world.
  /// True where the broad phase (the octree) found the sample (its sphere inflated by half a
  /// spacing) within reach of a solid leaf: the only samples the narrow phase evaluates.
  std::array<bool, Samples> in_reach{};
  Scalar radius{0};  ///< The phalanx's (and each sample's) radius (m).

  /// Zeros everywhere (Eigen's vectors are not zeroed by default).
  PhalanxSamples() {
    center.fill(Vector3<Scalar>::Zero());
    normal.fill(Vector3<Scalar>::UnitZ());
  }
};

}  // namespace grip
