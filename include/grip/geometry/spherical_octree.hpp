#pragma once
/// \file
/// Spherical octrees of objects (paper section 3), built from a signed distance field: a
/// Shape (shape.hpp), a mesh's field (mesh_shape.hpp), or any type with
///   Scalar distance(const Vector3<Scalar>& p, Vector3<Scalar>& outward_normal) const;
///   bool bounding_box(Vector3<Scalar>& lo, Vector3<Scalar>& hi) const;
/// whose distance is exact outside and never larger than the true depth inside.
///
/// The octree is the broad phase of collision detection (collision.hpp): its leaves cover the
/// shape, so a sphere that touches the shape overlaps a solid leaf. Its per-leaf surface model
/// (below) is what the paper mode of collision.hpp measures depths with.
///
/// The root is the cube around the shape's bounding box; a cell of half edge h is bounded by
/// the sphere of radius sqrt(3) h around its centre c. With phi the shape's SDF:
/// - phi(c) >  sqrt(3) h: the cell is outside the shape: dropped;
/// - phi(c) < -sqrt(3) h: the cell lies inside: kept as an (interior) leaf, not subdivided;
/// - otherwise the cell may meet the surface: subdivided into its 8 octants until the
///   maximum depth, where it becomes a (boundary) leaf.
/// A subdivided cell none of whose octants is kept stays as a childless node of kind Empty
/// (ignored by queries). So every point of the shape lies in some solid leaf cell, and every
/// point of a solid leaf cell lies within 2 sqrt(3) h of the shape (tested: containment and
/// convergence).
///
/// Leaf over-reach and its correction. A leaf sphere circumscribing a cube cell sticks out
/// beyond the cell by (sqrt(3) - 1) / 2 = 0.366 of the cell edge (beyond the surface by up to
/// 2 sqrt(3) h for a boundary cell), so depths measured against leaf spheres would be biased
/// by up to that much. Each leaf therefore also stores the true signed distance phi(c) and
/// the unit outward normal n(c) at its centre: the local surface model
///   phi_leaf(x) = phi(c) + n(c) . (x - c),
/// the tangent plane of the surface point c - phi(c) n(c). Collision uses phi_leaf, not the
/// leaf spheres (those only prune).
///
/// Accuracy per depth (root cube of half edge H, depth d: leaf half edge h = H / 2^d).
/// For a convex shape phi is convex, so phi_leaf(x) <= phi(x): each leaf gives a lower bound,
/// exact on planar faces (box faces, cylinder caps, within the face's region). On a curved
/// surface of radius R (sphere, cylinder side, capsule) the leaf holding the surface point
/// nearest x has its centre within sqrt(3) h of it, so the best leaf's error is at most
///   e(d) = 3 h^2 (R + s) / (2 R^2),   s = phi(x) clamped to >= 0,
/// about 1.5 h^2 / R: it falls 4-fold per level. Example, a 35 mm cylinder of height
/// 140 mm (H = 70 mm): d = 4: h = 4.4 mm, e <= 0.82 mm; d = 5: 0.21 mm; d = 6: 0.05 mm.
/// For a union of primitives the leaf model is that of the nearest primitive at c.

#include <array>
#include <cmath>
#include <cstdint>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/shape.hpp"
#include "grip/geometry/sphere_tree.hpp"

namespace grip {

/// The local surface model stored with each octree node (see the file comment).
template <class Scalar>
struct SurfacePlane {
  Scalar distance{0};                                ///< phi(c) (m): signed distance of the cell centre.
  Vector3<Scalar> normal{Vector3<Scalar>::UnitZ()};  ///< n(c): unit outward normal of the nearest surface.
};

/// What an octree cell is.
enum class CellKind : std::uint8_t {
  Interior,  ///< Entirely inside the shape: a leaf above the maximum depth.
  Boundary,  ///< May meet the surface: an inner node, or a leaf at the maximum depth.
  Empty,     ///< Subdivided, but none of its octants reaches the shape: a childless node to ignore.
};

/// Largest supported octree depth.
constexpr int max_octree_depth = 15;

/// A spherical octree of at most Capacity nodes (cells), in the object's frame.
/// Build once with build() (no heap); query per frame through tree(), plane() and
/// cell_half_edge().
template <class Scalar, int Capacity>
class SphericalOctree {
 public:
  static constexpr int capacity = Capacity;      ///< Most cells held.
  using Tree = SphereTree<Scalar, Capacity, 8>;  ///< The cells: a sphere tree of branching 8.

