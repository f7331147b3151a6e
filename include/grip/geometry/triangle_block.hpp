#pragma once
/// \file
/// Four triangles, or four boxes, in structure-of-arrays lanes, for MeshShape's hierarchy:
/// their squared distances to a point are computed together without branches, in Eigen arrays
/// of 4 lanes that map to SIMD instructions (2 + 2 lanes of double with SSE2, 4 with AVX).
/// Internal to mesh_shape.hpp.
///
/// Per lane, with u = b - a, v = c - a, n = u x v, ap = p - a: the projection of p onto the
/// plane has barycentric numerators s = (u.ap)(v.v) - (v.ap)(u.v), t = (v.ap)(u.u) -
/// (u.ap)(u.v) over det = (u.u)(v.v) - (u.v)^2; it lies in the triangle iff s >= 0, t >= 0 and
/// s + t <= det, and then the squared distance is (n.ap)^2 / n.n. Otherwise the closest point
/// lies on the boundary: the least of the three edges' squared distances, each from the point
/// of its segment (parameter clamped to [0, 1]), computed explicitly so that no cancellation
/// spoils small distances. Only the choice of the best triangle uses these numbers; its exact
/// closest point is then closest_point_on_triangle()'s.

#include <algorithm>
#include <cmath>
#include <limits>

#include "grip/core/simd.hpp"
#include "grip/core/types.hpp"
#include "grip/geometry/triangle.hpp"

namespace grip {
namespace detail {

/// Up to 4 non-degenerate triangles in lanes; unused lanes repeat lane 0.
template <class Scalar>
struct TriangleBlock {
  Scalar ax[4], ay[4], az[4];              ///< vertex a
  Scalar ux[4], uy[4], uz[4];              ///< u = b - a
  Scalar vx[4], vy[4], vz[4];              ///< v = c - a
  Scalar nx[4], ny[4], nz[4];              ///< n = u x v
  Scalar uu[4], uv[4], vv[4];              ///< u.u, u.v, v.v
  Scalar det[4];                           ///< (u.u)(v.v) - (u.v)^2
  Scalar inv_nn[4];                        ///< 1 / n.n
  Scalar inv_uu[4], inv_vv[4], inv_ww[4];  ///< 1 / u.u, 1 / v.v, 1 / w.w with w = c - b
  int id[4];                               ///< mesh triangle of each lane

  /// Stores triangle (a, b, c), mesh index `triangle`, in `lane`.
  void set(int lane, const Vector3<Scalar>& a, const Vector3<Scalar>& b, const Vector3<Scalar>& c, int triangle) {
    const Vector3<Scalar> u = b - a, v = c - a, w = c - b, n = u.cross(v);
    const int l = lane;
    ax[l] = a.x(), ay[l] = a.y(), az[l] = a.z();
    ux[l] = u.x(), uy[l] = u.y(), uz[l] = u.z();
    vx[l] = v.x(), vy[l] = v.y(), vz[l] = v.z();
    nx[l] = n.x(), ny[l] = n.y(), nz[l] = n.z();
    uu[l] = u.dot(u), uv[l] = u.dot(v), vv[l] = v.dot(v);
    det[l] = uu[l] * vv[l] - uv[l] * uv[l];
    inv_nn[l] = Scalar(1) / n.dot(n);
    inv_uu[l] = Scalar(1) / uu[l], inv_vv[l] = Scalar(1) / vv[l], inv_ww[l] = Scalar(1) / w.dot(w);
    id[l] = triangle;
  }

  /// Copies lane 0 into lanes count .. 3.
  void pad(int count) {
    for (int l = count; l < 4; ++l) {
      Scalar* fields[] = {ax, ay, az, ux, uy, uz,  vx,     vy,     vz,     nx,
                          ny, nz, uu, uv, vv, det, inv_nn, inv_uu, inv_vv, inv_ww};
      for (Scalar* f : fields) f[l] = f[0];
      id[l] = id[0];
    }
  }

