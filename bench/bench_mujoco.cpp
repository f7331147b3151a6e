// The MuJoCo adapter's cost per simulation step against mj_step of the same scene, in one run
// (goal: the adapter at most 10 % of mj_step for a grasp of about 20 contacts).
//
// Scene: a 6 cm box of 0.2 kg held between two rows of three pads (a hand's phalanges) on a
// rig welded to a mocap target, elliptic cones: 24 box-pad contacts. Each benchmark steps the
// same settled state: BM_MjStep restores it and calls mj_step; BM_AdapterUpdate reads it
// (update()); BM_AdapterSolve reads it and solves (solve_constrained, cold) into FeltForces.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <grip/mujoco/adapter.hpp>
#include <grip/solve/solve_constrained.hpp>

namespace {

std::string scene_xml() {
  std::string pads;
  const double ys[3] = {-0.018, 0.0, 0.018};
  int n = 0;
  for (const double x : {0.0345, -0.0345})
    for (const double y : ys) {
      pads += "<body name=\"pad" + std::to_string(n++) + "\" pos=\"" + std::to_string(x) + " " + std::to_string(y) +
              " 0\"><geom type=\"box\" size=\"0.005 0.008 0.02\" friction=\"1 0.005 0.0001\"/></body>";
    }
  return "<mujoco><option timestep=\"0.001\" cone=\"elliptic\" impratio=\"10\"/><worldbody>"
         "<geom type=\"plane\" pos=\"0 0 -0.5\" size=\"1 1 0.1\"/>"
         "<body name=\"target\" mocap=\"true\" pos=\"0 0 0.2\"/>"
         "<body name=\"rig\" pos=\"0 0 0.2\"><freejoint/><inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"0.01 0.01 "
         "0.01\"/>" +
         pads +
         "</body><body name=\"box\" pos=\"0 0 0.2\"><freejoint/><geom type=\"box\" size=\"0.03 0.03 0.03\" "
         "mass=\"0.2\"/>"
         "</body></worldbody><equality><weld body1=\"target\" body2=\"rig\" solref=\"0.01 1\"/></equality></mujoco>";
}

struct Fixture {
  mjModel* m{nullptr};
  mjData* d{nullptr};
  mjData* settled{nullptr};
  grip::mujoco::Adapter<> adapter;
  Fixture() {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("grip_bench_mujoco_" + std::to_string(::getpid()) + ".xml");
    {
      std::ofstream out(path);
      out << scene_xml();
    }
    char error[1000] = "";
    m = mj_loadXML(path.string().c_str(), nullptr, error, sizeof error);
    std::filesystem::remove(path);
    if (m == nullptr) {
      std::fprintf(stderr, "bench_mujoco: %s\n", error);
      std::exit(1);
    }
    d = mj_makeData(m);
    for (int i = 0; i < 300; ++i) mj_step(m, d);
    settled = mj_copyData(nullptr, m, d);
    grip::mujoco::BodyName names[6];
    const char* pad_names[6] = {"pad0", "pad1", "pad2", "pad3", "pad4", "pad5"};
    for (int i = 0; i < 6; ++i) names[i] = {pad_names[i], 2 + 3 * (i % 3) + (i < 3 ? 2 : 0)};
    if (adapter.bind(m, "box", names, 6) != grip::Status::Ok) std::exit(1);
  }
  ~Fixture() {
    mj_deleteData(settled);
    mj_deleteData(d);
    mj_deleteModel(m);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_MjStep(benchmark::State& state) {
  Fixture& f = fixture();
  for (auto _ : state) {
    state.PauseTiming();
    mj_copyData(f.d, f.m, f.settled);
    state.ResumeTiming();
    mj_step(f.m, f.d);
  }
  state.counters["contacts"] = f.d->ncon;
}

void BM_AdapterUpdate(benchmark::State& state) {
  Fixture& f = fixture();
  for (auto _ : state) benchmark::DoNotOptimize(f.adapter.update(f.m, f.settled));
  state.counters["grasp_contacts"] = f.adapter.grasp().size();
}

void BM_AdapterSolve(benchmark::State& state) {
  Fixture& f = fixture();
  grip::FeltForces<double> felt;
  grip::Status st = grip::Status::InvalidInput;
  for (auto _ : state) {
    f.adapter.update(f.m, f.settled);
    st = f.adapter.solve([](const auto& g, const auto& w) { return grip::solve_constrained(g, w); }, felt);
    benchmark::DoNotOptimize(felt);
  }
  state.counters["grasp_contacts"] = f.adapter.grasp().size();
  state.counters["ok"] = st == grip::Status::Ok ? 1 : 0;
}

BENCHMARK(BM_MjStep)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_AdapterUpdate)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_AdapterSolve)->Unit(benchmark::kMicrosecond)->MinTime(0.5);

}  // namespace
