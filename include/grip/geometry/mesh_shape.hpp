#pragma once
/// \file
/// The signed distance field of a closed triangle mesh (MeshShape), with an axis-aligned
/// bounding-box hierarchy in fixed storage, hierarchical winding numbers, and a view whose
/// sign comes from the winding number (WindingSignedDistance). No heap.
///
/// Hierarchy. build() sorts the triangles into a binary tree of axis-aligned boxes: each node
/// is split at the median (rounded to a multiple of 4) of its triangles' centroids along the
/// axis whose two halves have the least total box surface, down to leaves of 4 triangles (one leaf may hold fewer),
/// breadth first without recursion. The tree is then collapsed into a 4-wide one (each node
/// holds its grandchildren's boxes) for distance queries; the binary one serves winding numbers.
///
/// Distance (per frame). The closest surface point q of p is found by a depth-first descent
/// of the 4-wide hierarchy, nearest box first, pruning every box no nearer than the best
/// triangle so far (a fixed stack of 64 entries: the median split bounds the depth by
/// log2 T). Each node's 4 box distances, and each leaf's 4 triangle distances (projection onto
/// the plane when it falls inside, else the nearest of the three edges), are computed
/// together without branches in SIMD lanes; a leaf whose oriented box (third axis along its
/// triangles' mean normal: tight around a curved patch) is no nearer than the best is skipped
/// before its triangles. The best triangle's closest point and feature are
/// then those of its lane's formulas (the face's projection or the nearest point of an edge):
/// the distance is exact (to rounding).
///
/// Sign: that of (p - q) . n, n the angle-weighted pseudo-normal of the feature holding q
/// (face normal, the sum of an edge's two face normals, or the vertex pseudo-normal), which
/// Baerentzen and Aanaes (2005) prove correct for closed, consistently oriented 2-manifolds:
/// the meshes TriangleMesh::finalize() accepts (a self-intersecting surface is not detected,
/// and there the sign is not the winding number's). Negative inside. The normal is the unit
/// outward gradient: sign (p - q) / |p - q|,
/// or the feature's unit pseudo-normal when |p - q| <= tiny_distance() (sqrt(eps) times the
/// largest side of the bounding box), where rounding would spoil the direction. A point that
/// is not finite or beyond ScalarTraits::max_magnitude gets +max_magnitude (outside).
///
/// Winding number (offline). w(p) = sum of the triangles' solid angles / 4 pi: 1 inside, 0
/// outside, 1/2 on the surface (Jacobson, Kavan and Sorkine-Hornung 2013). winding_number()
/// descends the hierarchy: a node whose centre c (area-weighted centroid) is farther from p
/// than far_field() times its radius r (largest distance from c to its vertices) counts as a
/// dipole, N . (c - p) / |c - p|^3 with N the area-weighted normal sum (Barill, Dickson,
/// Schmidt, Levin and Jacobson 2018); nearer leaves sum exact solid angles. The kernel's
/// gradient is bounded by 2 / |x - p|^3, so a far node's error is at most
///   A 2 r / (4 pi (d - r)^3)        (A its area, d = |c - p|),
/// and the overload with `error_bound` returns the sum of those over the far nodes: a
/// rigorous but pessimistic bound. Actual errors are far smaller: at the default
/// far_field() = 2, below 0.06 on the test meshes (within 10 mm of their surface and in their
/// boxes), falling about as far_field()^-2: far below the margin of 1/2 that the inside test
/// w >= 1/2 has off the surface of a closed mesh (there the exact w is 0 or 1).
///
/// Storage (bytes, Scalar of s bytes): per triangle of MaxTriangles 36.75 s + 20 (its lane of
/// a leaf block, 20 s + 4; a quarter of the block's oriented box, 3.75 s; half a binary node
/// and its winding data, 7 s + 4; a quarter of a 4-wide node, 6 s + 8; the build's order, 4):
/// double 314 B, float 167 B, on top of the TriangleMesh. There are 2 ceil(T / 4) - 1 binary nodes and fewer than
/// ceil(T / 4) 4-wide ones.

