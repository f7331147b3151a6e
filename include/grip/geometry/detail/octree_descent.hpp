#pragma once
/// \file
/// Stage 2 of the paper's collision detection (section 3), the broad phase of
/// collision.hpp: the recursive descent of an object's spherical octree against one phalanx.
///
/// A phalanx's sphere tree has collinear leaves (x_j, r), so instead of splitting its inner
/// spheres the descent tests each octree node against the capsule those leaves sweep (a
/// tighter bound than any inner sphere), and at an octree leaf takes the samples whose
/// spheres reach it directly:
///   |x_j - c| <= r + rho  <=>  |s_j - s_c| <= sqrt((r + rho)^2 - d_perp^2)  along the axis,
/// an index range [j0, j1]. The leaf pairs found are exactly those of a sphere-by-sphere
/// descent (detect_contacts_exhaustive in collision.hpp is the unpruned reference).

#include <algorithm>
#include <cmath>

#include "grip/core/types.hpp"
#include "grip/geometry/spherical_octree.hpp"

namespace grip {
namespace detail {

/// One phalanx axis in the octree's frame: Samples points a + j spacing axis, swept by a
/// sphere of `radius` (the sample radius, inflated by the caller where it wants a margin).
template <class Scalar>
struct SegmentQuery {
  Vector3<Scalar> a{Vector3<Scalar>::Zero()};     ///< sample 0
  Vector3<Scalar> axis{Vector3<Scalar>::Zero()};  ///< unit direction (zero for a point)
  Scalar length{0};                               ///< |tip - base|
  Scalar spacing{0};                              ///< length / (samples - 1)
  Scalar radius{0};                               ///< swept radius
  int samples{2};                                 ///< number of samples

  /// The query of samples evenly spread over [a, b] with swept radius `r`.
  static SegmentQuery make(const Vector3<Scalar>& a, const Vector3<Scalar>& b, Scalar r, int samples) {
    SegmentQuery q;
    q.a = a;
    const Vector3<Scalar> ab = b - a;
    q.length = ab.norm();
    q.axis = q.length > Scalar(0) ? Vector3<Scalar>(ab / q.length) : Vector3<Scalar>::Zero();
    q.spacing = q.length / Scalar(samples - 1);
    q.radius = r;
    q.samples = samples;
    return q;
  }
};

/// Squared distance from point v (relative to sample 0) to the segment, and the axial
/// coordinate s of v (unclamped).
template <class Scalar>
Scalar segment_distance2(const SegmentQuery<Scalar>& seg, const Vector3<Scalar>& v, Scalar& s) {
  s = v.dot(seg.axis);
  const Scalar sc = std::min(std::max(s, Scalar(0)), seg.length);
  return (v - sc * seg.axis).squaredNorm();
}

/// Octree leaf o in reach of the segment: calls visit(o, j0, j1) with the samples j0..j1
/// whose spheres reach it (none if the range is empty). v = leaf centre - sample 0.
template <class Scalar, class Visit>
bool visit_leaf(const SegmentQuery<Scalar>& seg, int o, const Vector3<Scalar>& v, Scalar s, Scalar reach,
                Visit& visit) {
  if (!(seg.spacing > Scalar(0))) return visit(o, 0, seg.samples - 1);  // a point: every sample is at a
  const Scalar perp2 = v.squaredNorm() - s * s;
  const Scalar w = std::sqrt(std::max(reach * reach - perp2, Scalar(0)));
  const Scalar jlo = std::ceil((s - w) / seg.spacing), jhi = std::floor((s + w) / seg.spacing);
  const int j0 = jlo < Scalar(0) ? 0 : static_cast<int>(std::min(jlo, Scalar(seg.samples)));
  const int j1 = jhi > Scalar(seg.samples - 1) ? seg.samples - 1 : static_cast<int>(std::max(jhi, Scalar(-1)));
  return j0 <= j1 ? visit(o, j0, j1) : true;
}

/// Visits the children of octree node o (itself in reach): each child in reach is a leaf to
/// visit or a node to descend into (the reach test is made before the call, so that the many
/// children out of reach cost no call). Returns false as soon as `visit` does (it has all it
/// needs), true otherwise.
template <class Scalar, int Capacity, class Visit>
bool descend(const SegmentQuery<Scalar>& seg, const SphericalOctree<Scalar, Capacity>& oct, int o, Visit& visit) {
  const SphereNode<Scalar>& on = oct.tree().node(o);
  const int end = on.first_child + on.child_count;
  for (int k = on.first_child; k < end; ++k) {
    const SphereNode<Scalar>& cn = oct.tree().node(k);
    const Vector3<Scalar> v = cn.center - seg.a;
    Scalar s;
    const Scalar reach = seg.radius + cn.radius;
    if (segment_distance2(seg, v, s) > reach * reach) continue;
    if (cn.child_count > 0) {
      if (!descend(seg, oct, k, visit)) return false;
    } else if (oct.kind(k) != CellKind::Empty) {
      if (!visit_leaf(seg, k, v, s, reach, visit)) return false;
    }
  }
  return true;
}

/// The descent from the octree's root.
template <class Scalar, int Capacity, class Visit>
void descend_from_root(const SegmentQuery<Scalar>& seg, const SphericalOctree<Scalar, Capacity>& oct, Visit& visit) {
  const SphereNode<Scalar>& root = oct.tree().node(0);
  const Vector3<Scalar> v = root.center - seg.a;
  Scalar s;
  const Scalar reach = seg.radius + root.radius;
  if (segment_distance2(seg, v, s) > reach * reach) return;
  if (root.child_count > 0)
    descend(seg, oct, 0, visit);
  else if (oct.kind(0) != CellKind::Empty)
    visit_leaf(seg, 0, v, s, reach, visit);
}

}  // namespace detail
}  // namespace grip
