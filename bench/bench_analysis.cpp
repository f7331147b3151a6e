// Grasp analysis costs: exact-cone force closure and Ferrari-Canny epsilon for n = 3..20,
// and batch throughput on 2 threads against the serial loop in the same run.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <grip/analysis/batch.hpp>

namespace {

using G = grip::Grasp<grip::Dynamic, grip::HardFinger, double, 20>;

grip::Contact<double> random_contact(std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double th = std::acos(1 - 2 * u01(rng)), ph = 6.283185307179586 * u01(rng);
  const grip::Vector3<double> u(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  grip::Contact<double> c;
  c.position = 0.04 * u;
  c.normal = -u;
  c.friction = 0.3 + 0.5 * u01(rng);
  c.squeeze = 1.0;
  return c;
}

G random_grasp(std::mt19937& rng, int n) {
  G g;
  for (int i = 0; i < n; ++i) (void)g.add(random_contact(rng));
  return g;
}

std::vector<G> grasps(int n, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<G> v;
  for (int i = 0; i < count; ++i) v.push_back(random_grasp(rng, n));
  return v;
}

void BM_ForceClosure(benchmark::State& st) {
  const auto v = grasps(static_cast<int>(st.range(0)), 64, 1);
  std::size_t i = 0;
  for (auto _ : st) benchmark::DoNotOptimize(grip::force_closure(v[i++ % v.size()]));
}
BENCHMARK(BM_ForceClosure)->DenseRange(3, 20, 1);

void BM_EpsilonL1(benchmark::State& st) {
  const auto v = grasps(static_cast<int>(st.range(0)), 64, 2);
  auto ws = std::make_unique<grip::EpsilonWorkspace<double>>();
  std::size_t i = 0;
  for (auto _ : st)
    benchmark::DoNotOptimize(grip::ferrari_canny_epsilon<8>(v[i++ % v.size()], grip::EpsilonNorm::L1, 0.04, *ws));
}
BENCHMARK(BM_EpsilonL1)->DenseRange(3, 20, 1);

void BM_EpsilonLinf(benchmark::State& st) {
  const auto v = grasps(static_cast<int>(st.range(0)), 64, 3);
  auto ws = std::make_unique<grip::EpsilonWorkspace<double>>();
  std::size_t i = 0;
  for (auto _ : st)
    benchmark::DoNotOptimize(
        grip::ferrari_canny_epsilon<8>(v[i++ % v.size()], grip::EpsilonNorm::LInfinity, 0.04, *ws));
}
BENCHMARK(BM_EpsilonLinf)->DenseRange(3, 20, 1);

// Batch of 512 grasps of 6 contacts: threads = 1 (serial baseline) vs 2. items/s = grasps/s.
void BM_Batch(benchmark::State& st) {
  const auto v = grasps(6, 512, 4);
  std::vector<grip::GraspMetrics<double>> out(v.size());
  grip::BatchSettings<double> s;
  s.lever_length = 0.04;
  s.threads = static_cast<int>(st.range(0));
  for (auto _ : st) {
    grip::evaluate_batch<8>(v.data(), static_cast<int>(v.size()), out.data(), s);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<long long>(st.iterations()) * static_cast<long long>(v.size()));
}
BENCHMARK(BM_Batch)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
