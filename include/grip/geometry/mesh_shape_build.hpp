#pragma once
/// \file
/// Building MeshShape's hierarchy (mesh_shape.hpp declares it and includes this file; include
/// that header instead): the binary tree of boxes by median splits, with each node's winding-number
/// data, collapsed into the 4-wide tree of the distance queries, and each leaf's oriented box.

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

}  // namespace grip
