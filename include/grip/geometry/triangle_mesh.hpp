#pragma once
/// \file
/// A closed triangle mesh in fixed storage: vertices welded on entry, then checked and
/// completed by finalize() (adjacency, normals, pseudo-normals, volume). No heap.
///
/// Building. add_vertex() welds exact duplicates (the same coordinates bit for bit, +0 and -0
/// equal) through an open-addressing hash table held in the object, so an STL file's
/// unshared vertices become shared ones. add_triangle() appends an index triple; the
/// outward side is the counter-clockwise one (triangle.hpp). Any add_ call clears the
/// finalized state.
///
/// finalize() accepts the mesh (status Ok) only if, in this order:
/// - it has a triangle (else Empty) and no triangle repeats a vertex or has zero area
///   (DegenerateTriangle: |(b - a) x (c - a)| <= 16 eps l^2, l the longest edge, or a squared
///   edge length or |(b - a) x (c - a)|^2 below the smallest normal number of Scalar);
/// - every directed edge u -> v is used by exactly one triangle and v -> u by exactly one
///   other: an edge of one triangle is NotClosed, of three or more NonManifold, two uses in
///   the same direction InconsistentOrientation;
/// - the triangles around each vertex form one fan (else NonManifold);
/// - each edge's two face normals and each vertex's angle-weighted normals do not cancel
///   (else FoldedSurface), and no component has zero volume;
/// - the closed components nest consistently: each outward component lies outside all others
///   (winding number of the rest < 1/2 at one of its vertices) and each inward one (a cavity)
///   inside exactly one solid; else Overlapping. This is a check at one vertex per
///   component, not a full self-intersection test; it costs O(components x triangles).
/// The enclosed volume (divergence theorem, about the bounding box centre) is computed; if it
/// is negative the whole mesh is inward and every triangle is turned (report.flipped).
/// Unreferenced vertices are kept but ignored (bounding box, normals).
///
/// Derived data (valid while finalized()): unit face normals; per triangle edge the
/// neighbouring triangle; angle-weighted vertex pseudo-normals (Baerentzen and Aanaes 2005:
/// the sum over incident faces of the face's angle at the vertex times its normal); edge
/// pseudo-normals (the normalised sum of the two face normals) computed on the fly.
///
/// Storage (bytes, Scalar of s bytes): per vertex 6 s + 16 (with MaxVertices a power of two;
/// the hash table rounds 2 MaxVertices slots up to one, so up to 6 s + 24), per triangle
/// 3 s + 36: double 64 B per vertex and 60 B per triangle, float 40 B and 48 B.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "grip/core/index.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/mesh_report.hpp"
#include "grip/geometry/triangle.hpp"

namespace grip {

namespace detail {

/// Smallest power of two >= 2 n (at least 8): the size of a vertex hash table for n vertices.
constexpr std::size_t weld_table_size(int n) {
  std::size_t s = 8;
  while (s < 2 * detail::idx(n)) s *= 2;
  return s;
}

/// Bits of x (with -0 read as +0), widened to 64 bits.
template <class Scalar>
std::uint64_t scalar_bits(Scalar x) {
  static_assert(sizeof(Scalar) == 4 || sizeof(Scalar) == 8, "Scalar is float or double");
  const Scalar y = x == Scalar(0) ? Scalar(0) : x;
  if constexpr (sizeof(Scalar) == 8) {
    std::uint64_t u = 0;
    std::memcpy(&u, &y, 8);
    return u;
  } else {
    std::uint32_t u = 0;
    std::memcpy(&u, &y, 4);
    return u;
  }
}

/// A 64-bit mixing step (a multiply-xorshift finaliser).
inline std::uint64_t mix_bits(std::uint64_t h) {
  h ^= h >> 31;
  h *= 0x7fb5d329728ea185ULL;
  h ^= h >> 27;
  h *= 0x81dadef4bc2dd44dULL;
  h ^= h >> 33;
  return h;
}

}  // namespace detail

/// A triangle mesh of at most MaxVertices (welded) vertices and MaxTriangles triangles, held
/// in place (large: put it in static storage or a member).
template <class Scalar, int MaxVertices, int MaxTriangles>
class TriangleMesh {
  static_assert(MaxVertices >= 4 && MaxTriangles >= 4, "a closed mesh has at least 4 vertices and 4 triangles");
  static_assert(MaxTriangles <= (1 << 28), "triangle indices must fit an int with room for edge numbers");

 public:
  using ScalarType = Scalar;                          ///< The scalar type.
  static constexpr int max_vertices = MaxVertices;    ///< Most vertices held.
  static constexpr int max_triangles = MaxTriangles;  ///< Most triangles held.

