#pragma once
/// \file
/// Contacts between the posed hand and an object (paper section 3): the hand's sphere
/// hierarchy and the object's spherical octree find what can touch (the broad phase); the
/// object's own signed distance field decides depth, point and normal (the narrow phase).
///
/// Broad phase (the paper's two-stage recursive detection). Stage 1 tests the hand's sphere,
/// then each digit's, then each phalanx tree's root against the octree's root sphere; stage 2
/// descends the octree against each remaining phalanx (detail/octree_descent.hpp). A sample
/// sphere is "in reach" when, inflated by half the sample spacing, it overlaps a solid leaf.
/// The leaves cover the object, so a sample farther than that from the object is the only
/// kind ever skipped. A field with a bounded query (a MeshShape) is its own, finer stage 2:
/// every sample of a phalanx that passes stage 1 asks it, with the band as the limit, and the
/// octree answers only whether a missed sample's centre may lie inside (the same contacts).
///
/// Narrow phase (detail/narrow_phase.hpp). The field gives each sample in reach its exact
/// signed distance phi_j and outward normal n_j; each local minimum of phi_j within half a
/// spacing of touching is refined along the axis towards the capsule's deepest point; what
/// penetrates becomes at most K contacts per phalanx (K = HandContacts' PerPhalanx): depth
/// dr = r - phi at the contact's axis point x, normal -n(x) (into the object), point
/// x - phi(x) n(x), the surface point nearest x.
///
/// Bounds (r the phalanx radius, s its sample spacing; tests/collision/collision_bounds.test.cpp):
/// - Convex fields (sphere, box, cylinder, capsule; a union where the deepest point's
///   primitive is the only one within reach), with K = 1: the contact is the capsule's
///   deepest point, on faces, edges, rims, corners and for deep samples alike: depth
///   r - min_t phi(t) within tol = ContactSettings::refine_tolerance (1e-12 m in double,
///   1e-7 m in float by default); no contact unless the capsule penetrates by more than tol,
///   and none missed where it penetrates by more. The contact's axis point x is one whose
///   distance is within tol of the least, its point and normal exact for x; they are within
///   sqrt(2 tol R) (m) and sqrt(2 tol / R) (rad) of the deepest axis point's, R the radius of
///   curvature there of the level surface of phi (a sphere's: the distance from its centre; a
///   cylinder side's: from its axis; near an edge or corner: from it), and exact on a face.
/// - Meshes are refined triangle by triangle (detail/narrow_phase.hpp), then by the slopes
///   where that does not certify its point: exact for a convex mesh as above; on others the
///   bounds of any field below hold.
/// - Any field (meshes, unions): every depth is a true penetration of the capsule (never
///   more than its deepest), at least that of the deepest sample, and at least the capsule's
///   true depth minus s / 2 (phi is 1-Lipschitz); each contact's point and normal are exact
///   for its axis point.
/// - Inside a union the field is a bound (shape.hpp): depths there are a lower bound.
/// - The paper mode (detect_contacts without a field) measures depth against the octree
///   leaves' tangent planes: exact on planar faces, within e(d) of spherical_octree.hpp on
///   curved ones, and wrong near edges, rims and corners (a leaf carries one face's plane).
///   It needs no distance field at run time.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/collision/detail/narrow_phase.hpp"
#include "grip/geometry/detail/octree_descent.hpp"
#include "grip/collision/detail/paper_contacts.hpp"
#include "grip/collision/hand_collision_model.hpp"
#include "grip/collision/hand_contact.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {

/// A rigid transform (rotation and translation), e.g. an object's pose: object frame to world.
template <class Scalar>
using Isometry3 = Eigen::Transform<Scalar, 3, Eigen::Isometry>;

