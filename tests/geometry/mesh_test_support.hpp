#pragma once
// Shared helpers of the mesh tests: a seeded uniform draw that is the same on every standard
// library, meshes written out by hand or by formula (a cube, icospheres, a bumpy star-shaped
// blob with concave parts), and file reading for the shipped meshes of tests/data/meshes/.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <grip/geometry/triangle_mesh.hpp>

namespace grip_mesh_test {

/// Uniform in (0, 1) from the raw 32-bit output of mt19937 (no std::*_distribution).
inline double u01(std::mt19937& g) { return (double(g()) + 0.5) / 4294967296.0; }
/// Uniform in (lo, hi).
inline double uniform(std::mt19937& g, double lo, double hi) { return lo + (hi - lo) * u01(g); }

using V3 = Eigen::Vector3d;

/// A unit vector uniform on the sphere.
inline V3 unit_vector(std::mt19937& g) {
  const double z = uniform(g, -1, 1), a = uniform(g, 0, 2 * 3.141592653589793), s = std::sqrt(1 - z * z);
  return V3(s * std::cos(a), s * std::sin(a), z);
}

/// A triangle soup in double: vertices and outward (counter-clockwise) triangles.
struct Soup {
  std::vector<V3> v;
  std::vector<std::array<int, 3>> t;
};

/// The axis-aligned box of half sizes h around c, as 8 vertices and 12 outward triangles.
inline Soup box_soup(const V3& h, const V3& c = V3::Zero()) {
  Soup s;
  for (int i = 0; i < 8; ++i)
    s.v.push_back(c + V3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()));
  // Faces -z, +z, -y, +y, -x, +x as two triangles each (checked outward by the volume test).
  s.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

/// An icosphere of `levels` subdivisions (20 4^levels triangles) on the unit sphere.
inline Soup icosphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  Soup s;
  const double raw[12][3] = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                             {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  for (const auto& r : raw) s.v.push_back(V3(r[0], r[1], r[2]).normalized());
  s.t = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
         {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      s.v.push_back((s.v[static_cast<std::size_t>(a)] + s.v[static_cast<std::size_t>(b)]).normalized());
      const int k = static_cast<int>(s.v.size()) - 1;
      mid[key] = k;
      return k;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : s.t) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    s.t = next;
  }
  return s;
}

/// Radius of the bumpy blob along unit direction d: star-shaped with concave dents (m).
inline double bumpy_radius(const V3& d) {
  return 0.03 * (1 + 0.25 * std::sin(3 * d.x()) * std::cos(2 * d.y()) + 0.15 * std::cos(5 * d.z()));
}

/// An icosphere of `levels` scaled by `radius` and moved by `center`, or with radius r(d) if
/// `bumpy` (bumpy_radius).
inline Soup sphere_soup(int levels, double radius, const V3& center = V3::Zero(), bool bumpy = false) {
  Soup s = icosphere(levels);
  for (V3& p : s.v) p = center + (bumpy ? bumpy_radius(p) : radius) * p;
  return s;
}

/// Appends soup b to a.
inline void append(Soup& a, const Soup& b, bool reversed = false) {
  const int off = static_cast<int>(a.v.size());
  for (const V3& p : b.v) a.v.push_back(p);
  for (const auto& t : b.t) {
    if (reversed)
      a.t.push_back({t[0] + off, t[2] + off, t[1] + off});
    else
      a.t.push_back({t[0] + off, t[1] + off, t[2] + off});
  }
}

/// Loads a soup into a mesh (cleared) and finalizes it.
template <class Mesh>
grip::MeshReport load(const Soup& s, Mesh& mesh) {
  using S = typename Mesh::ScalarType;
  mesh.clear();
  std::vector<int> idx;
  for (const V3& p : s.v) idx.push_back(mesh.add_vertex(p.cast<S>()));
  for (const auto& t : s.t)
    mesh.add_triangle(idx[static_cast<std::size_t>(t[0])], idx[static_cast<std::size_t>(t[1])],
                      idx[static_cast<std::size_t>(t[2])]);
  return mesh.finalize();
}

/// Squared distance from p to segment [a, b] (plain doubles).
inline double segment_distance2(const double* p, const double* a, const double* b) {
  double ab[3], ap[3];
  for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ap[k] = p[k] - a[k];
  const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : 0;
  t = std::min(std::max(t, 0.0), 1.0);
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
  return d2;
}

/// Squared distance from p to triangle abc, written independently of grip's region logic: the
/// plane's distance if p projects inside (same-side tests with the edge normals), else the
/// least of the three edges' (plain doubles).
inline double triangle_distance2(const double* p, const double* a, const double* b, const double* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  const double* corner[3] = {a, b, c};
  bool inside = nn > 0;
  for (int e = 0; e < 3 && inside; ++e) {
    const double* s = corner[e];
    const double* t = corner[(e + 1) % 3];
    const double d[3] = {t[0] - s[0], t[1] - s[1], t[2] - s[2]}, w[3] = {p[0] - s[0], p[1] - s[1], p[2] - s[2]};
    const double x[3] = {d[1] * w[2] - d[2] * w[1], d[2] * w[0] - d[0] * w[2], d[0] * w[1] - d[1] * w[0]};
    inside = x[0] * n[0] + x[1] * n[1] + x[2] * n[2] >= 0;
  }
  if (inside) {
    const double h = (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2];
    return h * h / nn;
  }
  return std::min(segment_distance2(p, a, b), std::min(segment_distance2(p, b, c), segment_distance2(p, c, a)));
}

/// Van Oosterom and Strackee's solid angle of triangle abc at p, written out in plain doubles.
inline double solid_angle(const double* p, const double* a, const double* b, const double* c) {
  double x[3], y[3], z[3];
  for (int k = 0; k < 3; ++k) x[k] = a[k] - p[k], y[k] = b[k] - p[k], z[k] = c[k] - p[k];
  auto dot = [](const double* s, const double* t) { return s[0] * t[0] + s[1] * t[1] + s[2] * t[2]; };
  const double yz[3] = {y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]};
  const double lx = std::sqrt(dot(x, x)), ly = std::sqrt(dot(y, y)), lz = std::sqrt(dot(z, z));
  return 2 * std::atan2(dot(x, yz), lx * ly * lz + dot(x, y) * lz + dot(x, z) * ly + dot(y, z) * lx);
}

/// A mesh's triangles as plain double corner triples (9 numbers each), for brute-force loops.
template <class Mesh>
std::vector<std::array<double, 9>> plain_triangles(const Mesh& m) {
  std::vector<std::array<double, 9>> out;
  for (int t = 0; t < m.triangle_count(); ++t) {
    std::array<double, 9> c{};
    for (int j = 0; j < 3; ++j)
      for (int d = 0; d < 3; ++d)
        c[static_cast<std::size_t>(3 * j + d)] = double(m.vertex(m.triangle(t)[static_cast<std::size_t>(j)])(d));
    out.push_back(c);
  }
  return out;
}

/// The bytes of tests/data/meshes/<name>.
inline std::string read_data_file(const char* name) {
  const std::string path = std::string(GRIP_TEST_DATA_DIR) + "/meshes/" + name;
  std::string out;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return out;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  std::fclose(f);
  return out;
}

}  // namespace grip_mesh_test