  /// Removes every vertex and triangle.
  void clear();
  /// Adds vertex p, or finds the vertex with the same coordinates: returns its index, or -1
  /// (mesh unchanged) if p is not finite, exceeds ScalarTraits::max_magnitude, or is not yet
  /// in the mesh and the mesh is full.
  int add_vertex(const Vector3<Scalar>& p);
  /// add_vertex() that also numbers p as the next source vertex (as a file numbers them, e.g.
  /// OBJ's `v` statements, duplicates included): -1 also when MaxVertices source vertices
  /// are already numbered.
  int add_source_vertex(const Vector3<Scalar>& p);
  /// Mesh vertex of source vertex k (0-based), or -1 if k is not numbered.
  int source_vertex(long k) const { return k >= 0 && k < sources_ ? source_[detail::idx(k)] : -1; }
  /// Number of source vertices numbered since clear().
  int source_vertex_count() const { return sources_; }
  /// Appends triangle (a, b, c) (vertex indices, counter-clockwise seen from outside):
  /// returns its index, or -1 (mesh unchanged) if an index is not a vertex or the mesh is full.
  int add_triangle(int a, int b, int c);
  /// Checks the mesh and derives its adjacency, normals and volume (see the file comment).
  /// Offline: O(T log T) plus O(components x T). The report is also kept (report()).
  MeshReport finalize();

  /// True after a finalize() that returned Ok, until the next change.
  bool finalized() const { return finalized_; }
  /// The report of the last finalize() (a default, refusing report before any).
  const MeshReport& report() const { return report_; }
  /// Number of vertices.
  int vertex_count() const { return nv_; }
  /// Number of triangles.
  int triangle_count() const { return nt_; }
  // The accessors below check their preconditions with GRIP_ASSERT (core/assert.hpp).
  /// Vertex i, 0 <= i < vertex_count().
  const Vector3<Scalar>& vertex(int i) const {
    GRIP_ASSERT(i < nv_);
    return verts_[detail::idx(i)];
  }
  /// Vertex indices of triangle t, 0 <= t < triangle_count().
  const std::array<int, 3>& triangle(int t) const {
    GRIP_ASSERT(t < nt_);
    return tris_[detail::idx(t)];
  }
  /// Unit outward normal of triangle t, 0 <= t < triangle_count() (finalized meshes).
  const Vector3<Scalar>& face_normal(int t) const {
    GRIP_ASSERT(t < nt_);
    return face_n_[detail::idx(t)];
  }
  /// Unit angle-weighted pseudo-normal of vertex v, 0 <= v < vertex_count() (finalized meshes;
  /// zero if v is unused).
  const Vector3<Scalar>& vertex_normal(int v) const {
    GRIP_ASSERT(v < nv_);
    return vert_n_[detail::idx(v)];
  }
  /// The triangle across edge e (0: ab, 1: bc, 2: ca) of triangle t, 0 <= t < triangle_count()
  /// (finalized meshes).
  int neighbour(int t, int e) const {
    GRIP_ASSERT(t < nt_ && e < 3);
    return nbr_[detail::idx(t)][detail::idx(e)];
  }
  /// Unit pseudo-normal of edge e of triangle t: the normalised sum of its two face normals.
  Vector3<Scalar> edge_normal(int t, int e) const {
    return (face_normal(t) + face_normal(neighbour(t, e))).normalized();
  }
  /// Axis-aligned box of the referenced vertices: false (lo, hi untouched) unless finalized.
  bool bounding_box(Vector3<Scalar>& lo, Vector3<Scalar>& hi) const {
    if (!finalized_) return false;
    lo = lo_;
    hi = hi_;
    return true;
  }
  /// Enclosed volume (m^3, > 0 once finalized; 0 before).
  Scalar volume() const { return finalized_ ? volume_ : Scalar(0); }
  /// A number that changes with every change of the mesh (clear, add_, finalize): MeshShape
  /// compares it with the one it built from to notice a mesh changed under it.
  unsigned long revision() const { return revision_; }

 private:
  MeshReport refuse(MeshIssue issue, long element);
  MeshIssue check_edges(long& element);
  MeshIssue check_fans(long& element);
  MeshIssue check_components(long& element);
  int target(int h) const { return tris_[detail::idx(h / 3)][detail::idx((h % 3 + 1) % 3)]; }
  int origin(int h) const { return tris_[detail::idx(h / 3)][detail::idx(h % 3)]; }
  int count_edges(int u, int v, int* first) const;

  static constexpr std::size_t table_size = detail::weld_table_size(MaxVertices);
  std::array<Vector3<Scalar>, MaxVertices> verts_{};
  std::array<Vector3<Scalar>, MaxVertices> vert_n_{};
  std::array<int, table_size> table_{};       // vertex index + 1 per slot, 0 for empty
  std::array<int, MaxVertices> source_{};     // mesh vertex per source vertex
  std::array<int, MaxVertices + 1> start_{};  // finalize: out-edges of vertex v in half_[start_[v], start_[v + 1])
  std::array<std::array<int, 3>, MaxTriangles> tris_{};
  std::array<std::array<int, 3>, MaxTriangles> nbr_{};
  std::array<Vector3<Scalar>, MaxTriangles> face_n_{};
  std::array<int, 3 * MaxTriangles> half_{};  // finalize: half-edges 3 t + e sorted by origin, then scratch
  MeshReport report_{};
  Vector3<Scalar> lo_{Vector3<Scalar>::Zero()}, hi_{Vector3<Scalar>::Zero()};
  Scalar volume_{0};
  int nv_{0}, nt_{0}, sources_{0};
  unsigned long revision_{0};
  bool finalized_{false};
};

}  // namespace grip

#include "grip/geometry/triangle_mesh_impl.hpp"
