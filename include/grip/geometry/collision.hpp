#pragma once
/// \file
/// Two-stage recursive collision detection between the hand's sphere hierarchy and an
/// object's spherical octree (paper section 3), giving one contact per phalanx in contact.
///
/// Stage 1 (hand hierarchy): the hand's sphere, then each digit's, then each phalanx tree's
/// root is tested against the octree's root sphere; whole digits and phalanges are pruned.
/// Stage 2 (per phalanx): recursive descent of the octree against the phalanx's tree: an
/// octree node whose sphere does not reach the phalanx is dropped with everything below it.
/// (The phalanx tree's spheres are collinear, so its descent is done in closed form: the node
/// is tested against the capsule the leaves sweep, and at an octree leaf the samples in reach
/// are an index range along the axis; the leaf pairs are exactly those of sphere-by-sphere
/// descent, see detect_contacts_exhaustive.) At a pair of leaves
/// (sample sphere (x_j, r), octree leaf with surface model phi_leaf, see spherical_octree.hpp)
/// the sample's signed distance estimate is raised to phi_leaf(x_j) if larger: the estimate
/// of sample j is phi_j = max over overlapping leaves of phi_leaf(x_j) (each a lower bound of
/// the true distance for a convex shape; the best of them).
///
/// Combining per phalanx: sample j penetrates by p_j = r - phi_j > 0. The phalanx's contact
/// has depth dr = max_j p_j; inward normal = -(sum_j p_j n_j) / |sum_j p_j n_j| (the
/// depth-weighted mean of the leaves' outward normals, reversed); point = depth-weighted mean
/// of the samples' projections x_j - phi_j n_j onto the object's surface. Accuracy: the
/// octree's e(d) (spherical_octree.hpp) plus the sampling term (hand_collision_model.hpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/hand_collision_model.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/squeeze.hpp"

namespace grip {

/// One phalanx's contact with an object, in the world frame.
template <class Scalar>
struct HandContact {
  Finger finger{Finger::Thumb};                     ///< Which digit.
  Phalanx phalanx{Phalanx::Proximal};               ///< Which phalanx.
  Vector3<Scalar> point{Vector3<Scalar>::Zero()};   ///< Contact point on the object's surface (m), world.
  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()}; ///< Unit normal INTO the object (the push direction), world.
  Scalar depth{0};                                  ///< Interpenetration dr_i (m), > 0.
  int samples{0};                                   ///< How many of the phalanx's samples penetrate.
};

/// The contacts of one frame, at most one per phalanx, in phalanx order (hand_model.hpp).
template <class Scalar>
struct HandContacts {
  std::array<HandContact<Scalar>, hand_phalanx_count> items{};  ///< items[0 .. count).
  int count{0};                                                  ///< Number of contacts.
  /// Contact i, 0 <= i < count.
  const HandContact<Scalar>& operator[](int i) const { return items[static_cast<std::size_t>(i)]; }
  /// The contact of a finger's phalanx, or nullptr if it has none.
  const HandContact<Scalar>* find(Finger f, Phalanx p) const {
    for (int i = 0; i < count; ++i)
      if (items[static_cast<std::size_t>(i)].finger == f && items[static_cast<std::size_t>(i)].phalanx == p)
        return &items[static_cast<std::size_t>(i)];
    return nullptr;
  }
};

/// The phalanx mask of detect_contacts() selecting all 14 phalanges (bit k = phalanx k).
constexpr std::uint32_t all_phalanges = (1u << hand_phalanx_count) - 1u;

