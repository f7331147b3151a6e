#pragma once
/// \file
/// Exact small geometry of one triangle: the closest point to a point (with the feature that
/// holds it) and the signed solid angle the triangle subtends at a point.
///
/// Vertex and edge numbering. Triangle (a, b, c) has vertices 0, 1, 2 = a, b, c and edges
/// 0, 1, 2 = ab, bc, ca: edge e runs from vertex e to vertex (e + 1) mod 3. The outward
/// normal is that of the counter-clockwise order: (b - a) x (c - a) / |...|.
///
/// Closest point. The plane of the triangle is split into the seven Voronoi regions of its
/// features (the open face, three edges, three vertices) by the signs of dot products with
/// the edge vectors (Ericson, "Real-Time Collision Detection", 2005, section 5.1.5); the
/// closest point is the projection onto the feature of the region holding p. A triangle whose
/// cross product is at the level of rounding noise (zero area: collinear or coincident
/// vertices) has no face region: its closest point is the best of its three edges as
/// segments, so no division by a vanishing area ever happens and no NaN can come out.
///
/// Segment and triangle. Unless the segment crosses the triangle (distance 0), a closest pair
/// has a segment end or a point of a triangle edge in it (were both points interior to their
/// sets, the segment would be parallel to the face and could slide to an end or an edge at
/// the same distance). A pair with an edge point is among the three edge-segment distances;
/// one with an interior face point has an end as partner, its projection inside the face. So
/// the least of those is exact.
///
/// Solid angle. Van Oosterom and Strackee (1983): with x = a - p, y = b - p, z = c - p,
///   tan(Omega / 2) = x . (y x z) / (|x||y||z| + (x . y)|z| + (x . z)|y| + (y . z)|x|),
/// evaluated with atan2, so Omega is in [-2 pi, 2 pi], positive when p sees the triangle's
/// back (p lies on the side its outward normal points away from). For a closed outward mesh
/// the solid angles sum to 4 pi at an inside point and 0 outside: the winding number is that
/// sum over 4 pi. A point on a vertex gives atan2(0, 0) = 0, never NaN.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>

#include "grip/core/types.hpp"

