#pragma once
/// \file
/// The member definitions of MeshShape (mesh_shape.hpp): building the box hierarchy, the
/// closest-point descent and the winding numbers. Included by mesh_shape.hpp; include that
/// header instead.

#include <algorithm>

#include "grip/core/index.hpp"
#include "grip/geometry/mesh_shape.hpp"

namespace grip {

template <class Scalar, int MaxVertices, int MaxTriangles>
Status MeshShape<Scalar, MaxVertices, MaxTriangles>::build(const Mesh& mesh) {
  mesh_ = nullptr;
  node_count_ = 0;
  if (!mesh.finalized() || mesh.triangle_count() < 1) return Status::InvalidInput;
  const int nt = mesh.triangle_count();
  auto vertex = [&mesh](int t, int k) -> const Vector3<Scalar>& {
    return mesh.vertex(mesh.triangle(t)[detail::idx(k)]);
  };
  auto corner = [&mesh](int t, int k) { return mesh.vertex(mesh.triangle(t)[detail::idx(k)]).data(); };
  for (int t = 0; t < nt; ++t) slot_id_[detail::idx(t)] = t;
  // Breadth-first: node i covers slots [first, first + count) until it is split; its
  // children are appended, so every node's slots stay contiguous and children follow parents.
  // (Plain scalar loops: this runs O(T log T) times.)
  nodes_[0].first = 0;
  nodes_[0].count = nt;
  node_count_ = 1;
  const Scalar big = std::numeric_limits<Scalar>::max();
  for (int i = 0; i < node_count_; ++i) {
    MeshBoxNode<Scalar>& nd = nodes_[detail::idx(i)];
    MeshWindingNode<Scalar>& wn = wnodes_[detail::idx(i)];
    const int b = nd.first, e = nd.first + nd.count;
    Scalar lo[3] = {big, big, big}, hi[3] = {-big, -big, -big};
    Scalar nsum[3] = {0, 0, 0}, wsum[3] = {0, 0, 0}, area = Scalar(0);
    for (int s = b; s < e; ++s) {
      const int t = slot_id_[detail::idx(s)];
      const Scalar *p0 = corner(t, 0), *p1 = corner(t, 1), *p2 = corner(t, 2);
      const Scalar u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      const Scalar v[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      const Scalar n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const Scalar half_area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / Scalar(2);
      area += half_area;
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], std::min(p0[d], std::min(p1[d], p2[d])));
        hi[d] = std::max(hi[d], std::max(p0[d], std::max(p1[d], p2[d])));
        const Scalar c = (p0[d] + p1[d] + p2[d]) / Scalar(3);
        nsum[d] += n[d] / Scalar(2);
        wsum[d] += half_area * c;
      }
    }
    nd.lo = Vector3<Scalar>(lo[0], lo[1], lo[2]);
    nd.hi = Vector3<Scalar>(hi[0], hi[1], hi[2]);
    wn.normal_sum = Vector3<Scalar>(nsum[0], nsum[1], nsum[2]);
    wn.area = area;  // > 0: finalize() refused zero-area triangles
    const Scalar cx = wsum[0] / area, cy = wsum[1] / area, cz = wsum[2] / area;
    wn.center = Vector3<Scalar>(cx, cy, cz);
    Scalar r2 = Scalar(0);
    for (int s = b; s < e; ++s)
      for (int k = 0; k < 3; ++k) {
        const Scalar* p = corner(slot_id_[detail::idx(s)], k);
        r2 = std::max(r2, (p[0] - cx) * (p[0] - cx) + (p[1] - cy) * (p[1] - cy) + (p[2] - cz) * (p[2] - cz));
      }
    wn.radius = std::sqrt(r2);
    if (nd.count <= leaf_size || node_count_ + 2 > max_nodes) {  // a leaf: its block is first / 4
      nd.first = b / 4;
      continue;
    }
    // The median, rounded to a multiple of 4 so that every leaf but one is a full block, along
    // the axis whose two halves have the least total box surface (the smaller the boxes, the
    // fewer a distance query must open).
    const int left_count = std::max(4, (nd.count / 2 + 2) / 4 * 4);
    const int mid = b + left_count;
    auto split = [&](int axis) {
      std::nth_element(slot_id_.begin() + b, slot_id_.begin() + mid, slot_id_.begin() + e, [&](int x, int y) {
        return corner(x, 0)[axis] + corner(x, 1)[axis] + corner(x, 2)[axis] <
               corner(y, 0)[axis] + corner(y, 1)[axis] + corner(y, 2)[axis];
      });
    };
    auto surface = [&](int from, int to) {
      Scalar l[3] = {big, big, big}, h[3] = {-big, -big, -big};
      for (int s = from; s < to; ++s)
        for (int k = 0; k < 3; ++k)
          for (int d = 0; d < 3; ++d) {
            l[d] = std::min(l[d], corner(slot_id_[detail::idx(s)], k)[d]);
            h[d] = std::max(h[d], corner(slot_id_[detail::idx(s)], k)[d]);
          }
      return (h[0] - l[0]) * (h[1] - l[1]) + (h[1] - l[1]) * (h[2] - l[2]) + (h[2] - l[2]) * (h[0] - l[0]);
    };
    int axis = 0;
    Scalar least = big;
    for (int a = 0; a < 3; ++a) {
      split(a);
      const Scalar area_sum = surface(b, mid) + surface(mid, e);
      if (area_sum < least) {
        least = area_sum;
        axis = a;
      }
    }
    if (axis != 2) split(axis);
    const int left = node_count_;
    nodes_[detail::idx(left)].first = b;
    nodes_[detail::idx(left)].count = mid - b;
    nodes_[detail::idx(left + 1)].first = mid;
    nodes_[detail::idx(left + 1)].count = e - mid;
    node_count_ += 2;
    nd.first = left;
    nd.count = 0;
  }
  for (int s = 0; s < nt; ++s) {
    const int t = slot_id_[detail::idx(s)];
    blocks_[detail::idx(s / 4)].set(s % 4, vertex(t, 0), vertex(t, 1), vertex(t, 2), t);
  }
  if (nt % 4 != 0) blocks_[detail::idx(nt / 4)].pad(nt % 4);
  for (int k = 0; k < (nt + 3) / 4; ++k) set_leaf_box(k, std::min(4, nt - 4 * k));
  build_quads();
  Vector3<Scalar> lo = Vector3<Scalar>::Zero(), hi = lo;
  mesh.bounding_box(lo, hi);
  tiny_ = std::sqrt(std::numeric_limits<Scalar>::epsilon()) * (hi - lo).maxCoeff();
  mesh_ = &mesh;
  revision_ = mesh.revision();
  return Status::Ok;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