namespace detail {

/// Per-phalanx state of the stage-2 descent (object frame).
template <class Scalar, int Samples>
struct PhalanxQuery {
  std::array<BoundingSphere<Scalar>, 2 * Samples - 1> nodes;  // phalanx tree in the object frame
  std::array<Scalar, Samples> phi;                            // best estimate per sample
  std::array<int, Samples> leaf;                              // leaf giving it, -1 none
};

template <class Scalar, int Samples, int Capacity>
void leaf_pair(PhalanxQuery<Scalar, Samples>& q, int j, const SphericalOctree<Scalar, Capacity>& oct, int o) {
  const SurfacePlane<Scalar>& pl = oct.plane(o);
  const Vector3<Scalar>& x = q.nodes[static_cast<std::size_t>(Samples - 1 + j)].center;
  const Scalar phi = pl.distance + pl.normal.dot(x - oct.tree().node(o).center);
  std::size_t sj = static_cast<std::size_t>(j);
  if (q.leaf[sj] < 0 || phi > q.phi[sj]) {
    q.phi[sj] = phi;
    q.leaf[sj] = o;
  }
}

// Stage 2 descent of the octree against phalanx segment [a, b] (object frame) of radius r.
// The phalanx tree's leaves are collinear spheres (x_j, r), so instead of splitting its inner
// spheres the descent tests each octree node against the swept sphere (the capsule, a tighter
// bound than any inner sphere), and at an octree leaf takes the samples whose spheres reach
// it directly: |x_j - c| <= r + rho  <=>  |s_j - s_c| <= sqrt((r + rho)^2 - d_perp^2) along
// the axis. Same leaf pairs as the sphere-by-sphere test, fewer node visits.
template <class Scalar, int Samples>
struct SegmentQuery {
  Vector3<Scalar> a, axis;  // a = sample 0; axis = unit direction (zero for a point)
  Scalar length{0}, spacing{0}, radius{0};
};

// Squared distance from point v (relative to sample 0) to the segment, and the axial
// coordinate s of v (unclamped).
template <class Scalar, int Samples>
Scalar segment_distance2(const SegmentQuery<Scalar, Samples>& seg, const Vector3<Scalar>& v, Scalar& s) {
  s = v.dot(seg.axis);
  const Scalar sc = std::min(std::max(s, Scalar(0)), seg.length);
  return (v - sc * seg.axis).squaredNorm();
}

// Octree leaf o (solid) in reach of the segment: the samples j whose spheres reach it.
template <class Scalar, int Samples, int Capacity>
void leaf_samples(PhalanxQuery<Scalar, Samples>& q, const SegmentQuery<Scalar, Samples>& seg,
                  const SphericalOctree<Scalar, Capacity>& oct, int o, const Vector3<Scalar>& v, Scalar s,
                  Scalar reach) {
  if (!(seg.spacing > Scalar(0))) {  // a point-like phalanx: every sample is at a
    for (int j = 0; j < Samples; ++j) leaf_pair(q, j, oct, o);
    return;
  }
  const Scalar perp2 = v.squaredNorm() - s * s;
  const Scalar w = std::sqrt(std::max(reach * reach - perp2, Scalar(0)));
  const Scalar jlo = std::ceil((s - w) / seg.spacing), jhi = std::floor((s + w) / seg.spacing);
  const int j0 = jlo < Scalar(0) ? 0 : static_cast<int>(jlo);
  const int j1 = jhi > Scalar(Samples - 1) ? Samples - 1 : static_cast<int>(jhi);
  for (int j = j0; j <= j1; ++j) leaf_pair(q, j, oct, o);
}

// Visits the children of octree node o (itself in reach): each child in reach is a leaf to
// evaluate or a node to descend into. (The reach test is done here, before the call, so that
// the many children out of reach cost no call.)
template <class Scalar, int Samples, int Capacity>
void descend(PhalanxQuery<Scalar, Samples>& q, const SegmentQuery<Scalar, Samples>& seg,
             const SphericalOctree<Scalar, Capacity>& oct, int o) {
  const SphereNode<Scalar>& on = oct.tree().node(o);
  const int end = on.first_child + on.child_count;
  for (int k = on.first_child; k < end; ++k) {
    const SphereNode<Scalar>& cn = oct.tree().node(k);
    const Vector3<Scalar> v = cn.center - seg.a;
    Scalar s;
    const Scalar reach = seg.radius + cn.radius;
    if (segment_distance2(seg, v, s) > reach * reach) continue;
    if (cn.child_count > 0) descend(q, seg, oct, k);
    else if (oct.kind(k) != CellKind::Empty) leaf_samples(q, seg, oct, k, v, s, reach);
  }
}

// Stage 2 from the octree's root.
template <class Scalar, int Samples, int Capacity>
void descend_from_root(PhalanxQuery<Scalar, Samples>& q, const SegmentQuery<Scalar, Samples>& seg,
                       const SphericalOctree<Scalar, Capacity>& oct) {
  const SphereNode<Scalar>& root = oct.tree().node(0);
  const Vector3<Scalar> v = root.center - seg.a;
  Scalar s;
  const Scalar reach = seg.radius + root.radius;
  if (segment_distance2(seg, v, s) > reach * reach) return;
  if (root.child_count > 0) descend(q, seg, oct, 0);
  else if (oct.kind(0) != CellKind::Empty) leaf_samples(q, seg, oct, 0, v, s, reach);
}

/// Turns the per-sample estimates of phalanx k into at most one contact (object frame in,
/// world frame out). Returns true if the phalanx penetrates.
template <class Scalar, int Samples, int Capacity>
bool combine(const PhalanxQuery<Scalar, Samples>& q, Scalar radius, const SphericalOctree<Scalar, Capacity>& oct,
             const Eigen::Transform<Scalar, 3, Eigen::Isometry>& pose, HandContact<Scalar>& out) {
  Scalar depth = Scalar(0), wsum = Scalar(0);
  int count = 0, deepest = -1;
  Vector3<Scalar> nsum = Vector3<Scalar>::Zero(), psum = Vector3<Scalar>::Zero();
  for (int j = 0; j < Samples; ++j) {
    const std::size_t sj = static_cast<std::size_t>(j);
    if (q.leaf[sj] < 0) continue;
    const Scalar p = radius - q.phi[sj];
    if (!(p > Scalar(0))) continue;
    const Vector3<Scalar>& n = oct.plane(q.leaf[sj]).normal;
    const Vector3<Scalar>& x = q.nodes[static_cast<std::size_t>(Samples - 1 + j)].center;
    nsum += p * n;
    psum += p * (x - q.phi[sj] * n);
    wsum += p;
    ++count;
    if (p > depth) {
      depth = p;
      deepest = j;
    }
  }
  if (count == 0) return false;
  const Scalar nn = nsum.norm();
  Vector3<Scalar> n_out = nn > Scalar(1e-3) * wsum ? Vector3<Scalar>(nsum / nn)
                                                   : oct.plane(q.leaf[static_cast<std::size_t>(deepest)]).normal;
  out.depth = depth;
  out.samples = count;
  out.point = pose * Vector3<Scalar>(psum / wsum);
  out.normal = -(pose.linear() * n_out);
  out.normal.normalize();
  return true;
}

template <class Scalar>
bool rigid_pose_ok(const Eigen::Transform<Scalar, 3, Eigen::Isometry>& pose) {
  if (!pose.matrix().allFinite()) return false;
  const Matrix3<Scalar> R = pose.linear();
  return (R.transpose() * R - Matrix3<Scalar>::Identity()).cwiseAbs().maxCoeff() <= Scalar(1e-3);
}

}  // namespace detail