  /// Builds the octree of the distance field `shape` (a Shape, a MeshShape, ...: see the file
  /// comment) down to `max_depth` (0 .. max_octree_depth; 0 gives the root cell alone).
  /// Statuses: InvalidInput if the shape is empty, holds bad numbers or gives a non-finite
  /// distance, max_depth is out of range, or the cells do not fit in Capacity (then the tree
  /// is left empty: raise Capacity or lower max_depth; required_capacity() tells how many).
  /// Children are visited in octant order o = 0..7: bit 0 set = +x half, bit 1 = +y, bit 2 = +z.
  template <class Field>
  Status build(const Field& shape, int max_depth) {
    tree_.clear();
    depth_ = 0;
    needed_ = 0;
    Vector3<Scalar> lo = Vector3<Scalar>::Zero(), hi = Vector3<Scalar>::Zero();
    if (max_depth < 0 || max_depth > max_octree_depth || !shape.bounding_box(lo, hi) || !lo.allFinite() ||
        !hi.allFinite())
      return Status::InvalidInput;
    const Scalar sqrt3 = std::sqrt(Scalar(3));
    const Vector3<Scalar> c0 = (lo + hi) / Scalar(2);
    // Slightly larger than the bounding box so that surfaces never lie on the root's faces.
    half_edge_[0] = (hi - lo).maxCoeff() / Scalar(2) * (Scalar(1) + Scalar(1e-3));
    for (int l = 1; l <= max_octree_depth; ++l) half_edge_[detail::idx(l)] = half_edge_[detail::idx(l - 1)] / Scalar(2);
    Vector3<Scalar> n;
    const Scalar phi0 = shape.distance(c0, n);
    if (!std::isfinite(phi0) || !n.allFinite()) return Status::InvalidInput;
    tree_.add_root(c0, sqrt3 * half_edge_[0]);
    planes_[0] = SurfacePlane<Scalar>{phi0, n};
    kind_[0] = phi0 < -sqrt3 * half_edge_[0] ? CellKind::Interior : CellKind::Boundary;
    needed_ = 1;
    bool overflow = false;
    for (int i = 0; i < tree_.size(); ++i) {
      const SphereNode<Scalar>& cell = tree_.node(i);
      const int level = cell.level;
      const Scalar phi = planes_[detail::idx(i)].distance;
      if (level >= max_depth || phi < -cell.radius) continue;  // boundary leaf or interior leaf
      const Scalar hc = half_edge_[detail::idx(level + 1)];
      const Scalar rc = sqrt3 * hc;
      const Vector3<Scalar> parent_center = cell.center;
      for (int o = 0; o < 8; ++o) {
        const Vector3<Scalar> c =
            parent_center + Vector3<Scalar>((o & 1) ? hc : -hc, (o & 2) ? hc : -hc, (o & 4) ? hc : -hc);
        const Scalar d = shape.distance(c, n);
        if (!std::isfinite(d) || !n.allFinite()) {
          tree_.clear();
          depth_ = 0;
          return Status::InvalidInput;
        }
        if (d > rc) continue;
        ++needed_;
        if (overflow) continue;
        const int k = tree_.add_child(i, c, rc);
        if (k < 0) {
          overflow = true;
          continue;
        }
        planes_[detail::idx(k)] = SurfacePlane<Scalar>{d, n};
        kind_[detail::idx(k)] = d < -rc ? CellKind::Interior : CellKind::Boundary;
        if (level + 1 > depth_) depth_ = level + 1;
      }
      // The parent's sphere met the surface but no octant's does: nothing of the shape here.
      if (!overflow && cell.child_count == 0) kind_[detail::idx(i)] = CellKind::Empty;
      if (overflow) {
        tree_.clear();
        depth_ = 0;
        return Status::InvalidInput;
      }
    }
    return Status::Ok;
  }

  /// The sphere tree of cells (node spheres circumscribe their cubes).
  const Tree& tree() const { return tree_; }
  /// Surface model of cell i (meaningful for every cell; used at leaves). Precondition
  /// (GRIP_ASSERT): 0 <= i < tree().size().
  const SurfacePlane<Scalar>& plane(int i) const {
    GRIP_ASSERT(i < tree_.size());
    return planes_[detail::idx(i)];
  }
  /// Half edge (m) of the cubes at `level` (0 = root). Precondition (GRIP_ASSERT):
  /// 0 <= level <= max_octree_depth.
  Scalar cell_half_edge(int level) const {
    GRIP_ASSERT(level <= max_octree_depth);
    return half_edge_[detail::idx(level)];
  }
  /// Kind of cell i. Precondition (GRIP_ASSERT): 0 <= i < tree().size().
  CellKind kind(int i) const {
    GRIP_ASSERT(i < tree_.size());
    return kind_[detail::idx(i)];
  }
  /// True if leaf i lies entirely inside the shape (an interior cell).
  bool is_interior(int i) const { return kind(i) == CellKind::Interior; }
  /// True if cell i is a leaf holding part of the shape (interior, or boundary at full depth).
  bool is_solid_leaf(int i) const { return tree_.is_leaf(i) && kind(i) != CellKind::Empty; }
  /// Number of solid leaves.
  int leaf_count() const {
    int n = 0;
    for (int i = 0; i < tree_.size(); ++i) n += is_solid_leaf(i) ? 1 : 0;
    return n;
  }
  /// Deepest level reached by the last build.
  int depth() const { return depth_; }
  /// Cells the last build needed: > capacity when it failed for lack of room (counted up to
  /// the failure point plus the children of the cells already stored: a lower bound).
  long required_capacity() const { return needed_; }

  /// Index of the leaf whose cube contains object-frame point p, or -1 if none does (p is
  /// outside the shape, beyond the kept cells).
  int find_leaf(const Vector3<Scalar>& p) const {
    if (tree_.empty()) return -1;
    int i = 0;
    if (!(((p - tree_.node(0).center).cwiseAbs().maxCoeff()) <= half_edge_[0])) return -1;
    while (!tree_.is_leaf(i)) {
      const SphereNode<Scalar>& nd = tree_.node(i);
      const Scalar h = half_edge_[detail::idx(nd.level + 1)];
      int next = -1;
      for (int k = nd.first_child; k < nd.first_child + nd.child_count; ++k)
        if ((p - tree_.node(k).center).cwiseAbs().maxCoeff() <= h) {
          next = k;
          break;
        }
      if (next < 0) return -1;
      i = next;
    }
    return kind(i) == CellKind::Empty ? -1 : i;
  }

 private:
  Tree tree_{};
  std::array<SurfacePlane<Scalar>, detail::idx(Capacity)> planes_{};
  std::array<CellKind, detail::idx(Capacity)> kind_{};
  std::array<Scalar, max_octree_depth + 1> half_edge_{};
  int depth_{0};
  long needed_{0};
};

}  // namespace grip