void MeshShape<Scalar, MaxVertices, MaxTriangles>::build_quads() {
  // Quad q stands for binary node rep[q] (slot_id_ is free again: the blocks hold the order) and
  // holds the boxes of its children, or of its grandchildren where a child is inner. Quads are
  // made in order, so this loop is the breadth-first queue.
  int* rep = slot_id_.data();
  const Scalar inf = std::numeric_limits<Scalar>::infinity();
  rep[0] = 0;
  quad_count_ = 1;
  for (int q = 0; q < quad_count_; ++q) {
    const MeshBoxNode<Scalar>& b = nodes_[detail::idx(rep[q])];
    int entries[4] = {rep[q], -1, -1, -1};
    int n = 1;
    if (b.count == 0) {
      n = 0;
      for (int c = b.first; c <= b.first + 1; ++c) {
        const MeshBoxNode<Scalar>& cn = nodes_[detail::idx(c)];
        if (cn.count > 0) {
          entries[n++] = c;
        } else {
          entries[n++] = cn.first;
          entries[n++] = cn.first + 1;
        }
      }
    }
    detail::MeshQuadNode<Scalar>& qn = quads_[detail::idx(q)];
    for (int k = 0; k < 4; ++k) {
      qn.child[k] = 0;
      qn.count[k] = -1;
      for (int d = 0; d < 3; ++d) qn.lo[d][k] = qn.hi[d][k] = inf;  // empty: out of reach
      if (k >= n) continue;
      const MeshBoxNode<Scalar>& e = nodes_[detail::idx(entries[k])];
      if (e.count == 0 && quad_count_ >= max_quads) continue;  // (never: quads < inner nodes)
      for (int d = 0; d < 3; ++d) {
        qn.lo[d][k] = e.lo(d);
        qn.hi[d][k] = e.hi(d);
      }
      if (e.count > 0) {
        qn.child[k] = e.first;
        qn.count[k] = e.count;
      } else {
        qn.child[k] = quad_count_;
        qn.count[k] = 0;
        rep[quad_count_++] = entries[k];
      }
    }
  }
}

template <class Scalar, int MaxVertices, int MaxTriangles>
void MeshShape<Scalar, MaxVertices, MaxTriangles>::set_leaf_box(int k, int count) {
  // Third axis: the block's area-weighted normal; first: the coordinate axis least along it.
  const Block& bl = blocks_[detail::idx(k)];
  Vector3<Scalar> m = Vector3<Scalar>::Zero();
  for (int l = 0; l < count; ++l) m += Vector3<Scalar>(bl.nx[l], bl.ny[l], bl.nz[l]);
  Matrix3<Scalar> R = Matrix3<Scalar>::Identity();
  if (m.norm() > Scalar(0)) {
    const Vector3<Scalar> n = m.normalized();
    int least = 0;
    for (int d = 1; d < 3; ++d)
      if (std::abs(n(d)) < std::abs(n(least))) least = d;
    const Vector3<Scalar> e1 = (Vector3<Scalar>::Unit(least) - n * n(least)).normalized();
    R << e1.transpose(), n.cross(e1).transpose(), n.transpose();  // rows: the box's axes
  }
  const Scalar big = std::numeric_limits<Scalar>::max();
  Vector3<Scalar> lo = Vector3<Scalar>::Constant(big), hi = -lo;
  Scalar size = Scalar(0);
  for (int l = 0; l < count; ++l) {
    Vector3<Scalar> v[3];
    bl.vertices(l, v[0], v[1], v[2]);
    for (const Vector3<Scalar>& x : v) {
      lo = lo.cwiseMin(R * x);
      hi = hi.cwiseMax(R * x);
      size = std::max(size, x.cwiseAbs().maxCoeff());
    }
  }
  // Rounding of the rotations: a margin of 64 eps times the leaf's magnitude.
  const Scalar pad = Scalar(64) * std::numeric_limits<Scalar>::epsilon() * (size + (hi - lo).maxCoeff());
  detail::LeafBox<Scalar>& b = leaf_boxes_[detail::idx(k)];
  b.center = R.transpose() * ((lo + hi) / Scalar(2));
  b.rotation = R;
  b.half = (hi - lo) / Scalar(2) + Vector3<Scalar>::Constant(pad);
}

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