  /// Squared distances from p to the 4 lanes' triangles.
  GRIP_ALWAYS_INLINE void distances(const Vector3<Scalar>& p, Scalar out[4]) const {
    // Eigen arrays of 4 lanes: min, max, +, -, * only, which Eigen maps to SIMD instructions
    // (no select, no branch). Outside the triangle the plane's distance is pushed beyond the
    // edges' by big times the violated barycentric numerators (0 inside, so exact there).
    using A = Eigen::Array<Scalar, 4, 1>;
    using M = Eigen::Map<const A>;
    const Scalar big = std::numeric_limits<Scalar>::max() / Scalar(4);
    const A px = Scalar(p.x()) - M(ax), py = Scalar(p.y()) - M(ay), pz = Scalar(p.z()) - M(az);
    const M mux(ux), muy(uy), muz(uz), mvx(vx), mvy(vy), mvz(vz);
    const A d1 = mux * px + muy * py + muz * pz;
    const A d2 = mvx * px + mvy * py + mvz * pz;
    const A s = d1 * M(vv) - d2 * M(uv);
    const A t = d2 * M(uu) - d1 * M(uv);
    const A h = M(nx) * px + M(ny) * py + M(nz) * pz;
    const A outside = (-s).max(Scalar(0)) + (-t).max(Scalar(0)) + (s + t - M(det)).max(Scalar(0));
    const A face = h * h * M(inv_nn) + outside * big;
    A k = (d1 * M(inv_uu)).max(Scalar(0)).min(Scalar(1));  // edge ab
    const A e0 = (px - k * mux).square() + (py - k * muy).square() + (pz - k * muz).square();
    k = (d2 * M(inv_vv)).max(Scalar(0)).min(Scalar(1));  // edge ac
    const A e1 = (px - k * mvx).square() + (py - k * mvy).square() + (pz - k * mvz).square();
    const A wx = mvx - mux, wy = mvy - muy, wz = mvz - muz;  // edge bc: w = v - u from b, bp = ap - u
    const A bx = px - mux, by = py - muy, bz = pz - muz;
    k = ((wx * bx + wy * by + wz * bz) * M(inv_ww)).max(Scalar(0)).min(Scalar(1));
    const A e2 = (bx - k * wx).square() + (by - k * wy).square() + (bz - k * wz).square();
    Eigen::Map<A> result(out);
    result = face.min(e0).min(e1.min(e2));
  }

  /// Lane l's closest point q to p by the formulas of distances() (the least of the face and
  /// the three edges), with the feature that holds it: |p - q|^2. Equal to
  /// closest_point_on_triangle()'s answer to rounding, without its branches on regions.
  Scalar closest(int l, const Vector3<Scalar>& p, Vector3<Scalar>& q, TriangleFeature& feature) const {
    const Vector3<Scalar> a(ax[l], ay[l], az[l]), u(ux[l], uy[l], uz[l]), v(vx[l], vy[l], vz[l]);
    const Vector3<Scalar> ap = p - a;
    const Scalar d1 = u.dot(ap), d2 = v.dot(ap);
    const Scalar s = d1 * vv[l] - d2 * uv[l], t = d2 * uu[l] - d1 * uv[l];
    // The open face (its boundaries are edges): p's projection onto the plane, from the plane's
    // normal as closest_point_on_triangle() (s and t, differences of products, are too coarse
    // in float to place q within a few units in the last place of p).
    if (s > Scalar(0) && t > Scalar(0) && s + t < det[l]) {
      const Vector3<Scalar> n(nx[l], ny[l], nz[l]);
      const Scalar h = n.dot(ap) * inv_nn[l];
      q = p - h * n;
      feature = TriangleFeature::Face;
      return h * h * n.squaredNorm();
    }
    // q from the vertex and the edges, then |p - q|^2.
    auto clamp01 = [](Scalar x) { return x < Scalar(0) ? Scalar(0) : (x > Scalar(1) ? Scalar(1) : x); };
    // Each edge from its first vertex: (origin, direction, parameter, its edge, its two vertices).
    const Vector3<Scalar> w = v - u, bp = ap - u;
    const Scalar k[3] = {clamp01(d1 * inv_uu[l]), clamp01(d2 * inv_vv[l]), clamp01(w.dot(bp) * inv_ww[l])};
    const Vector3<Scalar> e[3] = {a + k[0] * u, a + k[1] * v, Vector3<Scalar>(a + u) + k[2] * w};
    const Scalar d[3] = {(p - e[0]).squaredNorm(), (p - e[1]).squaredNorm(), (p - e[2]).squaredNorm()};
    const int i = d[1] < d[0] ? (d[2] < d[1] ? 2 : 1) : (d[2] < d[0] ? 2 : 0);
    static constexpr TriangleFeature edge[3] = {TriangleFeature::EdgeAB, TriangleFeature::EdgeCA,
                                                TriangleFeature::EdgeBC};
    static constexpr TriangleFeature start[3] = {TriangleFeature::VertexA, TriangleFeature::VertexA,
                                                 TriangleFeature::VertexB};
    static constexpr TriangleFeature end[3] = {TriangleFeature::VertexB, TriangleFeature::VertexC,
                                               TriangleFeature::VertexC};
    q = e[i];
    feature = k[i] <= Scalar(0) ? start[i] : (k[i] >= Scalar(1) ? end[i] : edge[i]);
    return d[i];
  }