#include <array>
#include <cmath>
#include <limits>

#include "grip/core/index.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/triangle.hpp"
#include "grip/geometry/triangle_block.hpp"
#include "grip/geometry/triangle_mesh.hpp"

namespace grip {

/// One node of a MeshShape's box hierarchy.
template <class Scalar>
struct MeshBoxNode {
  Vector3<Scalar> lo{Vector3<Scalar>::Zero()};  ///< Box corner, smallest coordinates.
  Vector3<Scalar> hi{Vector3<Scalar>::Zero()};  ///< Box corner, largest coordinates.
  int first{0};  ///< Leaf: its block of triangles; inner: left child (the right one is first + 1).
  int count{0};  ///< Leaf: triangles held, 1 to 4; inner: 0.
};

/// The far-field data of a node for winding numbers.
template <class Scalar>
struct MeshWindingNode {
  Vector3<Scalar> center{Vector3<Scalar>::Zero()};      ///< Area-weighted centroid of the triangles.
  Vector3<Scalar> normal_sum{Vector3<Scalar>::Zero()};  ///< Sum of area times unit normal.
  Scalar radius{0};                                     ///< Largest distance from center to a vertex.
  Scalar area{0};                                       ///< Total area.
};

/// The signed distance field of a finalized TriangleMesh. The mesh must outlive the shape
/// and stay unchanged after build(). Large: put it in static storage or a member.
template <class Scalar, int MaxVertices, int MaxTriangles>
class MeshShape {
 public:
  using ScalarType = Scalar;                                     ///< The scalar type.
  using Mesh = TriangleMesh<Scalar, MaxVertices, MaxTriangles>;  ///< The mesh type.
  static constexpr int leaf_size = 4;                            ///< Triangles per leaf (one leaf may hold fewer).
  static constexpr int stack_size = 64;  ///< Traversal stack entries (3 per level of the 4-wide tree, + 4).
  static constexpr int max_nodes = 2 * ((MaxTriangles + 3) / 4);  ///< Node storage (binary hierarchy).
  static constexpr int max_quads = (MaxTriangles + 3) / 4;        ///< Node storage (4-wide hierarchy).

  /// Builds the hierarchy over a finalized mesh (kept by pointer). InvalidInput, and an
  /// empty shape, if the mesh is not finalized Ok. Offline: O(T log T). If the mesh changes
  /// afterwards (its revision()), the shape answers as an unbuilt one until built again.
  Status build(const Mesh& mesh);
  /// True after a successful build(), while the mesh is unchanged.
  bool built() const { return mesh_ != nullptr && mesh_->revision() == revision_; }
  /// The mesh of the last successful build(), or nullptr.
  const Mesh* mesh() const { return mesh_; }
  /// Nodes in the binary box hierarchy.
  int node_count() const { return node_count_; }
  /// Nodes in the 4-wide box hierarchy of distance queries.
  int quad_count() const { return quad_count_; }

