#pragma once
/// \file
/// MeshShape's queries (mesh_shape.hpp declares them and includes this file; include that header
/// instead): the closest-point descent of the box hierarchy, the signed distance with its
/// pseudo-normals, and the generalised winding number that decides inside from outside.

#include <algorithm>

#include "grip/core/index.hpp"
#include "grip/geometry/mesh_shape.hpp"

namespace grip {

template <class Scalar, int MaxVertices, int MaxTriangles>
bool MeshShape<Scalar, MaxVertices, MaxTriangles>::out_of_range(const Vector3<Scalar>& p, Scalar& d,
                                                                Vector3<Scalar>& normal) {
  const Scalar m = p.cwiseAbs().maxCoeff();
  if (m <= ScalarTraits<Scalar>::max_magnitude) return false;
  d = ScalarTraits<Scalar>::max_magnitude;
  normal = Vector3<Scalar>::UnitZ();
  if (p.allFinite()) normal = (p / m).normalized();  // outside the mesh's box: away from it
  return true;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
int MeshShape<Scalar, MaxVertices, MaxTriangles>::nearest_slot(const Vector3<Scalar>& p, Scalar& best2, int slot,
                                                               int done) const {
  struct Entry {
    int index;  // a quad (count == 0) or a block (count > 0)
    int count;
    Scalar d2;
  };
  // Depth first over the 4-wide tree: at each node the 4 box distances together; of the
  // children nearer than the best so far, the nearest is visited at once and the others are
  // pushed for later, when the best may have dropped below them. Leaves are tested as they
  // are reached.
  const Scalar px = p.x(), py = p.y(), pz = p.z();
  Entry stack[stack_size];
  int sp = 0;
  Entry en{0, 0, Scalar(0)};
  for (;;) {
    if (en.count > 0 && en.index != done && leaf_boxes_[detail::idx(en.index)].distance2(p) < best2) {
      Scalar d2[4];
      blocks_[detail::idx(en.index)].distances(p, d2);
      for (int l = 0; l < en.count; ++l)
        if (d2[l] < best2) {
          best2 = d2[l];
          slot = 4 * en.index + l;
        }
    } else if (en.count == 0) {
      const detail::MeshQuadNode<Scalar>& qn = quads_[detail::idx(en.index)];
      Scalar d2[4];
      qn.distances(px, py, pz, d2);
      // The nearest child at once, the others in reach pushed (in any order: the best so far
      // rarely falls much once the nearest has been searched).
      const int k01 = d2[1] < d2[0] ? 1 : 0, k23 = d2[3] < d2[2] ? 3 : 2;
      const int nearest = d2[k23] < d2[k01] ? k23 : k01;
      if (d2[nearest] < best2) {
        for (int k = 0; k < 4; ++k)
          if (k != nearest && d2[k] < best2 && sp < stack_size) stack[sp++] = Entry{qn.child[k], qn.count[k], d2[k]};
        en = Entry{qn.child[nearest], qn.count[nearest], d2[nearest]};
        continue;
      }
    }
    do {  // the next pushed child still nearer than the best
      if (sp == 0) return slot;
      en = stack[--sp];
    } while (!(en.d2 < best2));
  }
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::closest_point(const Vector3<Scalar>& p, Vector3<Scalar>& q,
                                                                   int& triangle, TriangleFeature& feature) const {
  triangle = -1;
  feature = TriangleFeature::Face;
  q = p;
  Scalar far = Scalar(0);
  Vector3<Scalar> unused = Vector3<Scalar>::UnitZ();
  if (!built() || out_of_range(p, far, unused)) return ScalarTraits<Scalar>::max_magnitude;
  Scalar best2 = std::numeric_limits<Scalar>::infinity();
  const int slot = nearest_slot(p, best2, 0);
  triangle = blocks_[detail::idx(slot / 4)].id[slot % 4];
  return std::sqrt(blocks_[detail::idx(slot / 4)].closest(slot % 4, p, q, feature));
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::signed_distance(const Vector3<Scalar>& p, int slot,
                                                                     Vector3<Scalar>& normal) const {
  const int t = blocks_[detail::idx(slot / 4)].id[slot % 4];
  Vector3<Scalar> q;
  TriangleFeature f = TriangleFeature::Face;
  const Scalar d = std::sqrt(blocks_[detail::idx(slot / 4)].closest(slot % 4, p, q, f));
  const Vector3<Scalar> diff = p - q;
  // The pseudo-normal, unnormalised where only its sign matters.
  const int e = feature_edge(f), v = feature_vertex(f);
  const Vector3<Scalar> n = e >= 0 ? Vector3<Scalar>(mesh_->face_normal(t) + mesh_->face_normal(mesh_->neighbour(t, e)))
                            : v >= 0 ? mesh_->vertex_normal(mesh_->triangle(t)[detail::idx(v)])
                                     : mesh_->face_normal(t);
  const Scalar sign = diff.dot(n) < Scalar(0) ? Scalar(-1) : Scalar(1);
  if (d > tiny_)
    normal = diff * (sign / d);
  else
    normal = n.normalized();
  return sign * d;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
bool MeshShape<Scalar, MaxVertices, MaxTriangles>::distance_within(const Vector3<Scalar>& p, Scalar limit, Scalar& phi,
                                                                   Vector3<Scalar>& normal, int& hint) const {
  Scalar far = Scalar(0);
  Vector3<Scalar> unused = Vector3<Scalar>::UnitZ();
  if (!built() || out_of_range(p, far, unused) || !(limit > Scalar(0))) return false;
  Scalar best2 = limit * limit;
  int slot = -1, done = -1;
  if (hint >= 0 && hint < mesh_->triangle_count()) {  // slots 0 .. T - 1 hold the triangles
    // The hint's whole block first (padded lanes repeat lane 0 and never win), then the
    // descent skips it.
    done = hint / 4;
    Scalar d2[4];
    blocks_[detail::idx(done)].distances(p, d2);
    for (int l = 0; l < 4; ++l)
      if (d2[l] < best2) {
        best2 = d2[l];
        slot = 4 * done + l;
      }
  }
  slot = nearest_slot(p, best2, slot, done);
  if (slot < 0) return false;
  hint = slot;
  phi = signed_distance(p, slot, normal);
  return true;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::segment_distance2(int hint, const Vector3<Scalar>& p0,
                                                                       const Vector3<Scalar>& p1, Scalar& u) const {
  u = Scalar(0);
  if (!built() || hint < 0 || hint >= mesh_->triangle_count()) return std::numeric_limits<Scalar>::infinity();
  const std::array<int, 3>& tri = mesh_->triangle(blocks_[detail::idx(hint / 4)].id[hint % 4]);
  return segment_triangle_distance2(p0, p1, mesh_->vertex(tri[0]), mesh_->vertex(tri[1]), mesh_->vertex(tri[2]), u);
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Vector3<Scalar> MeshShape<Scalar, MaxVertices, MaxTriangles>::pseudo_normal(int t, TriangleFeature feature) const {
  if (!built()) return Vector3<Scalar>::UnitZ();
  const int e = feature_edge(feature), v = feature_vertex(feature);
  if (e >= 0) return mesh_->edge_normal(t, e);
  if (v >= 0) return mesh_->vertex_normal(mesh_->triangle(t)[detail::idx(v)]);
  return mesh_->face_normal(t);
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::distance(const Vector3<Scalar>& p, Vector3<Scalar>& normal) const {
  normal = Vector3<Scalar>::UnitZ();
  Scalar far = ScalarTraits<Scalar>::max_magnitude;
  if (!built() || out_of_range(p, far, normal)) return far;
  Scalar best2 = std::numeric_limits<Scalar>::infinity();
  return signed_distance(p, nearest_slot(p, best2, 0), normal);
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::winding_number(const Vector3<Scalar>& p,
                                                                    Scalar& error_bound) const {
  error_bound = Scalar(0);
  if (!built() || !(p.cwiseAbs().maxCoeff() <= ScalarTraits<Scalar>::max_magnitude)) return Scalar(0);
  const Scalar beta2 = beta_ * beta_;
  int stack[stack_size];
  int sp = 0;
  stack[sp++] = 0;
  Scalar sum = Scalar(0), bound = Scalar(0);
  while (sp > 0) {
    const int i = stack[--sp];
    const MeshWindingNode<Scalar>& wn = wnodes_[detail::idx(i)];
    const Vector3<Scalar> r = wn.center - p;
    const Scalar d2 = r.squaredNorm();
    if (d2 > beta2 * wn.radius * wn.radius) {  // far: the dipole term
      const Scalar d = std::sqrt(d2);
      sum += r.dot(wn.normal_sum) / (d2 * d);
      const Scalar gap = d - wn.radius;
      bound += Scalar(2) * wn.area * wn.radius / (gap * gap * gap);
      continue;
    }
    const MeshBoxNode<Scalar>& nd = nodes_[detail::idx(i)];
    if (nd.count > 0) {
      for (int l = 0; l < nd.count; ++l) sum += slot_solid_angle(p, 4 * nd.first + l);
    } else if (sp + 2 <= stack_size) {
      stack[sp++] = nd.first + 1;
      stack[sp++] = nd.first;
    }
  }
  const Scalar four_pi = Scalar(4) * Scalar(3.14159265358979323846);
  error_bound = bound / four_pi;
  return sum / four_pi;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
Scalar MeshShape<Scalar, MaxVertices, MaxTriangles>::winding_number_exact(const Vector3<Scalar>& p) const {
  if (!built() || !(p.cwiseAbs().maxCoeff() <= ScalarTraits<Scalar>::max_magnitude)) return Scalar(0);
  Scalar sum = Scalar(0);
  for (int s = 0; s < mesh_->triangle_count(); ++s) sum += slot_solid_angle(p, s);
  return sum / (Scalar(4) * Scalar(3.14159265358979323846));
}

}  // namespace grip