/// The per-frame entry point: contacts between the posed hand and one object (or obstacle),
/// whose octree is built in its own frame and placed in the world by `object_pose`
/// (object-frame point -> world point). Writes out.items[0 .. out.count), phalanx order.
/// Statuses: InvalidInput (out.count = 0) if the model was never posed, the octree is empty,
/// or the pose is not finite and rigid (rotation orthonormal within 1e-3); Ok otherwise
/// (out.count may be 0: no contact). No heap; recursion depth <= octree depth.
/// `phalanx_mask` (bit k = phalanx k, default all 14) skips the phalanges whose bit is clear.
template <class Scalar, int Samples, int Capacity>
Status detect_contacts(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& object,
                       const Eigen::Transform<Scalar, 3, Eigen::Isometry>& object_pose, HandContacts<Scalar>& out,
                       std::uint32_t phalanx_mask = all_phalanges) {
  out.count = 0;
  if (!hand.posed() || object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  const Eigen::Transform<Scalar, 3, Eigen::Isometry> to_object = object_pose.inverse(Eigen::Isometry);
  const SphereNode<Scalar>& root = object.tree().node(0);
  const BoundingSphere<Scalar> root_world{object_pose * root.center, root.radius};
  if (!overlap(hand.hand_sphere(), root_world)) return Status::Ok;
  detail::PhalanxQuery<Scalar, Samples> q;
  for (int f = 0; f < 5; ++f) {
    if (!overlap(hand.finger_sphere(f), root_world)) continue;
    const int first = HandCollisionModel<Scalar, Samples>::first_phalanx(f);
    for (int k = first; k < first + HandCollisionModel<Scalar, Samples>::phalanges_of(f); ++k) {
      if (!((phalanx_mask >> k) & 1u) || !overlap(hand.phalanx_node(k, 0), root_world)) continue;
      for (int i = 0; i < 2 * Samples - 1; ++i) {
        q.nodes[static_cast<std::size_t>(i)].center = to_object * hand.phalanx_node(k, i).center;
        q.nodes[static_cast<std::size_t>(i)].radius = hand.phalanx_node(k, i).radius;
      }
      q.leaf.fill(-1);
      detail::SegmentQuery<Scalar, Samples> seg;
      seg.a = q.nodes[static_cast<std::size_t>(Samples - 1)].center;
      const Vector3<Scalar> ab = q.nodes[static_cast<std::size_t>(2 * Samples - 2)].center - seg.a;
      seg.length = ab.norm();
      seg.axis = seg.length > Scalar(0) ? Vector3<Scalar>(ab / seg.length) : Vector3<Scalar>::Zero();
      seg.spacing = seg.length / Scalar(Samples - 1);
      seg.radius = hand.capsule(k).radius;
      detail::descend_from_root(q, seg, object);
      HandContact<Scalar>& c = out.items[static_cast<std::size_t>(out.count)];
      if (detail::combine(q, hand.capsule(k).radius, object, object_pose, c)) {
        c.finger = phalanx_finger(k);
        c.phalanx = phalanx_kind(k);
        ++out.count;
      }
    }
  }
  return Status::Ok;
}

/// Reference version of detect_contacts() with no pruning: every phalanx sample against
/// every octree leaf (the baseline of bench/bench_collision.cpp; same result, since every
/// octree and hand sphere contains its descendants).
template <class Scalar, int Samples, int Capacity>
Status detect_contacts_exhaustive(const HandCollisionModel<Scalar, Samples>& hand,
                                  const SphericalOctree<Scalar, Capacity>& object,
                                  const Eigen::Transform<Scalar, 3, Eigen::Isometry>& object_pose,
                                  HandContacts<Scalar>& out) {
  out.count = 0;
  if (!hand.posed() || object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  const Eigen::Transform<Scalar, 3, Eigen::Isometry> to_object = object_pose.inverse(Eigen::Isometry);
  detail::PhalanxQuery<Scalar, Samples> q;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    for (int i = 0; i < 2 * Samples - 1; ++i) {
      q.nodes[static_cast<std::size_t>(i)].center = to_object * hand.phalanx_node(k, i).center;
      q.nodes[static_cast<std::size_t>(i)].radius = hand.phalanx_node(k, i).radius;
    }
    q.leaf.fill(-1);
    for (int o = 0; o < object.tree().size(); ++o) {
      if (!object.is_solid_leaf(o)) continue;
      const SphereNode<Scalar>& on = object.tree().node(o);
      for (int j = 0; j < Samples; ++j) {
        const BoundingSphere<Scalar>& s = q.nodes[static_cast<std::size_t>(Samples - 1 + j)];
        const Scalar r = s.radius + on.radius;
        if ((s.center - on.center).squaredNorm() <= r * r) detail::leaf_pair(q, j, object, o);
      }
    }
    HandContact<Scalar>& c = out.items[static_cast<std::size_t>(out.count)];
    if (detail::combine(q, hand.capsule(k).radius, object, object_pose, c)) {
      c.finger = phalanx_finger(k);
      c.phalanx = phalanx_kind(k);
      ++out.count;
    }
  }
  return Status::Ok;
}

}  // namespace grip