/// The per-frame entry point: contacts between the posed hand and an object whose octree and
/// distance field `field` (a Shape, a MeshShape, ...: see spherical_octree.hpp) are given in
/// the object's frame, placed in the world by `object_pose` (object point -> world point).
/// Writes out.items[0 .. out.count): at most PerPhalanx contacts per phalanx, phalanx order.
/// Statuses: InvalidInput (out.count = 0) if the model was never posed, the octree is empty,
/// the pose is not finite and rigid (rotation orthonormal within 1e-3), or the settings are
/// out of range (refine_iterations in [0, 64], refine_tolerance >= 0, cluster_angle in
/// [0, pi]); Ok otherwise
/// (out.count may be 0). `phalanx_mask` (bit k = body k) skips bodies whose bit is clear, as
/// are those the posture does not have (HandCollisionModel::bodies(): the paper's hand has
/// no palm). No heap; recursion depth at most the octree's depth.
template <class Scalar, int Samples, int Capacity, class Field, int PerPhalanx>
Status detect_contacts(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& octree,
                       const Field& field, const Isometry3<Scalar>& object_pose, HandContacts<Scalar, PerPhalanx>& out,
                       const ContactSettings<Scalar>& settings = ContactSettings<Scalar>{},
                       std::uint32_t phalanx_mask = all_hand_bodies);

/// The same contacts without the octree: every sample of every phalanx whose sphere tree
/// reaches the field's bounding box is evaluated. For analytic shapes, whose distance is
/// cheap (CylinderScene), and as the reference of the octree's broad phase (identical
/// results). Statuses as detect_contacts, and InvalidInput for an empty field.
template <class Scalar, int Samples, class Field, int PerPhalanx>
Status detect_contacts_direct(const HandCollisionModel<Scalar, Samples>& hand, const Field& field,
                              const Isometry3<Scalar>& object_pose, HandContacts<Scalar, PerPhalanx>& out,
                              const ContactSettings<Scalar>& settings = ContactSettings<Scalar>{},
                              std::uint32_t phalanx_mask = all_hand_bodies);

/// Diagnosis of body k (0 .. 18, one the posture has): its sample centres, each one's exact signed distance and
/// outward normal (evaluated for every sample, in reach or not), and which ones the broad
/// phase found in reach. InvalidInput for k out of range, an unposed model, an empty octree
/// or a bad pose (out unchanged); Ok otherwise.
template <class Scalar, int Samples, int Capacity, class Field>
Status query_samples(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& octree,
                     const Field& field, const Isometry3<Scalar>& object_pose, int k,
                     PhalanxSamples<Scalar, Samples>& out);

/// The paper mode: depths from the octree leaves' tangent planes alone (no distance field at
/// run time; see the file comment for its bounds). At most one contact per phalanx: sample j
/// takes the best (largest) leaf-plane distance phi_j over the leaves it overlaps; with
/// p_j = r - phi_j > 0, depth = max_j p_j, inward normal = -(sum_j p_j n_j) / |sum_j p_j n_j|,
/// point = the p_j-weighted mean of x_j - phi_j n_j. Statuses as detect_contacts.
template <class Scalar, int Samples, int Capacity>
Status detect_contacts(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& object,
                       const Isometry3<Scalar>& object_pose, HandContacts<Scalar>& out,
                       std::uint32_t phalanx_mask = all_hand_bodies);

/// The paper mode with no pruning: every phalanx sample against every octree leaf (the
/// reference of the descent; same result, since every sphere contains its descendants).
template <class Scalar, int Samples, int Capacity>
Status detect_contacts_exhaustive(const HandCollisionModel<Scalar, Samples>& hand,
                                  const SphericalOctree<Scalar, Capacity>& object, const Isometry3<Scalar>& object_pose,
                                  HandContacts<Scalar>& out);

// ---------------------------------------------------------------------------------------------
// Definitions.

