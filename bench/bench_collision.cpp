// Contact generation for the whole hand in a power grasp of a 35 mm cylinder, per frame,
// against the octree depth (3..6), with the exhaustive all-leaf-pairs loop as the baseline in
// the same run. Target: a frame under 20 us.
//   BM_Detect<S, Samples>/depth   detect_contacts only (the posed hand given)
//   BM_Frame<S, Samples>/depth    forward kinematics + sphere hierarchy + detect_contacts
//   BM_Exhaustive<S, 8>/depth     baseline: every phalanx sample against every octree leaf
//   BM_BuildOctree<S>/depth       set-up cost of the octree (once per object)
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <grip/geometry/collision.hpp>
#include <grip/geometry/hand_closure.hpp>

namespace {

using namespace grip;
template <class S>
using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;
constexpr int cap = 32768;  // depth 6 needs about 23600 cells
constexpr int min_depth = 3, max_depth = 6;

template <class S>
struct Scene {
  SphericalOctree<S, cap> octree[max_depth + 1];
  HandDimensions<S> dims{HandDimensions<S>::standard()};
  Iso<S> pose{Iso<S>::Identity()};
  JointAngles<S> angles{JointAngles<S>::Zero()};
  Scene() {
    const Shape<S> shape(make_cylinder<S>(S(0.035), S(0.07)));
    for (int d = min_depth; d <= max_depth; ++d) octree[d].build(shape, d);
    pose.linear() = Eigen::AngleAxis<S>(S(3.14159265358979323846 / 2), Vector3<S>::UnitX()).toRotationMatrix();
    pose.translation() = Vector3<S>(dims.base[1].x() + S(0.02), S(0), -(S(0.035) + dims.radius[2] + S(0.001)));
    // Close the hand on the depth-5 octree: 2 mm target depth, as in tests/geometry/power_grasp.
    close_hand(dims, Iso<S>::Identity(), octree[5], pose, S(0.002), S(0.02), angles);
  }
};
template <class S>
Scene<S>& scene() {
  static Scene<S>* s = new Scene<S>();  // large: heap once at bench start-up, never freed
  return *s;
}

template <class S, int Samples>
void BM_Detect(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto& oct = sc.octree[state.range(0)];
  HandPosture<S> posture;
  forward_kinematics(sc.dims, Iso<S>::Identity(), sc.angles, posture);
  HandCollisionModel<S, Samples> hand;
  hand.set_posture(posture);
  HandContacts<S> out;
  for (auto _ : state) {
    detect_contacts(hand, oct, sc.pose, out);
    benchmark::DoNotOptimize(out.count);
    benchmark::ClobberMemory();
  }
  state.counters["contacts"] = out.count;
  state.counters["leaves"] = oct.leaf_count();
}

template <class S, int Samples>
void BM_Frame(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto& oct = sc.octree[state.range(0)];
  HandPosture<S> posture;
  HandCollisionModel<S, Samples> hand;
  HandContacts<S> out;
  JointAngles<S> q = sc.angles;
  for (auto _ : state) {
    benchmark::DoNotOptimize(q.data());
    forward_kinematics(sc.dims, Iso<S>::Identity(), q, posture);
    hand.set_posture(posture);
    detect_contacts(hand, oct, sc.pose, out);
    benchmark::DoNotOptimize(out.count);
    benchmark::ClobberMemory();
  }
  state.counters["contacts"] = out.count;
}

template <class S, int Samples>
void BM_Exhaustive(benchmark::State& state) {
  Scene<S>& sc = scene<S>();
  const auto& oct = sc.octree[state.range(0)];
  HandPosture<S> posture;
  forward_kinematics(sc.dims, Iso<S>::Identity(), sc.angles, posture);
  HandCollisionModel<S, Samples> hand;
  hand.set_posture(posture);
  HandContacts<S> out;
  for (auto _ : state) {
    detect_contacts_exhaustive(hand, oct, sc.pose, out);
    benchmark::DoNotOptimize(out.count);
    benchmark::ClobberMemory();
  }
  state.counters["contacts"] = out.count;
}

template <class S>
void BM_BuildOctree(benchmark::State& state) {
  static SphericalOctree<S, cap> oct;
  const Shape<S> shape(make_cylinder<S>(S(0.035), S(0.07)));
  for (auto _ : state) {
    oct.build(shape, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(oct.tree().size());
  }
  state.counters["cells"] = oct.tree().size();
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Detect, float, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Detect, double, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Detect, float, 4)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Frame, float, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Frame, double, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Exhaustive, float, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Exhaustive, double, 8)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_BuildOctree, double)->DenseRange(min_depth, max_depth)->Unit(benchmark::kMillisecond);
