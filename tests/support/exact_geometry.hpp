#pragma once
// Independent exact geometry for the collision tests: signed distances of the solids written
// from their surfaces (distance to each face, disc or tube, then the sign from a containment
// test: not the formulas of grip's shape.hpp), the deepest point of a phalanx's axis by dense
// sampling and ternary search, a seeded uniform draw that is the same on every standard
// library, and random rotations.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Geometry>

namespace grip_test {

using V3 = Eigen::Vector3d;

/// Uniform in (0, 1) from the raw 32-bit output of mt19937 (the same draw everywhere).
inline double u01(std::mt19937& g) { return (double(g()) + 0.5) / 4294967296.0; }
/// Uniform in (lo, hi).
inline double uniform(std::mt19937& g, double lo, double hi) { return lo + (hi - lo) * u01(g); }
/// A unit vector uniform on the sphere (z uniform, azimuth uniform).
inline V3 unit_vector(std::mt19937& g) {
  const double z = uniform(g, -1, 1), a = uniform(g, 0, 2 * 3.141592653589793), s = std::sqrt(1 - z * z);
  return V3(s * std::cos(a), s * std::sin(a), z);
}
/// A random rotation (axis uniform, angle uniform in [0, pi)).
inline Eigen::Matrix3d rotation(std::mt19937& g) {
  const double angle = uniform(g, 0, 3.141592653589793);  // (drawn in this order on every compiler)
  const V3 axis = unit_vector(g);
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// Distance from q to the axis-aligned rectangle {|x_u| <= hu, |x_v| <= hv, x_w = w0}.
inline double rectangle_distance(const V3& q, int u, int v, int w, double hu, double hv, double w0) {
  const double du = std::max(std::abs(q(u)) - hu, 0.0), dv = std::max(std::abs(q(v)) - hv, 0.0);
  return std::sqrt(du * du + dv * dv + (q(w) - w0) * (q(w) - w0));
}

/// A box of half sizes h (local frame: x = R^T (p - c)): min over its six faces, signed.
struct ExactBox {
  V3 c, h;
  Eigen::Matrix3d R;
  double operator()(const V3& p) const {
    const V3 q = R.transpose() * (p - c);
    double d = 1e9;
    for (int w = 0; w < 3; ++w)
      for (int s = -1; s <= 1; s += 2)
        d = std::min(d, rectangle_distance(q, (w + 1) % 3, (w + 2) % 3, w, h((w + 1) % 3), h((w + 2) % 3), s * h(w)));
    const bool inside = std::abs(q.x()) <= h.x() && std::abs(q.y()) <= h.y() && std::abs(q.z()) <= h.z();
    return inside ? -d : d;
  }
};

/// A solid cylinder (axis local z): min over its tube and two discs, signed.
struct ExactCylinder {
  V3 c;
  Eigen::Matrix3d R;
  double radius, half;
  double operator()(const V3& p) const {
    const V3 q = R.transpose() * (p - c);
    const double rho = std::hypot(q.x(), q.y());
    const double zc = std::clamp(q.z(), -half, half);
    double d = std::hypot(rho - radius, q.z() - zc);  // the tube
    const double rc = std::min(rho, radius);
    for (int s = -1; s <= 1; s += 2) d = std::min(d, std::hypot(rho - rc, q.z() - s * half));  // the discs
    return rho <= radius && std::abs(q.z()) <= half ? -d : d;
  }
};

/// A ball.
struct ExactSphere {
  V3 c;
  double radius;
  double operator()(const V3& p) const { return (p - c).norm() - radius; }
};

/// A capsule: points within `radius` of the segment [c - half R e_z, c + half R e_z].
struct ExactCapsule {
  V3 c;
  Eigen::Matrix3d R;
  double radius, half;
  double operator()(const V3& p) const {
    const V3 q = R.transpose() * (p - c);
    const double z = std::clamp(q.z(), -half, half);
    return (q - V3(0, 0, z)).norm() - radius;
  }
};

/// The smallest value of f on the segment [a, b] and where (t in [0, 1]): f on a grid of
/// `grid` + 1 points, then a ternary search around each grid minimum (100 steps).
template <class F>
double segment_minimum(const F& f, const V3& a, const V3& b, double* t_min = nullptr, int grid = 2000) {
  double best = f(a), bt = 0;
  double prev2 = 1e300, prev = best;
  auto polish = [&](double lo, double hi) {
    for (int it = 0; it < 100; ++it) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (f(a + m1 * (b - a)) < f(a + m2 * (b - a)))
        hi = m2;
      else
        lo = m1;
    }
    const double t = 0.5 * (lo + hi), v = f(a + t * (b - a));
    if (v < best) {
      best = v;
      bt = t;
    }
  };
  for (int i = 1; i <= grid; ++i) {
    const double t = double(i) / grid, v = f(a + t * (b - a));
    if (v < best) {
      best = v;
      bt = t;
    }
    if (prev < prev2 && prev <= v) polish(std::max(0.0, double(i - 2) / grid), double(i) / grid);
    prev2 = prev;
    prev = v;
  }
  if (prev < prev2) polish(double(grid - 1) / grid, 1.0);
  if (t_min) *t_min = bt;
  return best;
}

}  // namespace grip_test