namespace detail {

template <class Scalar>
bool rigid_pose_ok(const Isometry3<Scalar>& pose) {
  if (!pose.matrix().allFinite()) return false;
  const Matrix3<Scalar> R = pose.linear();
  return (R.transpose() * R - Matrix3<Scalar>::Identity()).cwiseAbs().maxCoeff() <= Scalar(1e-3);
}

template <class Scalar>
bool settings_ok(const ContactSettings<Scalar>& s) {
  return s.refine_iterations >= 0 && s.refine_iterations <= 64 && s.refine_tolerance >= Scalar(0) &&
         s.cluster_angle >= Scalar(0) && s.cluster_angle <= Scalar(3.14159265358979323846);
}

/// Phalanx k of the posed hand in the object frame.
template <class Scalar, int Samples>
PhalanxAxis<Scalar> object_axis(const HandCollisionModel<Scalar, Samples>& hand, int k,
                                const Isometry3<Scalar>& to_object) {
  const PhalanxCapsule<Scalar>& c = hand.capsule(k);
  return PhalanxAxis<Scalar>{to_object * c.base, to_object * c.tip, c.radius};
}

/// The broad phase's margin of phalanx k: half its sample spacing when refining, else 0.
template <class Scalar, int Samples>
Scalar reach_margin(const HandCollisionModel<Scalar, Samples>& hand, int k, const ContactSettings<Scalar>& settings) {
  if (settings.refine_iterations <= 0) return Scalar(0);
  const PhalanxCapsule<Scalar>& c = hand.capsule(k);
  return Scalar(0.5) * (c.tip - c.base).norm() / Scalar(Samples - 1);
}

/// Marks the samples the octree descent finds in reach; stops when all are.
template <class Scalar, int Samples>
struct MarkReach {
  SampleField<Scalar, Samples>* field;
  int marked{0};
  bool operator()(int, int j0, int j1) {
    for (int j = j0; j <= j1; ++j) {
      bool& r = field->reach[detail::idx(j)];
      marked += r ? 0 : 1;
      r = true;
    }
    return marked < Samples;
  }
};

/// True if object-frame point p lies in the cube of a solid leaf below octree cell i (itself
/// holding p): any of them, where p lies on cells' common faces. Recursion depth at most the
/// octree's depth.
template <class Scalar, int Capacity>
bool in_solid_leaf(const SphericalOctree<Scalar, Capacity>& octree, int i, const Vector3<Scalar>& p) {
  const auto& tree = octree.tree();
  if (i < 0 || i >= tree.size()) return false;  // (never: children of cells are cells)
  if (tree.is_leaf(i)) return octree.kind(i) != CellKind::Empty;
  const SphereNode<Scalar>& nd = tree.node(i);
  const Scalar h = octree.cell_half_edge(nd.level + 1);
  for (int k = nd.first_child; k < nd.first_child + nd.child_count; ++k)
    if ((p - tree.node(k).center).cwiseAbs().maxCoeff() <= h && in_solid_leaf(octree, k, p)) return true;
  return false;
}

/// True if object-frame point p lies in the cube of a solid leaf of the octree.
template <class Scalar, int Capacity>
bool in_solid_leaf(const SphericalOctree<Scalar, Capacity>& octree, const Vector3<Scalar>& p) {
  const auto& tree = octree.tree();
  return !tree.empty() && (p - tree.node(0).center).cwiseAbs().maxCoeff() <= octree.cell_half_edge(0) &&
         in_solid_leaf(octree, 0, p);
}

/// Narrow phase of one phalanx (samples in reach marked in s) and its contacts appended to out.
template <class Scalar, int Samples, class Field, int PerPhalanx, class Inside>
void emit_contacts(const Field& field, const PhalanxAxis<Scalar>& ax, SampleField<Scalar, Samples>& s, int k,
                   const ContactSettings<Scalar>& settings, const Isometry3<Scalar>& pose,
                   HandContacts<Scalar, PerPhalanx>& out, Inside&& may_be_inside, JointSample<Scalar>& joint) {
  FieldProbe<Scalar, Field> probe{field};
  const Scalar band = band_of<Scalar, Samples>(ax, settings);
  evaluate_samples(probe, ax, band, s, may_be_inside, joint);
  std::array<Penetration<Scalar>, PerPhalanx> found;
  std::array<int, PerPhalanx> members{};
  const int n = phalanx_contacts<PerPhalanx>(field, probe, ax, s, band, settings, found, members);
  for (int i = 0; i < n; ++i) {
    const Penetration<Scalar>& p = found[detail::idx(i)];
    HandContact<Scalar>& c = out.items[detail::idx(out.count++)];
    c.finger = phalanx_finger(k);
    c.phalanx = phalanx_kind(k);
    c.depth = p.depth;
    c.samples = members[detail::idx(i)];
    c.sample = p.sample;
    c.axis_parameter = p.t;
    c.point = pose * Vector3<Scalar>(ax.at(p.t) - p.phi * p.normal);
    c.normal = -(pose.linear() * p.normal).normalized();
  }
}

/// Stage 1 and the per-phalanx loop shared by the octree entry points: calls
/// per_phalanx(k, to_object) for each phalanx in the mask whose tree root (inflated by
/// `margin`) overlaps the octree's root sphere.
template <class Scalar, int Samples, int Capacity, class PerPhalanxFn>
void for_phalanges_in_reach(const HandCollisionModel<Scalar, Samples>& hand,
                            const SphericalOctree<Scalar, Capacity>& octree, const Isometry3<Scalar>& object_pose,
                            Scalar margin, std::uint32_t mask, PerPhalanxFn&& per_phalanx) {
  const Isometry3<Scalar> to_object = object_pose.inverse(Eigen::Isometry);
  const SphereNode<Scalar>& root = octree.tree().node(0);
  const BoundingSphere<Scalar> root_world{object_pose * root.center, root.radius + margin};
  if (!overlap(hand.hand_sphere(), root_world)) return;
  for (int f = 0; f < HandCollisionModel<Scalar, Samples>::group_count; ++f) {
    if (!overlap(hand.finger_sphere(f), root_world)) continue;
    const int first = HandCollisionModel<Scalar, Samples>::first_phalanx(f);
    for (int k = first; k < first + HandCollisionModel<Scalar, Samples>::phalanges_of(f); ++k)
      if (((mask & hand.bodies()) >> k & 1u) && overlap(hand.phalanx_node(k, 0), root_world)) per_phalanx(k, to_object);
  }
}

}  // namespace detail

