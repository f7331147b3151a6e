#pragma once
/// \file
/// The paper mode of collision.hpp: each sample's signed distance estimated from the octree
/// leaves' tangent planes (spherical_octree.hpp), then one contact per phalanx from the
/// penetrating samples (the depth-weighted mean normal and point).

#include <array>

#include <Eigen/Geometry>

#include "grip/core/index.hpp"
#include "grip/core/types.hpp"
#include "grip/collision/hand_collision_model.hpp"
#include "grip/collision/hand_contact.hpp"
#include "grip/geometry/spherical_octree.hpp"

namespace grip {
namespace detail {

/// Paper mode: per-sample best leaf-plane estimate.
template <class Scalar, int Samples, int Capacity>
struct PlaneEstimates {
  const SphericalOctree<Scalar, Capacity>* oct;
  std::array<Vector3<Scalar>, Samples> x;  // sample centres, object frame
  std::array<Scalar, Samples> phi;
  std::array<int, Samples> leaf;
  bool operator()(int o, int j0, int j1) {
    const SurfacePlane<Scalar>& pl = oct->plane(o);
    for (int j = j0; j <= j1; ++j) {
      const auto sj = detail::idx(j);
      const Scalar d = pl.distance + pl.normal.dot(x[sj] - oct->tree().node(o).center);
      if (leaf[sj] < 0 || d > phi[sj]) {
        phi[sj] = d;
        leaf[sj] = o;
      }
    }
    return true;
  }
};

/// Paper mode: the estimates of phalanx k into at most one contact (world frame out).
template <class Scalar, int Samples, int Capacity>
bool combine_planes(const PlaneEstimates<Scalar, Samples, Capacity>& q, Scalar radius,
                    const Eigen::Transform<Scalar, 3, Eigen::Isometry>& pose, HandContact<Scalar>& out) {
  Scalar depth = Scalar(0), wsum = Scalar(0);
  int count = 0, deepest = -1;
  Vector3<Scalar> nsum = Vector3<Scalar>::Zero(), psum = Vector3<Scalar>::Zero();
  for (int j = 0; j < Samples; ++j) {
    const auto sj = detail::idx(j);
    if (q.leaf[sj] < 0) continue;
    const Scalar p = radius - q.phi[sj];
    if (!(p > Scalar(0))) continue;
    const Vector3<Scalar>& n = q.oct->plane(q.leaf[sj]).normal;
    nsum += p * n;
    psum += p * (q.x[sj] - q.phi[sj] * n);
    wsum += p;
    ++count;
    if (p > depth) {
      depth = p;
      deepest = j;
    }
  }
  if (count == 0) return false;
  const Scalar nn = nsum.norm();
  const Vector3<Scalar> n_out =
      nn > Scalar(1e-3) * wsum ? Vector3<Scalar>(nsum / nn) : q.oct->plane(q.leaf[detail::idx(deepest)]).normal;
  out.depth = depth;
  out.samples = count;
  out.sample = deepest;
  out.axis_parameter = Scalar(deepest) / Scalar(Samples - 1);
  out.point = pose * Vector3<Scalar>(psum / wsum);
  out.normal = -(pose.linear() * n_out).normalized();
  return true;
}

/// Paper mode: the estimates of phalanx k reset, sample centres in the object frame.
template <class Scalar, int Samples, int Capacity>
void reset_estimates(PlaneEstimates<Scalar, Samples, Capacity>& q, const HandCollisionModel<Scalar, Samples>& hand,
                     int k, const Eigen::Transform<Scalar, 3, Eigen::Isometry>& to_object) {
  for (int j = 0; j < Samples; ++j) q.x[detail::idx(j)] = to_object * hand.phalanx_node(k, Samples - 1 + j).center;
  q.leaf.fill(-1);
}

/// Paper mode: appends phalanx k's contact, when combine_planes() finds one, to `out` (which
/// has room: a phalanx gives at most one contact, out.count < out.capacity).
template <class Scalar, int Samples, int Capacity>
void append_combined(const PlaneEstimates<Scalar, Samples, Capacity>& q, Scalar radius,
                     const Eigen::Transform<Scalar, 3, Eigen::Isometry>& pose, int k, HandContacts<Scalar>& out) {
  GRIP_ASSERT(out.count < HandContacts<Scalar>::capacity);
  HandContact<Scalar>& c = out.items[detail::idx(out.count)];
  if (!combine_planes(q, radius, pose, c)) return;
  c.finger = phalanx_finger(k);
  c.phalanx = phalanx_kind(k);
  ++out.count;
}

}  // namespace detail
}  // namespace grip
