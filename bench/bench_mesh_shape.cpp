// The signed distance field of a triangle mesh: tests/data/meshes/blob.obj (5120 triangles, about
// 78 mm across), with the loop over all triangles as the baseline in the same run.
//   BM_Distance<S>/range_um       distance() at points within range of the surface (1024 points
//                                 spread over the whole surface, taken in turn: caches cold-ish)
//   BM_DistancePath<S>/range_um   the same along a path that moves 0.1 mm per call over the
//                                 surface (a phalanx sample from frame to frame: caches warm)
//   BM_BruteForce<S>/range_um     baseline: closest_point_on_triangle over every triangle
//   BM_WindingFast<S>/range_um    winding_number() (far field 2), BM_WindingExact<S> O(T)
//   BM_Build<S>                   MeshShape::build (the hierarchy), BM_ReadFinalize<S> read_obj
//                                 from memory, welding and finalize()
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>

namespace {

using namespace grip;
constexpr int max_v = 4096, max_t = 8192, points = 1024;

std::string blob_text() {
  std::string out;
  std::FILE* f = std::fopen(GRIP_TEST_DATA_DIR "/meshes/blob.obj", "rb");
  if (f == nullptr) return out;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  std::fclose(f);
  return out;
}

template <class S>
struct Scene {
  std::string text{blob_text()};
  TriangleMesh<S, max_v, max_t> mesh;
  MeshShape<S, max_v, max_t> shape;
  Scene() {
    const MeshReport r = read_obj(text.data(), text.size(), mesh);
    if (!r.ok() || shape.build(mesh) != Status::Ok) std::fprintf(stderr, "blob.obj: %s\n", to_string(r.issue));
  }
  // Points q + d n: q uniform on a random triangle, n its normal, d uniform in [-range, range].
  std::vector<Vector3<S>> near_points(double range, std::uint32_t seed) const {
    std::mt19937 g(seed);
    auto u = [&g] { return (double(g()) + 0.5) / 4294967296.0; };
    std::vector<Vector3<S>> out;
    for (int i = 0; i < points; ++i) {
      const int t = static_cast<int>(u() * mesh.triangle_count());
      double a = u(), b = u();
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const auto& tri = mesh.triangle(t);
      const Vector3<double> p0 = mesh.vertex(tri[0]).template cast<double>(),
                            p1 = mesh.vertex(tri[1]).template cast<double>(),
                            p2 = mesh.vertex(tri[2]).template cast<double>();
      const Vector3<double> q = p0 + a * (p1 - p0) + b * (p2 - p0);
      out.push_back((q + (2 * u() - 1) * range * mesh.face_normal(t).template cast<double>()).template cast<S>());
    }
    return out;
  }
  // A path over the surface: a point on a circle of latitude, pushed out to the surface and
  // then off it by range times a slow oscillation; 0.1 mm between calls.
  std::vector<Vector3<S>> path_points(double range) const {
    std::vector<Vector3<S>> out;
    for (int i = 0; i < points; ++i) {
      const double a = 1e-4 * i / 0.03, z = 0.3 * std::sin(0.7 * a);
      const Vector3<double> dir(std::cos(a) * std::sqrt(1 - z * z), std::sin(a) * std::sqrt(1 - z * z), z);
      Vector3<S> q = Vector3<S>::Zero();
      int t = 0;
      TriangleFeature f = TriangleFeature::Face;
      shape.closest_point((0.1 * dir).template cast<S>(), q, t, f);  // the surface point seen from outside
      out.push_back(
          (q.template cast<double>() + range * std::sin(0.05 * i) * mesh.face_normal(t).template cast<double>())
              .template cast<S>());
    }
    return out;
  }
};
template <class S>
Scene<S>& scene() {
  static Scene<S>* s = new Scene<S>();  // large: heap once at bench start-up, never freed
  return *s;
}

template <class S>
void BM_Distance(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto pts = sc.near_points(1e-6 * double(state.range(0)), 1);
  std::size_t i = 0;
  for (auto _ : state) {
    Vector3<S> n = Vector3<S>::Zero();
    benchmark::DoNotOptimize(sc.shape.distance(pts[i], n));
    benchmark::DoNotOptimize(n.data());
    i = (i + 1) % pts.size();
  }
  state.counters["triangles"] = sc.mesh.triangle_count();
}

template <class S>
void BM_DistancePath(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto pts = sc.path_points(1e-6 * double(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    Vector3<S> n = Vector3<S>::Zero();
    benchmark::DoNotOptimize(sc.shape.distance(pts[i], n));
    benchmark::DoNotOptimize(n.data());
    i = (i + 1) % pts.size();
  }
}

template <class S>
void BM_BruteForce(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto pts = sc.near_points(1e-6 * double(state.range(0)), 1);
  const auto& m = sc.mesh;
  std::size_t i = 0;
  for (auto _ : state) {
    S best = std::numeric_limits<S>::infinity();
    for (int t = 0; t < m.triangle_count(); ++t) {
      Vector3<S> q = Vector3<S>::Zero();
      TriangleFeature f = TriangleFeature::Face;
      const auto& tri = m.triangle(t);
      const S d2 = closest_point_on_triangle(pts[i], m.vertex(tri[0]), m.vertex(tri[1]), m.vertex(tri[2]), q, f);
      best = d2 < best ? d2 : best;
    }
    benchmark::DoNotOptimize(best);
    i = (i + 1) % pts.size();
  }
}

template <class S>
void BM_WindingFast(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto pts = sc.near_points(1e-6 * double(state.range(0)), 2);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sc.shape.winding_number(pts[i]));
    i = (i + 1) % pts.size();
  }
}

template <class S>
void BM_WindingExact(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto pts = sc.near_points(1e-6 * double(state.range(0)), 2);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sc.shape.winding_number_exact(pts[i]));
    i = (i + 1) % pts.size();
  }
}

template <class S>
void BM_Build(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  static MeshShape<S, max_v, max_t> shape;
  for (auto _ : state) benchmark::DoNotOptimize(shape.build(sc.mesh));
  state.counters["nodes"] = shape.node_count();
}

template <class S>
void BM_ReadFinalize(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  static TriangleMesh<S, max_v, max_t> mesh;
  for (auto _ : state) benchmark::DoNotOptimize(read_obj(sc.text.data(), sc.text.size(), mesh).status);
  state.counters["bytes"] = static_cast<double>(sc.text.size());
}

// Ranges in micrometres.
BENCHMARK_TEMPLATE(BM_Distance, double)->Arg(1000)->Arg(3000)->Arg(10000);
BENCHMARK_TEMPLATE(BM_Distance, float)->Arg(1000)->Arg(3000)->Arg(10000);
BENCHMARK_TEMPLATE(BM_DistancePath, double)->Arg(1000)->Arg(10000);
BENCHMARK_TEMPLATE(BM_DistancePath, float)->Arg(1000)->Arg(10000);
BENCHMARK_TEMPLATE(BM_BruteForce, double)->Arg(10000);
BENCHMARK_TEMPLATE(BM_BruteForce, float)->Arg(10000);
BENCHMARK_TEMPLATE(BM_WindingFast, double)->Arg(1000)->Arg(10000);
BENCHMARK_TEMPLATE(BM_WindingFast, float)->Arg(10000);
BENCHMARK_TEMPLATE(BM_WindingExact, double)->Arg(10000);
BENCHMARK_TEMPLATE(BM_Build, double)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Build, float)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ReadFinalize, double)->Unit(benchmark::kMillisecond);

}  // namespace