template <class Scalar, int Samples, int Capacity, class Field, int PerPhalanx>
Status detect_contacts(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& octree,
                       const Field& field, const Isometry3<Scalar>& object_pose, HandContacts<Scalar, PerPhalanx>& out,
                       const ContactSettings<Scalar>& settings, std::uint32_t phalanx_mask) {
  out.count = 0;
  if (!hand.posed() || octree.tree().empty() || !detail::rigid_pose_ok(object_pose) || !detail::settings_ok(settings))
    return Status::InvalidInput;
  Scalar margin = Scalar(0);
  for (int k = 0; k < hand_body_count; ++k) margin = std::max(margin, detail::reach_margin(hand, k, settings));
  detail::JointSample<Scalar> joint;
  detail::for_phalanges_in_reach(
      hand, octree, object_pose, margin, phalanx_mask, [&](int k, const Isometry3<Scalar>& to_object) {
        const detail::PhalanxAxis<Scalar> ax = detail::object_axis(hand, k, to_object);
        detail::SampleField<Scalar, Samples> s;
        detail::MarkReach<Scalar, Samples> mark{&s};
        if constexpr (detail::has_bounded_query<Field, Scalar>::value) {  // stage 2: the field's own hierarchy
          s.reach.fill(true);
          mark.marked = Samples;
        } else {
          detail::descend_from_root(detail::SegmentQuery<Scalar>::make(
                                        ax.a, ax.b, ax.radius + detail::reach_margin(hand, k, settings), Samples),
                                    octree, mark);
        }
        if (mark.marked > 0)
          detail::emit_contacts(
              field, ax, s, k, settings, object_pose, out,
              [&octree](const Vector3<Scalar>& x) { return detail::in_solid_leaf(octree, x); }, joint);
      });
  return Status::Ok;
}

template <class Scalar, int Samples, class Field, int PerPhalanx>
Status detect_contacts_direct(const HandCollisionModel<Scalar, Samples>& hand, const Field& field,
                              const Isometry3<Scalar>& object_pose, HandContacts<Scalar, PerPhalanx>& out,
                              const ContactSettings<Scalar>& settings, std::uint32_t phalanx_mask) {
  out.count = 0;
  Vector3<Scalar> lo, hi;
  if (!hand.posed() || !detail::rigid_pose_ok(object_pose) || !detail::settings_ok(settings) ||
      !field.bounding_box(lo, hi) || !lo.allFinite() || !hi.allFinite())
    return Status::InvalidInput;
  const Isometry3<Scalar> to_object = object_pose.inverse(Eigen::Isometry);
  const BoundingSphere<Scalar> bounds{object_pose * Vector3<Scalar>((lo + hi) / Scalar(2)),
                                      (hi - lo).norm() / Scalar(2)};
  detail::JointSample<Scalar> joint;
  for (int k = 0; k < hand_body_count; ++k) {
    if (!((phalanx_mask & hand.bodies()) >> k & 1u)) continue;
    BoundingSphere<Scalar> root = hand.phalanx_node(k, 0);
    root.radius += detail::reach_margin(hand, k, settings);
    if (!overlap(root, bounds)) continue;
    detail::SampleField<Scalar, Samples> s;
    s.reach.fill(true);
    detail::emit_contacts(
        field, detail::object_axis(hand, k, to_object), s, k, settings, object_pose, out,
        [](const Vector3<Scalar>&) { return true; }, joint);
  }
  return Status::Ok;
}

