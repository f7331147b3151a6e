// Cost of monitoring every contact of a 20-contact grasp (exact Coulomb cone, an 8-sided
// pyramid, soft-finger elliptic cone) against solve_range_space on the same grasps, same run.
// Target: monitor < 1/10 of the solve. Per call: BM_Classify20 against BM_SolveRangeSpace20
// (each in its own loop over the same 64 grasps). BM_MonitorToSolveRatio reports ratios
// directly as counters (see there): classify (the modes: StabilityMonitor::classify, AVX-512
// when the build has it) and evaluate (the full GraspState with margins), measured on the same
// grasps in one loop, cold, steady and in the frame after the solve; both write into one result
// object kept across frames, as a real-time loop would.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <random>
#include <type_traits>
#include <vector>

#include <grip/contact/pyramid_cone.hpp>
#include <grip/monitor/resolution.hpp>
#include <grip/monitor/stability_monitor.hpp>
#include <grip/solve/solve_range_space.hpp>

namespace {

template <class Model>
using G = grip::Grasp<20, Model, double>;

grip::Contact<double> random_contact(std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double th = std::acos(1 - 2 * u01(rng)), ph = 6.283185307179586 * u01(rng);
  const grip::Vector3<double> u(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  grip::Contact<double> c;
  c.position = 0.04 * u;
  c.normal = -u;
  c.friction = 0.3 + 0.5 * u01(rng);
  c.torsional_friction = 0.005;
  c.squeeze = 2.0 * u01(rng);
  return c;
}

// Grasps per benchmark, cycled through (a power of two).
constexpr std::size_t kCases = 64;

// The i-th case, cycling: a mask, not a division (which costs tens of ns beside a 40-ns call).
template <class V>
const typename V::value_type& cycled(const V& v, std::size_t i) {
  return v[i & (kCases - 1)];
}

template <class Model>
struct Case {
  G<Model> grasp;
  grip::Wrench<double> w;
  typename G<Model>::ForceVector forces;
};

template <class Model>
std::vector<Case<Model>> cases(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<Case<Model>> v(kCases);
  for (auto& c : v) {
    for (int i = 0; i < 20; ++i) (void)c.grasp.set(i, random_contact(rng));
    for (int k = 0; k < 3; ++k) c.w(k) = 5 * n01(rng);
    for (int k = 3; k < 6; ++k) c.w(k) = 0.1 * n01(rng);
    c.forces = grip::solve_range_space(c.grasp, c.w).forces;
  }
  return v;
}

void BM_SolveRangeSpace20(benchmark::State& st) {
  const auto v = cases<grip::HardFinger>(1);
  std::size_t i = 0;
  for (auto _ : st) {
    const auto& c = cycled(v, i++);
    benchmark::DoNotOptimize(grip::solve_range_space(c.grasp, c.w));
  }
}
BENCHMARK(BM_SolveRangeSpace20);

// Full = true: StabilityMonitor::evaluate (GraspState); false: classify (GraspModes). Both write
// into one result object kept across iterations.
template <class Cone, class Model, bool Full>
void monitor20(benchmark::State& st) {
  const auto v = cases<Model>(1);
  const grip::StabilityMonitor<G<Model>, Cone> monitor;
  std::conditional_t<Full, grip::GraspState<G<Model>>, grip::GraspModes<G<Model>>> out;
  std::size_t i = 0;
  for (auto _ : st) {
    const auto& c = cycled(v, i++);
    if constexpr (Full)
      monitor.evaluate(c.grasp, c.forces, out);
    else
      monitor.classify(c.grasp, c.forces, out);
    benchmark::DoNotOptimize(out);
  }
}
template <class Cone, class Model>
void BM_Monitor20(benchmark::State& st) {
  monitor20<Cone, Model, true>(st);
}
template <class Cone, class Model>
void BM_Classify20(benchmark::State& st) {
  monitor20<Cone, Model, false>(st);
}
BENCHMARK_TEMPLATE(BM_Monitor20, grip::CoulombCone<double>, grip::HardFinger);
BENCHMARK_TEMPLATE(BM_Monitor20, grip::PyramidCone<8, double>, grip::HardFinger);
BENCHMARK_TEMPLATE(BM_Monitor20, grip::SoftFingerCone<double>, grip::SoftFinger);
BENCHMARK_TEMPLATE(BM_Classify20, grip::CoulombCone<double>, grip::HardFinger);
BENCHMARK_TEMPLATE(BM_Classify20, grip::PyramidCone<8, double>, grip::HardFinger);
BENCHMARK_TEMPLATE(BM_Classify20, grip::SoftFingerCone<double>, grip::SoftFinger);

void BM_MonitorAndResolve20(benchmark::State& st) {
  const auto v = cases<grip::HardFinger>(1);
  std::size_t i = 0;
  for (auto _ : st) {
    const auto& c = cycled(v, i++);
    const auto s = grip::monitor_grasp(c.grasp, c.forces);
    benchmark::DoNotOptimize(grip::resolve(c.grasp, c.forces, s, c.w));
  }
}
BENCHMARK(BM_MonitorAndResolve20);

// All three in one loop, each timed over a batch of 64 grasps: the ratios in the same run.
// "cold": each pass reads the 64 grasps (about 220 KB) from L2, the monitor right after the
// solver has moved on. "in_frame": what monitoring adds to a frame of a real-time loop, where
// it classifies the forces the solver has just written: (solve + classify) - solve, over the
// same batch, both passes in every iteration (their order alternates). "steady": ten
// classification passes in a row (the core's 512-bit units stay awake), per pass.
// Each iteration (about 0.1 ms) gives its own ratios, and the counters are their medians: the
// VM this was tuned on changes speed by tens of percent within a second, which a ratio of
// sums over the whole run mixes in (the in-frame figure is a difference of two passes 10 times
// its size). The *_ns counters are medians too.
void BM_MonitorToSolveRatio(benchmark::State& st) {
  const auto v = cases<grip::HardFinger>(1);
  using clock = std::chrono::steady_clock;
  const grip::StabilityMonitor<G<grip::HardFinger>> monitor;
  grip::GraspState<G<grip::HardFinger>> state;
  grip::GraspModes<G<grip::HardFinger>> modes;
  std::vector<double> solve, eval, cls, frame, steady;
  const auto seconds = [](clock::time_point a, clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  const auto solve_pass = [&] {
    for (const auto& c : v) {
      const auto sol = grip::solve_range_space(c.grasp, c.w);
      benchmark::DoNotOptimize(sol);
    }
  };
  const auto frame_pass = [&] {
    for (const auto& c : v) {
      const auto sol = grip::solve_range_space(c.grasp, c.w);
      monitor.classify(c.grasp, sol.forces, modes);
      benchmark::DoNotOptimize(modes);
    }
  };
  bool frame_first = false;
  for (auto _ : st) {
    const auto t0 = clock::now();
    for (const auto& c : v) benchmark::DoNotOptimize(grip::solve_range_space(c.grasp, c.w));
    const auto t1 = clock::now();
    for (const auto& c : v) {
      monitor.evaluate(c.grasp, c.forces, state);
      benchmark::DoNotOptimize(state);
    }
    const auto t2 = clock::now();
    for (const auto& c : v) {
      monitor.classify(c.grasp, c.forces, modes);
      benchmark::DoNotOptimize(modes);
    }
    const auto t3 = clock::now();
    frame_first = !frame_first;
    if (frame_first)
      frame_pass();
    else
      solve_pass();
    const auto t4 = clock::now();
    if (frame_first)
      solve_pass();
    else
      frame_pass();
    const auto t5 = clock::now();
    for (int r = 0; r < 10; ++r)
      for (const auto& c : v) {
        monitor.classify(c.grasp, c.forces, modes);
        benchmark::DoNotOptimize(modes);
      }
    const auto t6 = clock::now();
    const double with = seconds(frame_first ? t3 : t4, frame_first ? t4 : t5);
    const double without = seconds(frame_first ? t4 : t3, frame_first ? t5 : t4);
    solve.push_back(seconds(t0, t1));
    eval.push_back(seconds(t1, t2));
    cls.push_back(seconds(t2, t3));
    frame.push_back((with - without) / without);
    steady.push_back(seconds(t5, t6) / 10);
  }
  const auto median = [](std::vector<double> x) {
    if (x.empty()) return 0.0;
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  const auto ratios = [&](const std::vector<double>& num) {
    std::vector<double> r(num.size());
    for (std::size_t k = 0; k < num.size(); ++k) r[k] = num[k] / solve[k];
    return median(r);
  };
  const double per = 1e9 / double(v.size());
  const double solve_ns = per * median(solve);
  st.counters["classify_over_solve_cold"] = ratios(cls);
  st.counters["classify_over_solve_in_frame"] = median(frame);
  st.counters["classify_over_solve_steady"] = ratios(steady);
  st.counters["evaluate_over_solve_cold"] = ratios(eval);
  st.counters["solve_ns"] = solve_ns;
  st.counters["classify_ns_cold"] = per * median(cls);
  st.counters["classify_ns_in_frame"] = median(frame) * solve_ns;
  st.counters["evaluate_ns_cold"] = per * median(eval);
}
BENCHMARK(BM_MonitorToSolveRatio);

}  // namespace