  /// Signed distance (m) of p, negative inside; `normal` receives the unit outward gradient
  /// (see the file comment). Per frame: no heap, O(log T) typical. +max_magnitude and
  /// normal UnitZ before build().
  Scalar distance(const Vector3<Scalar>& p, Vector3<Scalar>& normal) const;
  /// Signed distance (m) of p.
  Scalar distance(const Vector3<Scalar>& p) const {
    Vector3<Scalar> n = Vector3<Scalar>::UnitZ();
    return distance(p, n);
  }
  /// The narrow phase's query (collision.hpp): the exact signed distance `phi` and outward
  /// normal of p, as distance() gives them, when the surface lies within `limit` (m) of p;
  /// false (phi and normal unchanged) when it does not, or before build(). `hint` starts the
  /// search: pass -1, or the value a query of a nearby point left (an opaque slot of the
  /// hierarchy); it receives p's. A good hint and a small limit prune most of the hierarchy.
  bool distance_within(const Vector3<Scalar>& p, Scalar limit, Scalar& phi, Vector3<Scalar>& normal, int& hint) const;
  /// The narrow phase's refinement: the least squared distance between segment [p0, p1] and
  /// the triangle that `hint` (a value distance_within() left) names, with `u` the segment
  /// parameter in [0, 1] of a point attaining it (segment_triangle_distance2()); +infinity and
  /// u = 0 for a hint that names no triangle, or before build().
  Scalar segment_distance2(int hint, const Vector3<Scalar>& p0, const Vector3<Scalar>& p1, Scalar& u) const;
  /// Unsigned distance (m) to the surface; writes the closest point q, its mesh triangle and
  /// the feature of that triangle holding q. Returns +max_magnitude and triangle -1 before
  /// build() or for a point not finite or beyond max_magnitude.
  Scalar closest_point(const Vector3<Scalar>& p, Vector3<Scalar>& q, int& triangle, TriangleFeature& feature) const;
  /// Unit outward pseudo-normal of `feature` of mesh triangle t.
  Vector3<Scalar> pseudo_normal(int t, TriangleFeature feature) const;
  /// Distance below which normals are pseudo-normals: sqrt(eps) times the box's largest side.
  Scalar tiny_distance() const { return tiny_; }

  /// Generalized winding number at p by the hierarchy (0 before build()).
  Scalar winding_number(const Vector3<Scalar>& p) const {
    Scalar bound = Scalar(0);
    return winding_number(p, bound);
  }
  /// Generalized winding number at p; `error_bound` receives a rigorous bound on its error.
  Scalar winding_number(const Vector3<Scalar>& p, Scalar& error_bound) const;
  /// Generalized winding number at p summing every triangle's solid angle: O(T).
  Scalar winding_number_exact(const Vector3<Scalar>& p) const;
  /// Sets the far-field factor beta (>= 1; +infinity makes winding_number() exact): a node
  /// counts as a dipole when its centre is farther than beta times its radius. InvalidInput
  /// (unchanged) otherwise.
  Status set_far_field(Scalar beta) {
    if (!(beta >= Scalar(1))) return Status::InvalidInput;
    beta_ = beta;
    return Status::Ok;
  }
  /// The far-field factor (default 2).
  Scalar far_field() const { return beta_; }

  /// The mesh's axis-aligned bounding box: false (lo, hi untouched) unless built().
  bool bounding_box(Vector3<Scalar>& lo, Vector3<Scalar>& hi) const { return built() && mesh_->bounding_box(lo, hi); }
  /// Node i of the box hierarchy (0 is the root). Precondition (GRIP_ASSERT): 0 <= i < node_count().
  const MeshBoxNode<Scalar>& node(int i) const {
    GRIP_ASSERT(i < node_count_);
    return nodes_[detail::idx(i)];
  }
  /// Far-field data of node i. Precondition (GRIP_ASSERT): 0 <= i < node_count().
  const MeshWindingNode<Scalar>& winding_node(int i) const {
    GRIP_ASSERT(i < node_count_);
    return wnodes_[detail::idx(i)];
  }

 private:
  using Block = detail::TriangleBlock<Scalar>;
  Scalar slot_solid_angle(const Vector3<Scalar>& p, int s) const {
    Vector3<Scalar> a = Vector3<Scalar>::Zero(), b = a, c = a;
    blocks_[detail::idx(s / 4)].vertices(s % 4, a, b, c);
    return triangle_solid_angle(p, a, b, c);
  }
  /// +max_magnitude and the direction of p for a point out of range; false if p is fine.
  static bool out_of_range(const Vector3<Scalar>& p, Scalar& d, Vector3<Scalar>& normal);
  /// The slot (4 block + lane) of the triangle nearest p among those nearer than sqrt(best2),
  /// or `slot` unchanged if none is; best2 is lowered to its squared distance. Block `done`
  /// (-1: none) has been searched already and is skipped.
  int nearest_slot(const Vector3<Scalar>& p, Scalar& best2, int slot, int done = -1) const;
  /// The signed distance of p and its outward normal from the triangle of `slot`.
  Scalar signed_distance(const Vector3<Scalar>& p, int slot, Vector3<Scalar>& normal) const;