template <class Scalar, int Samples, int Capacity, class Field>
Status query_samples(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& octree,
                     const Field& field, const Isometry3<Scalar>& object_pose, int k,
                     PhalanxSamples<Scalar, Samples>& out) {
  if (k < 0 || k >= hand_body_count || !hand.posed() || !(hand.bodies() >> k & 1u) || octree.tree().empty() ||
      !detail::rigid_pose_ok(object_pose))
    return Status::InvalidInput;
  const Isometry3<Scalar> to_object = object_pose.inverse(Eigen::Isometry);
  const detail::PhalanxAxis<Scalar> ax = detail::object_axis(hand, k, to_object);
  detail::SampleField<Scalar, Samples> s;
  detail::MarkReach<Scalar, Samples> mark{&s};
  const ContactSettings<Scalar> settings{};
  detail::descend_from_root(
      detail::SegmentQuery<Scalar>::make(ax.a, ax.b, ax.radius + detail::reach_margin(hand, k, settings), Samples),
      octree, mark);
  out.radius = ax.radius;
  for (int j = 0; j < Samples; ++j) {
    const auto sj = detail::idx(j);
    Vector3<Scalar> n;
    const Vector3<Scalar> x = ax.at(Scalar(j) / Scalar(Samples - 1));
    out.distance[sj] = field.distance(x, n);
    out.center[sj] = object_pose * x;
    out.normal[sj] = object_pose.linear() * n;
    out.in_reach[sj] = s.reach[sj];
  }
  return Status::Ok;
}

template <class Scalar, int Samples, int Capacity>
Status detect_contacts(const HandCollisionModel<Scalar, Samples>& hand, const SphericalOctree<Scalar, Capacity>& object,
                       const Isometry3<Scalar>& object_pose, HandContacts<Scalar>& out, std::uint32_t phalanx_mask) {
  out.count = 0;
  if (!hand.posed() || object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  detail::PlaneEstimates<Scalar, Samples, Capacity> q{&object, {}, {}, {}};
  detail::for_phalanges_in_reach(
      hand, object, object_pose, Scalar(0), phalanx_mask, [&](int k, const Isometry3<Scalar>& to_object) {
        detail::reset_estimates(q, hand, k, to_object);
        const Scalar r = hand.capsule(k).radius;
        detail::descend_from_root(detail::SegmentQuery<Scalar>::make(q.x[0], q.x[Samples - 1], r, Samples), object, q);
        detail::append_combined(q, r, object_pose, k, out);
      });
  return Status::Ok;
}

template <class Scalar, int Samples, int Capacity>
Status detect_contacts_exhaustive(const HandCollisionModel<Scalar, Samples>& hand,
                                  const SphericalOctree<Scalar, Capacity>& object, const Isometry3<Scalar>& object_pose,
                                  HandContacts<Scalar>& out) {
  out.count = 0;
  if (!hand.posed() || object.tree().empty() || !detail::rigid_pose_ok(object_pose)) return Status::InvalidInput;
  const Isometry3<Scalar> to_object = object_pose.inverse(Eigen::Isometry);
  detail::PlaneEstimates<Scalar, Samples, Capacity> q{&object, {}, {}, {}};
  for (int k = 0; k < hand_body_count; ++k) {
    if (!(hand.bodies() >> k & 1u)) continue;
    detail::reset_estimates(q, hand, k, to_object);
    const Scalar r = hand.capsule(k).radius;
    for (int o = 0; o < object.tree().size(); ++o) {
      if (!object.is_solid_leaf(o)) continue;
      const SphereNode<Scalar>& on = object.tree().node(o);
      for (int j = 0; j < Samples; ++j) {
        const Scalar reach = r + on.radius;
        if ((q.x[detail::idx(j)] - on.center).squaredNorm() <= reach * reach) q(o, j, j);
      }
    }
    detail::append_combined(q, r, object_pose, k, out);
  }
  return Status::Ok;
}

}  // namespace grip