namespace grip {

/// The feature of a triangle (a, b, c) that holds a closest point.
enum class TriangleFeature : std::uint8_t {
  Face,     ///< The open interior of the triangle.
  EdgeAB,   ///< The open edge 0, from a to b.
  EdgeBC,   ///< The open edge 1, from b to c.
  EdgeCA,   ///< The open edge 2, from c to a.
  VertexA,  ///< Vertex 0.
  VertexB,  ///< Vertex 1.
  VertexC,  ///< Vertex 2.
};

/// Edge index 0..2 of an edge feature, or -1 for the face or a vertex.
constexpr int feature_edge(TriangleFeature f) {
  return f == TriangleFeature::EdgeAB ? 0 : f == TriangleFeature::EdgeBC ? 1 : f == TriangleFeature::EdgeCA ? 2 : -1;
}

/// Vertex index 0..2 of a vertex feature, or -1 for the face or an edge.
constexpr int feature_vertex(TriangleFeature f) {
  return f == TriangleFeature::VertexA ? 0 : f == TriangleFeature::VertexB ? 1 : f == TriangleFeature::VertexC ? 2 : -1;
}

/// The closest point q of triangle (a, b, c) to p, exact to rounding. Returns |p - q|^2,
/// writes q and the feature holding q. Any finite input is handled, including zero-area
/// triangles (then the face is never reported).
template <class Scalar>
Scalar closest_point_on_triangle(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                                 const Vector3<Scalar>& c, Vector3<Scalar>& q, TriangleFeature& feature);

/// The least squared distance between segment [p0, p1] and triangle (a, b, c); `u` receives
/// the segment parameter in [0, 1] of a point that attains it (p0 + u (p1 - p0)). 0 when the
/// segment meets the triangle (u then at a meeting point). Exact to rounding for any finite
/// input (see the file comment).
template <class Scalar>
Scalar segment_triangle_distance2(const Vector3<Scalar>& p0, const Vector3<Scalar>& p1, const Vector3<Scalar>& a,
                                  const Vector3<Scalar>& b, const Vector3<Scalar>& c, Scalar& u);

/// The signed solid angle (sr, in [-2 pi, 2 pi]) that triangle (a, b, c) subtends at p:
/// positive when p lies behind the triangle (against its outward normal).
template <class Scalar>
Scalar triangle_solid_angle(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                            const Vector3<Scalar>& c);

namespace detail {

/// Closest point on segment [a, b] (a point if a == b): |p - q|^2; `t` receives the segment
/// parameter in [0, 1].
template <class Scalar>
Scalar closest_point_on_segment(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                                Vector3<Scalar>& q, Scalar& t) {
  const Vector3<Scalar> ab = b - a;
  const Scalar len2 = ab.squaredNorm();
  t = Scalar(0);
  if (len2 > Scalar(0)) {
    t = (p - a).dot(ab) / len2;
    t = t < Scalar(0) ? Scalar(0) : (t > Scalar(1) ? Scalar(1) : t);
  }
  q = t <= Scalar(0) ? a : (t >= Scalar(1) ? b : Vector3<Scalar>(a + t * ab));
  return (p - q).squaredNorm();
}

/// Closest points of segments [p, p + d] and [q, q + e]: their squared distance, with `s` and
/// `t` the parameters (in [0, 1]) of a closest pair. The unconstrained minimiser of
/// |p + s d - q - t e|^2 is clamped to [0, 1] in s, t is the best for that s, and s is
/// recomputed once if t had to be clamped: exact for convex quadratics over the unit square.
/// A zero-length segment is a point.
template <class Scalar>
Scalar closest_points_of_segments(const Vector3<Scalar>& p, const Vector3<Scalar>& d, const Vector3<Scalar>& q,
                                  const Vector3<Scalar>& e, Scalar& s, Scalar& t) {
  auto clamp01 = [](Scalar x) { return x < Scalar(0) ? Scalar(0) : (x > Scalar(1) ? Scalar(1) : x); };
  const Vector3<Scalar> r = p - q;
  const Scalar dd = d.dot(d), ee = e.dot(e), de = d.dot(e), dr = d.dot(r), er = e.dot(r);
  const Scalar den = dd * ee - de * de;  // >= 0 (Cauchy-Schwarz); 0 when parallel or degenerate
  s = den > Scalar(0) ? clamp01((de * er - dr * ee) / den) : Scalar(0);
  if (!(ee > Scalar(0))) {
    t = Scalar(0);
    s = dd > Scalar(0) ? clamp01(-dr / dd) : Scalar(0);
  } else {
    t = (de * s + er) / ee;
    if (t < Scalar(0) || t > Scalar(1)) {
      t = clamp01(t);
      s = dd > Scalar(0) ? clamp01((t * de - dr) / dd) : Scalar(0);
    }
  }
  return (r + s * d - t * e).squaredNorm();
}

/// The zero-area fallback: best of the three edges as segments.
template <class Scalar>
Scalar closest_point_on_flat_triangle(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                                      const Vector3<Scalar>& c, Vector3<Scalar>& q, TriangleFeature& feature) {
  const Vector3<Scalar>* v[3] = {&a, &b, &c};
  Scalar best = std::numeric_limits<Scalar>::infinity();
  for (int e = 0; e < 3; ++e) {
    Vector3<Scalar> qe = p;
    Scalar t = Scalar(0);
    const Scalar d2 = closest_point_on_segment(p, *v[e], *v[(e + 1) % 3], qe, t);
    if (d2 < best) {
      best = d2;
      q = qe;
      if (t <= Scalar(0))
        feature = static_cast<TriangleFeature>(4 + e);
      else if (t >= Scalar(1))
        feature = static_cast<TriangleFeature>(4 + (e + 1) % 3);
      else
        feature = static_cast<TriangleFeature>(1 + e);
    }
  }
  return best;
}

}  // namespace detail

template <class Scalar>
Scalar closest_point_on_triangle(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                                 const Vector3<Scalar>& c, Vector3<Scalar>& q, TriangleFeature& feature) {
  const Vector3<Scalar> ab = b - a, ac = c - a, ap = p - a;
  // Zero area (to rounding): |ab x ac| tiny against the squared longest edge.
  const Scalar area2 = ab.cross(ac).squaredNorm();
  const Scalar l2 = std::max(std::max(ab.squaredNorm(), ac.squaredNorm()), (c - b).squaredNorm());
  const Scalar eps = Scalar(16) * std::numeric_limits<Scalar>::epsilon();
  if (!(area2 > eps * eps * l2 * l2)) return detail::closest_point_on_flat_triangle(p, a, b, c, q, feature);

  const Scalar d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= Scalar(0) && d2 <= Scalar(0)) {
    q = a;
    feature = TriangleFeature::VertexA;
    return ap.squaredNorm();
  }
  const Vector3<Scalar> bp = p - b;
  const Scalar d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= Scalar(0) && d4 <= d3) {
    q = b;
    feature = TriangleFeature::VertexB;
    return bp.squaredNorm();
  }
  const Scalar vc = d1 * d4 - d3 * d2;
  if (vc <= Scalar(0) && d1 >= Scalar(0) && d3 <= Scalar(0)) {
    const Scalar den = d1 - d3;
    const Scalar v = den > Scalar(0) ? d1 / den : Scalar(0);
    q = a + v * ab;
    feature = TriangleFeature::EdgeAB;
    return (p - q).squaredNorm();
  }
  const Vector3<Scalar> cp = p - c;
  const Scalar d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= Scalar(0) && d5 <= d6) {
    q = c;
    feature = TriangleFeature::VertexC;
    return cp.squaredNorm();
  }
  const Scalar vb = d5 * d2 - d1 * d6;
  if (vb <= Scalar(0) && d2 >= Scalar(0) && d6 <= Scalar(0)) {
    const Scalar den = d2 - d6;
    const Scalar w = den > Scalar(0) ? d2 / den : Scalar(0);
    q = a + w * ac;
    feature = TriangleFeature::EdgeCA;
    return (p - q).squaredNorm();
  }
  const Scalar va = d3 * d6 - d5 * d4;
  const Scalar e1 = d4 - d3, e2 = d5 - d6;
  if (va <= Scalar(0) && e1 >= Scalar(0) && e2 >= Scalar(0)) {
    const Scalar den = e1 + e2;
    const Scalar w = den > Scalar(0) ? e1 / den : Scalar(0);
    q = b + w * (c - b);
    feature = TriangleFeature::EdgeBC;
    return (p - q).squaredNorm();
  }
  const Scalar den = va + vb + vc;
  if (!(den > Scalar(0))) return detail::closest_point_on_flat_triangle(p, a, b, c, q, feature);
  // The face region: p's projection onto the plane, from the plane's own normal (the
  // barycentric numerators above are differences of products, too coarse in float to place
  // q within a few units in the last place of p).
  const Vector3<Scalar> n = ab.cross(ac);
  const Scalar h = n.dot(ap) / area2;
  q = p - h * n;
  feature = TriangleFeature::Face;
  return h * h * area2;
}

