#pragma once
/// \file
/// The member definitions of TriangleMesh (triangle_mesh.hpp): welding, and the checks and
/// derivations of finalize(). Included by triangle_mesh.hpp; include that header instead.

#include <initializer_list>
#include <utility>

#include "grip/core/index.hpp"
#include "grip/geometry/triangle_mesh.hpp"

namespace grip {

template <class Scalar, int MaxVertices, int MaxTriangles>
void TriangleMesh<Scalar, MaxVertices, MaxTriangles>::clear() {
  table_.fill(0);
  ++revision_;
  nv_ = 0;
  nt_ = 0;
  sources_ = 0;
  finalized_ = false;
  report_ = MeshReport{};
  volume_ = Scalar(0);
}

template <class Scalar, int MaxVertices, int MaxTriangles>
int TriangleMesh<Scalar, MaxVertices, MaxTriangles>::add_vertex(const Vector3<Scalar>& p) {
  if (!p.allFinite() || !(p.cwiseAbs().maxCoeff() <= ScalarTraits<Scalar>::max_magnitude)) return -1;
  Vector3<Scalar> key = Vector3<Scalar>::Zero();
  for (int k = 0; k < 3; ++k) key(k) = p(k) == Scalar(0) ? Scalar(0) : p(k);  // -0 -> +0
  std::uint64_t h = detail::mix_bits(detail::scalar_bits(key.x()));
  h = detail::mix_bits(h ^ detail::scalar_bits(key.y()));
  h = detail::mix_bits(h ^ detail::scalar_bits(key.z()));
  std::size_t i = static_cast<std::size_t>(h) & (table_size - 1);
  while (table_[i] != 0) {
    const int v = table_[i] - 1;
    if (verts_[detail::idx(v)] == key) return v;
    i = (i + 1) & (table_size - 1);
  }
  if (nv_ >= MaxVertices) return -1;
  verts_[detail::idx(nv_)] = key;
  table_[i] = nv_ + 1;
  finalized_ = false;
  ++revision_;
  return nv_++;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
int TriangleMesh<Scalar, MaxVertices, MaxTriangles>::add_source_vertex(const Vector3<Scalar>& p) {
  if (sources_ >= MaxVertices) return -1;
  const int v = add_vertex(p);
  if (v < 0) return -1;
  source_[detail::idx(sources_++)] = v;
  return v;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
int TriangleMesh<Scalar, MaxVertices, MaxTriangles>::add_triangle(int a, int b, int c) {
  if (nt_ >= MaxTriangles || a < 0 || b < 0 || c < 0 || a >= nv_ || b >= nv_ || c >= nv_) return -1;
  tris_[detail::idx(nt_)] = {a, b, c};
  finalized_ = false;
  ++revision_;
  return nt_++;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
MeshReport TriangleMesh<Scalar, MaxVertices, MaxTriangles>::refuse(MeshIssue issue, long element) {
  report_.status = Status::InvalidInput;
  report_.issue = issue;
  report_.element = element;
  finalized_ = false;
  return report_;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
int TriangleMesh<Scalar, MaxVertices, MaxTriangles>::count_edges(int u, int v, int* first) const {
  const int* b = half_.data() + start_[detail::idx(u)];
  const int* e = half_.data() + start_[detail::idx(u + 1)];
  const int* lo = std::lower_bound(b, e, v, [this](int h, int x) { return target(h) < x; });
  const int* hi = std::upper_bound(lo, e, v, [this](int x, int h) { return x < target(h); });
  if (first != nullptr && lo != hi) *first = *lo;
  return static_cast<int>(hi - lo);
}

template <class Scalar, int MaxVertices, int MaxTriangles>
MeshIssue TriangleMesh<Scalar, MaxVertices, MaxTriangles>::check_edges(long& element) {
  // Out-going half-edges h = 3 t + e of every vertex, contiguous (counting sort by origin),
  // each vertex's list sorted by target: then u -> v is found by binary search.
  const int nh = 3 * nt_;
  std::fill(start_.begin(), start_.begin() + nv_ + 1, 0);
  for (int h = 0; h < nh; ++h) ++start_[detail::idx(origin(h) + 1)];
  for (int v = 1; v <= nv_; ++v) start_[detail::idx(v)] += start_[detail::idx(v - 1)];
  for (int h = 0; h < nh; ++h) half_[detail::idx(start_[detail::idx(origin(h))]++)] = h;
  for (int v = nv_; v >= 1; --v) start_[detail::idx(v)] = start_[detail::idx(v - 1)];
  start_[0] = 0;
  for (int v = 0; v < nv_; ++v)
    std::sort(half_.begin() + start_[detail::idx(v)], half_.begin() + start_[detail::idx(v + 1)],
              [this](int a, int b) { return target(a) < target(b); });
  for (int h = 0; h < nh; ++h) {
    const int u = origin(h), v = target(h);
    int twin = -1;
    const int same = count_edges(u, v, nullptr);
    const int reverse = count_edges(v, u, &twin);
    element = h / 3;
    if (same + reverse == 1) return MeshIssue::NotClosed;
    if (same + reverse > 2) return MeshIssue::NonManifold;
    if (same == 2) return MeshIssue::InconsistentOrientation;
    nbr_[detail::idx(h / 3)][detail::idx(h % 3)] = twin / 3;
  }
  element = -1;
  return MeshIssue::None;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
MeshIssue TriangleMesh<Scalar, MaxVertices, MaxTriangles>::check_fans(long& element) {
  // Walk around each used vertex v from one out-going half-edge: the edge w -> v before it in
  // its triangle has its twin v -> w in the neighbour, the next out-going half-edge. A
  // manifold vertex's walk meets all its triangles before returning.
  for (int v = 0; v < nv_; ++v) {
    const int degree = start_[detail::idx(v + 1)] - start_[detail::idx(v)];
    if (degree == 0) continue;
    const int h0 = half_[detail::idx(start_[detail::idx(v)])];
    int h = h0, steps = 0;
    do {
      const int t = h / 3, ep = (h % 3 + 2) % 3;
      const int w = tris_[detail::idx(t)][detail::idx(ep)];
      const int nb = nbr_[detail::idx(t)][detail::idx(ep)];
      int next = -1;
      for (int k = 0; k < 3; ++k)
        if (tris_[detail::idx(nb)][detail::idx(k)] == v && tris_[detail::idx(nb)][detail::idx((k + 1) % 3)] == w)
          next = 3 * nb + k;
      if (next < 0) break;
      h = next;
      ++steps;
    } while (h != h0 && steps <= degree);
    if (h != h0 || steps != degree) {
      element = h0 / 3;
      return MeshIssue::NonManifold;
    }
  }
  element = -1;
  return MeshIssue::None;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
MeshIssue TriangleMesh<Scalar, MaxVertices, MaxTriangles>::check_components(long& element) {
  // Components by breadth-first search over neighbours: half_[t] = component of t, and
  // half_[nt_ ...] the queue. Components are numbered by their first triangle.
  int* comp = half_.data();
  int* queue = half_.data() + nt_;
  std::fill(comp, comp + nt_, -1);
  int count = 0;
  for (int t0 = 0; t0 < nt_; ++t0) {
    if (comp[t0] >= 0) continue;
    int head = 0, tail = 0;
    comp[t0] = count;
    queue[tail++] = t0;
    while (head < tail) {
      const int t = queue[head++];
      for (int e = 0; e < 3; ++e) {
        const int nb = nbr_[detail::idx(t)][detail::idx(e)];
        if (comp[nb] < 0) {
          comp[nb] = count;
          queue[tail++] = nb;
        }
      }
    }
    ++count;
  }
  report_.components = count;
  if (count == 1) return MeshIssue::None;
  const Vector3<Scalar> c0 = (lo_ + hi_) / Scalar(2);
  const Scalar four_pi = Scalar(4) * Scalar(3.14159265358979323846);
  int first = 0;
  for (int k = 0; k < count; ++k) {
    while (comp[first] != k) ++first;
    const Vector3<Scalar>& x = verts_[detail::idx(tris_[detail::idx(first)][0])];
    Scalar vol = Scalar(0), angle = Scalar(0);
    for (int t = 0; t < nt_; ++t) {
      const std::array<int, 3>& tri = tris_[detail::idx(t)];
      const Vector3<Scalar>& a = verts_[detail::idx(tri[0])];
      const Vector3<Scalar>& b = verts_[detail::idx(tri[1])];
      const Vector3<Scalar>& c = verts_[detail::idx(tri[2])];
      if (comp[t] == k)
        vol += (a - c0).dot((b - c0).cross(c - c0));
      else
        angle += triangle_solid_angle(x, a, b, c);
    }
    element = first;
    if (!(vol != Scalar(0))) return MeshIssue::FoldedSurface;
    const Scalar w = angle / four_pi;
    const bool consistent = vol > Scalar(0) ? w < Scalar(0.5) : (w > Scalar(0.5) && w < Scalar(1.5));
    if (!consistent) return MeshIssue::Overlapping;
  }
  element = -1;
  return MeshIssue::None;
}

template <class Scalar, int MaxVertices, int MaxTriangles>
MeshReport TriangleMesh<Scalar, MaxVertices, MaxTriangles>::finalize() {
  finalized_ = false;
  ++revision_;
  report_ = MeshReport{};
  report_.vertices = nv_;
  report_.triangles = nt_;
  if (nt_ == 0) return refuse(MeshIssue::Empty, -1);
  const Scalar eps = Scalar(16) * std::numeric_limits<Scalar>::epsilon();
  for (int t = 0; t < nt_; ++t) {
    const std::array<int, 3>& tri = tris_[detail::idx(t)];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return refuse(MeshIssue::DegenerateTriangle, t);
    const Vector3<Scalar>& a = verts_[detail::idx(tri[0])];
    const Vector3<Scalar>& b = verts_[detail::idx(tri[1])];
    const Vector3<Scalar>& c = verts_[detail::idx(tri[2])];
    // The same test as closest_point_on_triangle's: an accepted triangle always has a face;
    // and no squared length below the smallest normal number, so that their inverses are finite.
    const Vector3<Scalar> ab = b - a, ac = c - a;
    const Scalar ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm(), bc2 = (c - b).squaredNorm();
    const Scalar l2 = std::max(std::max(ab2, ac2), bc2), area2 = ab.cross(ac).squaredNorm();
    const Scalar smallest = std::numeric_limits<Scalar>::min();
    if (!(area2 > eps * eps * l2 * l2) || !(std::min(std::min(ab2, ac2), std::min(bc2, area2)) >= smallest))
      return refuse(MeshIssue::DegenerateTriangle, t);
    if (t == 0) lo_ = hi_ = a;
    for (const Vector3<Scalar>* v : {&a, &b, &c}) {
      lo_ = lo_.cwiseMin(*v);
      hi_ = hi_.cwiseMax(*v);
    }
  }
  long element = -1;
  MeshIssue issue = check_edges(element);
  if (issue == MeshIssue::None) issue = check_fans(element);
  if (issue != MeshIssue::None) return refuse(issue, element);

  // Volume by the divergence theorem, about the box centre (smaller round-off).
  const Vector3<Scalar> c0 = (lo_ + hi_) / Scalar(2);
  Scalar six_volume = Scalar(0);
  for (int t = 0; t < nt_; ++t) {
    const std::array<int, 3>& tri = tris_[detail::idx(t)];
    six_volume += (verts_[detail::idx(tri[0])] - c0)
                      .dot((verts_[detail::idx(tri[1])] - c0).cross(verts_[detail::idx(tri[2])] - c0));
  }
  if (!(six_volume != Scalar(0)) || !std::isfinite(six_volume)) return refuse(MeshIssue::FoldedSurface, -1);
  if (six_volume < Scalar(0)) {  // inward: turn every triangle (a, b, c) -> (a, c, b)
    for (int t = 0; t < nt_; ++t) {
      std::swap(tris_[detail::idx(t)][1], tris_[detail::idx(t)][2]);
      std::swap(nbr_[detail::idx(t)][0], nbr_[detail::idx(t)][2]);
    }
    six_volume = -six_volume;
    report_.flipped = true;
  }

  // Face normals, then angle-weighted vertex pseudo-normals.
  std::fill(vert_n_.begin(), vert_n_.begin() + nv_, Vector3<Scalar>::Zero());
  for (int t = 0; t < nt_; ++t) {
    const std::array<int, 3>& tri = tris_[detail::idx(t)];
    const Vector3<Scalar>* p[3] = {&verts_[detail::idx(tri[0])], &verts_[detail::idx(tri[1])],
                                   &verts_[detail::idx(tri[2])]};
    const Vector3<Scalar> n = (*p[1] - *p[0]).cross(*p[2] - *p[0]).normalized();
    face_n_[detail::idx(t)] = n;
    for (int k = 0; k < 3; ++k) {
      const Vector3<Scalar> u = *p[(k + 1) % 3] - *p[k], w = *p[(k + 2) % 3] - *p[k];
      vert_n_[detail::idx(tri[detail::idx(k)])] += std::atan2(u.cross(w).norm(), u.dot(w)) * n;
    }
  }
  const Scalar fold = Scalar(64) * std::numeric_limits<Scalar>::epsilon();
  for (int t = 0; t < nt_; ++t)
    for (int e = 0; e < 3; ++e)
      if (!((face_n_[detail::idx(t)] + face_n_[detail::idx(neighbour(t, e))]).norm() > fold))
        return refuse(MeshIssue::FoldedSurface, t);
  for (int v = 0; v < nv_; ++v) {
    if (start_[detail::idx(v + 1)] == start_[detail::idx(v)]) continue;  // unused vertex: normal stays zero
    Vector3<Scalar>& n = vert_n_[detail::idx(v)];
    const Scalar len = n.norm();
    if (!(len > fold)) return refuse(MeshIssue::FoldedSurface, half_[detail::idx(start_[detail::idx(v)])] / 3);
    n /= len;
  }
  issue = check_components(element);
  if (issue != MeshIssue::None) return refuse(issue, element);
  volume_ = six_volume / Scalar(6);
  report_.status = Status::Ok;
  report_.issue = MeshIssue::None;
  finalized_ = true;
  return report_;
}

}  // namespace grip