  void build_quads();
  void set_leaf_box(int block, int count);

  std::array<MeshBoxNode<Scalar>, max_nodes> nodes_{};
  std::array<detail::MeshQuadNode<Scalar>, max_quads> quads_{};
  std::array<MeshWindingNode<Scalar>, max_nodes> wnodes_{};
  std::array<detail::LeafBox<Scalar>, (MaxTriangles + 3) / 4> leaf_boxes_{};  // oriented box of each block
  std::array<Block, (MaxTriangles + 3) / 4> blocks_{};                        // triangles in leaf order, 4 per block
  std::array<int, MaxTriangles> slot_id_{};                                   // build: mesh triangle of each slot
  const Mesh* mesh_{nullptr};
  unsigned long revision_{0};
  int node_count_{0};
  int quad_count_{0};
  Scalar tiny_{0};
  Scalar beta_{2};
};

/// A signed distance view of a MeshShape (or any type with the same closest_point,
/// pseudo_normal, tiny_distance, winding_number and bounding_box members) whose sign comes
/// from the winding number: inside where w(p) >= 1/2. |d| and the normal's rule are those of
/// the shape. Offline use (e.g. building a spherical octree): the fast winding number costs
/// several times a distance query. Keeps a pointer: the shape must outlive the view.
template <class Field>
class WindingSignedDistance {
 public:
  using ScalarType = typename Field::ScalarType;  ///< The scalar type.

  /// A view of `field`; `exact` uses winding_number_exact (O(T)) instead of the hierarchy.
  explicit WindingSignedDistance(const Field& field, bool exact = false) : field_(&field), exact_(exact) {}

  /// Signed distance (m) of p, negative where the winding number is >= 1/2; `normal`
  /// receives the unit outward gradient.
  ScalarType distance(const Vector3<ScalarType>& p, Vector3<ScalarType>& normal) const {
    using S = ScalarType;
    Vector3<S> q = p;
    int t = -1;
    TriangleFeature f = TriangleFeature::Face;
    const S d = field_->closest_point(p, q, t, f);
    if (t < 0) {  // not built, or p out of range: outside, as the shape says
      normal = p.allFinite() && p.norm() > S(0) ? Vector3<S>(p.normalized()) : Vector3<S>(Vector3<S>::UnitZ());
      return d;
    }
    const S w = exact_ ? field_->winding_number_exact(p) : field_->winding_number(p);
    const S sign = w >= S(0.5) ? S(-1) : S(1);
    normal = d > field_->tiny_distance() ? Vector3<S>((p - q) * (sign / d)) : field_->pseudo_normal(t, f);
    return sign * d;
  }
  /// Signed distance (m) of p.
  ScalarType distance(const Vector3<ScalarType>& p) const {
    Vector3<ScalarType> n;
    return distance(p, n);
  }
  /// The shape's axis-aligned bounding box (false before it is built).
  bool bounding_box(Vector3<ScalarType>& lo, Vector3<ScalarType>& hi) const { return field_->bounding_box(lo, hi); }

 private:
  const Field* field_;
  bool exact_;
};

/// The winding-number-signed view of `shape` (see WindingSignedDistance).
template <class Field>
WindingSignedDistance<Field> winding_signed(const Field& shape, bool exact = false) {
  return WindingSignedDistance<Field>(shape, exact);
}

}  // namespace grip

#include "grip/geometry/mesh_shape_build.hpp"
#include "grip/geometry/mesh_shape_query.hpp"