template <class Scalar>
Scalar segment_triangle_distance2(const Vector3<Scalar>& p0, const Vector3<Scalar>& p1, const Vector3<Scalar>& a,
                                  const Vector3<Scalar>& b, const Vector3<Scalar>& c, Scalar& u) {
  // Crossing: the endpoints' heights over the plane differ in sign and the crossing point lies
  // in the triangle (barycentric coordinates of its projection, all >= 0).
  const Vector3<Scalar> d = p1 - p0, n = (b - a).cross(c - a);
  const Scalar h0 = n.dot(p0 - a), h1 = n.dot(p1 - a);
  if ((h0 <= Scalar(0)) != (h1 <= Scalar(0)) || (h0 == Scalar(0) && h1 == Scalar(0))) {
    const Scalar w = h0 == h1 ? Scalar(0) : h0 / (h0 - h1);
    const Vector3<Scalar> x = p0 + w * d;
    if (n.dot((b - a).cross(x - a)) >= Scalar(0) && n.dot((c - b).cross(x - b)) >= Scalar(0) &&
        n.dot((a - c).cross(x - c)) >= Scalar(0) && n.squaredNorm() > Scalar(0)) {
      u = w;
      return Scalar(0);
    }
  }
  // Otherwise a closest pair holds a point of a triangle edge (the segment against the three
  // edges) or an interior point of the face, whose partner is then a segment end (an end
  // whose projection falls inside the face, at its height).
  Scalar best = std::numeric_limits<Scalar>::infinity();
  u = Scalar(0);
  const Vector3<Scalar> ab = b - a, ac = c - a;
  const Scalar uu = ab.dot(ab), uv = ab.dot(ac), vv = ac.dot(ac), nn = n.squaredNorm();
  for (int k = 0; k < 2 && nn > Scalar(0); ++k) {
    const Vector3<Scalar> ap = (k == 0 ? p0 : p1) - a;
    const Scalar d1 = ab.dot(ap), d2 = ac.dot(ap), s = d1 * vv - d2 * uv, t = d2 * uu - d1 * uv;
    const Scalar h = k == 0 ? h0 : h1;
    if (s >= Scalar(0) && t >= Scalar(0) && s + t <= uu * vv - uv * uv && h * h / nn < best) {
      best = h * h / nn;
      u = Scalar(k);
    }
  }
  const Vector3<Scalar>* v[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    Scalar s = Scalar(0), t = Scalar(0);
    const Scalar e2 = detail::closest_points_of_segments(p0, d, *v[k], Vector3<Scalar>(*v[(k + 1) % 3] - *v[k]), s, t);
    if (e2 < best) {
      best = e2;
      u = s;
    }
  }
  return best;
}

template <class Scalar>
Scalar triangle_solid_angle(const Vector3<Scalar>& p, const Vector3<Scalar>& a, const Vector3<Scalar>& b,
                            const Vector3<Scalar>& c) {
  const Vector3<Scalar> x = a - p, y = b - p, z = c - p;
  const Scalar lx = x.norm(), ly = y.norm(), lz = z.norm();
  const Scalar num = x.dot(y.cross(z));
  const Scalar den = lx * ly * lz + x.dot(y) * lz + x.dot(z) * ly + y.dot(z) * lx;
  return Scalar(2) * std::atan2(num, den);
}

}  // namespace grip
