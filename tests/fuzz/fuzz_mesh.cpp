// libFuzzer target over grip's mesh readers and mesh distance field (clang
// -fsanitize=fuzzer,address,undefined). The bytes are read as OBJ and as STL into small meshes
// of float and double; each reader must return a status without reading past the bytes or
// writing past the mesh. Any broken promise aborts, which libFuzzer reports as a crash:
// - counts beyond the capacities;
// - an Ok report of a mesh that is not closed and consistently oriented (every edge's
//   neighbour runs along it the other way), or with a non-positive or non-finite volume;
// - when Ok: MeshShape::build refusing it, or a distance, normal or winding number that is
//   not finite at a finite point (bounding-box corners, centre, points outside), or a heap
//   allocation in distance() (Eigen's check armed).
// Seeds: tests/fuzz/corpus/mesh/. Build and run (N minutes = 60 N seconds, split between
// this target and grip_fuzz_solvers), from the source tree:
//   cmake --workflow --preset ci-fuzz && bash cmake/fuzz.sh 600
#define EIGEN_RUNTIME_NO_MALLOC
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>

namespace {

constexpr int max_vertices = 64, max_triangles = 128;

void fail(const char* what) {
  std::fprintf(stderr, "broken promise: %s\n", what);
  std::abort();
}

template <class S>
void check_mesh(const grip::TriangleMesh<S, max_vertices, max_triangles>& mesh, const grip::MeshReport& r) {
  using Mesh = grip::TriangleMesh<S, max_vertices, max_triangles>;
  if (mesh.vertex_count() < 0 || mesh.vertex_count() > Mesh::max_vertices) fail("vertex count beyond capacity");
  if (mesh.triangle_count() < 0 || mesh.triangle_count() > Mesh::max_triangles) fail("triangle count beyond capacity");
  if (r.vertices > Mesh::max_vertices || r.triangles > Mesh::max_triangles) fail("report counts beyond capacity");
  if (r.ok() != (r.issue == grip::MeshIssue::None)) fail("status and issue disagree");
  if (!r.ok()) return;
  if (!mesh.finalized()) fail("Ok but not finalized");
  if (!(mesh.volume() > S(0)) || !std::isfinite(mesh.volume())) fail("Ok with a bad volume");
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const std::array<int, 3>& tri = mesh.triangle(t);
    if (!mesh.face_normal(t).allFinite()) fail("non-finite face normal");
    for (int e = 0; e < 3; ++e) {
      const int nb = mesh.neighbour(t, e);
      if (nb < 0 || nb >= mesh.triangle_count()) fail("Ok but not closed");
      const int u = tri[static_cast<std::size_t>(e)], v = tri[static_cast<std::size_t>((e + 1) % 3)];
      int back = 0;
      for (int k = 0; k < 3; ++k)
        back += mesh.triangle(nb)[static_cast<std::size_t>(k)] == v &&
                mesh.triangle(nb)[static_cast<std::size_t>((k + 1) % 3)] == u;
      if (back != 1) fail("Ok but an edge's neighbour does not run back along it");
      if (!mesh.vertex_normal(u).allFinite() || !(std::abs(mesh.vertex_normal(u).norm() - S(1)) < S(1e-3)))
        fail("bad vertex pseudo-normal");
    }
  }
}

template <class S>
void query(const grip::TriangleMesh<S, max_vertices, max_triangles>& mesh) {
  static grip::MeshShape<S, max_vertices, max_triangles> shape;
  if (shape.build(mesh) != grip::Status::Ok) fail("build refused an Ok mesh");
  grip::Vector3<S> lo = grip::Vector3<S>::Zero(), hi = lo;
  if (!shape.bounding_box(lo, hi)) fail("no bounding box");
  const grip::Vector3<S> c = (lo + hi) / S(2), e = hi - lo;
  const grip::Vector3<S> points[] = {lo,
                                     hi,
                                     c,
                                     c + S(3) * e,
                                     lo - e,
                                     c + grip::Vector3<S>(e.x(), S(0), S(0)) / S(3),
                                     mesh.vertex(mesh.triangle(0)[0])};
  const auto view = grip::winding_signed(shape);
  for (const grip::Vector3<S>& p : points) {
    if (!p.allFinite()) continue;
    grip::Vector3<S> n = grip::Vector3<S>::Zero();
    Eigen::internal::set_is_malloc_allowed(false);
    const S d = shape.distance(p, n);
    Eigen::internal::set_is_malloc_allowed(true);
    if (!std::isfinite(d) || !n.allFinite()) fail("non-finite distance or normal at a finite point");
    if (!(std::abs(n.norm() - S(1)) < S(1e-3))) fail("normal not unit");
    S bound = S(0);
    const S w = shape.winding_number(p, bound);
    if (!std::isfinite(w) || !std::isfinite(bound) || !std::isfinite(shape.winding_number_exact(p)))
      fail("non-finite winding number");
    const S dv = view.distance(p, n);
    if (!std::isfinite(dv) || !n.allFinite()) fail("non-finite view distance");
  }
}

template <class S>
void run(const char* data, std::size_t size) {
  static grip::TriangleMesh<S, max_vertices, max_triangles> mesh;
  grip::MeshReport r = grip::read_obj(data, size, mesh);
  check_mesh(mesh, r);
  if (r.ok()) query(mesh);
  r = grip::read_stl(data, size, mesh);
  check_mesh(mesh, r);
  if (r.ok()) query(mesh);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const char* bytes = reinterpret_cast<const char*>(data);
  run<double>(bytes, size);
  run<float>(bytes, size);
  return 0;
}
