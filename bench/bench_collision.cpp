// Contacts of the whole hand per frame (collision.hpp), double, for three objects the hand
// has closed on: the 35 mm cylinder of the paper's power grasp, a 6 cm cube (the paper's
// Fig. 3), and a 5 120-triangle mesh (tests/data/meshes/blob.obj). Baselines in the same run:
// the all-pairs loop (every sample of every phalanx evaluated exactly, with no broad phase;
// for the mesh, against every triangle) and the paper mode (octree leaves only).
//   BM_Contacts<Object>/depth   detect_contacts, exact narrow phase (the posed hand given)
//   BM_Frame<Object>/depth      forward kinematics + sphere hierarchy + detect_contacts
//   BM_AllPairs<Object>         every sample against the exact field (mesh: every triangle)
//   BM_PaperMode<Object>/depth  detect_contacts without a field (leaf planes only)
//   BM_PaperExhaustive<Object>/depth  the paper mode's all-leaf-pairs reference
//   BM_BuildOctree<Object>/depth      the octree's set-up cost (once per object)
// Target: at most 20 us per frame at the recommended depth, 3 (docs/collision.md).
#include <benchmark/benchmark.h>

#include <cstdio>

#include <Eigen/Geometry>

#include <grip/collision/collision.hpp>
#include <grip/collision/hand_closure.hpp>
#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>
#include <grip/geometry/triangle.hpp>

namespace {

using namespace grip;
using S = double;
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
constexpr int cap = 32768;
constexpr int min_depth = 3, max_depth = 5;
using Blob = TriangleMesh<S, 4096, 8192>;
using BlobShape = MeshShape<S, 4096, 8192>;

// The mesh's distance by brute force: every triangle, sign from the nearest one's
// pseudo-normal via MeshShape (the all-pairs baseline's field).
struct BruteMesh {
  const BlobShape* shape;
  S distance(const Vector3<S>& p, Vector3<S>& normal) const {
    const Blob& m = *shape->mesh();
    S best = S(1e300);
    for (int t = 0; t < m.triangle_count(); ++t) {
      const auto tri = m.triangle(t);
      Vector3<S> q;
      TriangleFeature feature;
      const S d2 = closest_point_on_triangle(p, m.vertex(tri[0]), m.vertex(tri[1]), m.vertex(tri[2]), q, feature);
      if (d2 < best) best = d2;
    }
    const S signed_d = shape->distance(p, normal);  // the sign (and normal) only
    return signed_d < S(0) ? -std::sqrt(best) : std::sqrt(best);
  }
  bool bounding_box(Vector3<S>& lo, Vector3<S>& hi) const { return shape->bounding_box(lo, hi); }
};

enum class Object { Cylinder, Cube, Mesh };

struct Fixture {
  Shape<S> cylinder{make_cylinder<S>(S(0.035), S(0.07))};
  Shape<S> cube{make_box<S>(Vector3<S>::Constant(S(0.03)))};
  Blob blob;
  BlobShape blob_shape;
  SphericalOctree<S, cap> octree[3][max_depth + 1];
  HandDimensions<S> dims{HandDimensions<S>::standard()};
  Iso pose[3];
  JointAngles<S> angles[3];