  /// Vertices of lane l.
  void vertices(int l, Vector3<Scalar>& a, Vector3<Scalar>& b, Vector3<Scalar>& c) const {
    a = Vector3<Scalar>(ax[l], ay[l], az[l]);
    b = a + Vector3<Scalar>(ux[l], uy[l], uz[l]);
    c = a + Vector3<Scalar>(vx[l], vy[l], vz[l]);
  }
};

/// An oriented box around a TriangleBlock's triangles (third axis along their mean normal):
/// far tighter than the axis-aligned box of a curved patch.
template <class Scalar>
struct LeafBox {
  Vector3<Scalar> center{Vector3<Scalar>::Zero()};
  Matrix3<Scalar> rotation{Matrix3<Scalar>::Identity()};  ///< rows: the box's axes
  Vector3<Scalar> half{Vector3<Scalar>::Zero()};          ///< half extents along them

  /// Squared distance from p to the box (0 inside).
  GRIP_ALWAYS_INLINE Scalar distance2(const Vector3<Scalar>& p) const {
    const Vector3<Scalar> local = rotation * (p - center);
    return (local.cwiseAbs() - half).cwiseMax(Scalar(0)).squaredNorm();
  }
};

/// A node of the 4-wide box hierarchy that distance queries descend: up to 4 children's boxes in
/// lanes. A child is a leaf (count > 0: `child` is its TriangleBlock, `count` its triangles), an
/// inner node (count == 0: `child` is its MeshQuadNode) or empty (count < 0, an infinite box that
/// no query reaches).
template <class Scalar>
struct MeshQuadNode {
  Scalar lo[3][4];  ///< lower box corners: [axis][lane]
  Scalar hi[3][4];  ///< upper box corners
  int child[4];     ///< block or node index per lane
  int count[4];     ///< triangles of a leaf; 0 for an inner node; -1 for empty

  /// Squared distances from (px, py, pz) to the 4 boxes (branch-free, SIMD through Eigen).
  GRIP_ALWAYS_INLINE void distances(Scalar px, Scalar py, Scalar pz, Scalar out[4]) const {
    using A = Eigen::Array<Scalar, 4, 1>;
    using M = Eigen::Map<const A>;
    const A dx = (M(lo[0]) - px).max(px - M(hi[0])).max(Scalar(0));
    const A dy = (M(lo[1]) - py).max(py - M(hi[1])).max(Scalar(0));
    const A dz = (M(lo[2]) - pz).max(pz - M(hi[2])).max(Scalar(0));
    Eigen::Map<A> result(out);
    result = dx * dx + dy * dy + dz * dz;
  }
};

}  // namespace detail
}  // namespace grip