  Fixture() {
    static char buffer[1 << 20];
    const MeshReport r = read_mesh_file(GRIP_TEST_DATA_DIR "/meshes/blob.obj", buffer, sizeof buffer, blob);
    if (r.status != Status::Ok || blob_shape.build(blob) != Status::Ok) std::printf("cannot load blob.obj\n");
    for (int d = min_depth; d <= max_depth; ++d) {
      octree[0][d].build(cylinder, d);
      octree[1][d].build(cube, d);
      octree[2][d].build(winding_signed(blob_shape), d);
    }
    // Each object under the palm, the hand closed on it 2 mm deep (exact contacts, depth 5).
    pose[0] = Iso::Identity();
    pose[0].linear() = Eigen::AngleAxis<S>(S(1.5707963267948966), Vector3<S>::UnitX()).toRotationMatrix();
    pose[0].translation() = Vector3<S>(dims.base[1].x() + S(0.02), S(0), -(S(0.035) + dims.radius[2] + S(0.001)));
    pose[1] = Iso::Identity();
    pose[1].translation() = Vector3<S>(dims.base[1].x() + S(0.025), S(0), -(S(0.03) + dims.radius[2] - S(0.002)));
    Vector3<S> lo, hi;
    blob_shape.bounding_box(lo, hi);
    pose[2] = Iso::Identity();
    pose[2].translation() =
        Vector3<S>(dims.base[1].x() + S(0.02), S(0), -(S(0.5) * (hi.z() - lo.z()) + dims.radius[2]));
    for (int o = 0; o < 3; ++o) {
      angles[o] = JointAngles<S>::Zero();
      if (o == 0) close_hand(dims, Iso::Identity(), octree[o][5], cylinder, pose[o], S(0.002), S(0.02), angles[o]);
      if (o == 1) close_hand(dims, Iso::Identity(), octree[o][5], cube, pose[o], S(0.002), S(0.02), angles[o]);
      if (o == 2) close_hand(dims, Iso::Identity(), octree[o][5], blob_shape, pose[o], S(0.002), S(0.02), angles[o]);
    }
  }
};
Fixture& fixture() {
  static Fixture* f = new Fixture();  // large: heap once at bench start-up, never freed
  return *f;
}

// Calls fn(field) with the object's exact distance field.
template <class Fn>
void with_field(Object o, Fn&& fn) {
  Fixture& f = fixture();
  if (o == Object::Cylinder)
    fn(f.cylinder);
  else if (o == Object::Cube)
    fn(f.cube);
  else
    fn(f.blob_shape);
}

template <Object O>
void posed_hand(HandCollisionModel<S>& hand) {
  Fixture& f = fixture();
  HandPosture<S> posture;
  forward_kinematics(f.dims, Iso::Identity(), f.angles[int(O)], posture);
  hand.set_posture(posture);
}

template <Object O>
void BM_Contacts(benchmark::State& state) {
  Fixture& f = fixture();
  const auto& oct = f.octree[int(O)][state.range(0)];
  HandCollisionModel<S> hand;
  posed_hand<O>(hand);
  HandContacts<S> out;
  with_field(O, [&](const auto& field) {
    for (auto _ : state) {
      detect_contacts(hand, oct, field, f.pose[int(O)], out);
      benchmark::DoNotOptimize(out.count);
      benchmark::ClobberMemory();
    }
  });
  state.counters["contacts"] = out.count;
  state.counters["leaves"] = oct.leaf_count();
}

template <Object O>
void BM_Frame(benchmark::State& state) {
  Fixture& f = fixture();
  const auto& oct = f.octree[int(O)][state.range(0)];
  HandPosture<S> posture;
  HandCollisionModel<S> hand;
  HandContacts<S> out;
  JointAngles<S> q = f.angles[int(O)];
  with_field(O, [&](const auto& field) {
    for (auto _ : state) {
      benchmark::DoNotOptimize(q.data());
      forward_kinematics(f.dims, Iso::Identity(), q, posture);
      hand.set_posture(posture);
      detect_contacts(hand, oct, field, f.pose[int(O)], out);
      benchmark::DoNotOptimize(out.count);
      benchmark::ClobberMemory();
    }
  });
  state.counters["contacts"] = out.count;
}

template <Object O>
void BM_AllPairs(benchmark::State& state) {
  Fixture& f = fixture();
  HandCollisionModel<S> hand;
  posed_hand<O>(hand);
  HandContacts<S> out;
  auto run = [&](const auto& field) {
    for (auto _ : state) {
      detect_contacts_direct(hand, field, f.pose[int(O)], out, ContactSettings<S>{}, all_phalanges);
      benchmark::DoNotOptimize(out.count);
      benchmark::ClobberMemory();
    }
  };
  if (O == Object::Mesh)
    run(BruteMesh{&f.blob_shape});
  else
    with_field(O, run);
  state.counters["contacts"] = out.count;
}

template <Object O>
void BM_PaperMode(benchmark::State& state) {
  Fixture& f = fixture();
  const auto& oct = f.octree[int(O)][state.range(0)];
  HandCollisionModel<S> hand;
  posed_hand<O>(hand);
  HandContacts<S> out;
  for (auto _ : state) {
    detect_contacts(hand, oct, f.pose[int(O)], out);
    benchmark::DoNotOptimize(out.count);
    benchmark::ClobberMemory();
  }
  state.counters["contacts"] = out.count;
}

template <Object O>
void BM_PaperExhaustive(benchmark::State& state) {
  Fixture& f = fixture();
  const auto& oct = f.octree[int(O)][state.range(0)];
  HandCollisionModel<S> hand;
  posed_hand<O>(hand);
  HandContacts<S> out;
  for (auto _ : state) {
    detect_contacts_exhaustive(hand, oct, f.pose[int(O)], out);
    benchmark::DoNotOptimize(out.count);
    benchmark::ClobberMemory();
  }
  state.counters["contacts"] = out.count;
}

template <Object O>
void BM_BuildOctree(benchmark::State& state) {
  static SphericalOctree<S, cap> oct;
  Fixture& f = fixture();
  for (auto _ : state) {
    if (O == Object::Mesh)
      oct.build(winding_signed(f.blob_shape), static_cast<int>(state.range(0)));
    else
      with_field(O, [&](const auto& field) { oct.build(field, static_cast<int>(state.range(0))); });
    benchmark::DoNotOptimize(oct.tree().size());
  }
  state.counters["cells"] = oct.tree().size();
}

}  // namespace

#define GRIP_COLLISION_BENCH(O)                                                                         \
  BENCHMARK_TEMPLATE(BM_Contacts, O)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);  \
  BENCHMARK_TEMPLATE(BM_Frame, O)->Arg(3)->Arg(5)->Unit(benchmark::kMicrosecond);                       \
  BENCHMARK_TEMPLATE(BM_AllPairs, O)->Unit(benchmark::kMicrosecond);                                    \
  BENCHMARK_TEMPLATE(BM_PaperMode, O)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond); \
  BENCHMARK_TEMPLATE(BM_PaperExhaustive, O)->Arg(5)->Unit(benchmark::kMicrosecond);                     \
  BENCHMARK_TEMPLATE(BM_BuildOctree, O)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMillisecond);

GRIP_COLLISION_BENCH(Object::Cylinder)
GRIP_COLLISION_BENCH(Object::Cube)
GRIP_COLLISION_BENCH(Object::Mesh)
