// The paper's Table 2 (n = 3, 5, 10, 15, 20) extended to 32 and 64 contacts: time to solve
// min F2 s.t. G f + w_ext = 0 for a spherical grip, with
//   - naive: what a user would write: Eigen MatrixXd H of eq. 9 and PartialPivLU (the baseline),
//   - solve_kkt: the paper's Gaussian elimination on the fixed-size H,
//   - solve_range_space, fixed N and bounded (Dynamic, MaxN = 64).
// All in one run; compare the per-n ratios against "naive".
//
// solve_kkt at n = 64 keeps a 198 x 198 H on the stack (310 KB), above Eigen's default
// static-allocation guard, so this benchmark raises the guard.
#define EIGEN_STACK_ALLOCATION_LIMIT 0
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <grip/grip.hpp>

namespace {

// n contacts spread over a 4 cm sphere (golden-angle spiral), mu 0.8, squeeze 1-3 N.
template <class GraspT>
GraspT spherical_grip(int n) {
  GraspT g;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, rho = std::sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
    grip::Contact<double> c;
    c.position << 0.04 * rho * std::cos(phi), 0.04 * rho * std::sin(phi), 0.04 * z;
    c.normal = -c.position.normalized();
    c.friction = 0.8;
    c.squeeze = 1.0 + 2.0 * (i % 3) / 2.0;
    if constexpr (GraspT::fixed_size == grip::Dynamic)
      (void)g.add(c);
    else
      (void)g.set(i, c);
  }
  return g;
}

grip::Wrench<double> weight_and_shake() {
  grip::Wrench<double> w;
  w << 1.5, -0.5, -0.5 * 9.81 - 3.0, 0.02, -0.01, 0.005;
  return w;
}

template <int N>
void naive_partial_piv_lu(benchmark::State& state) {
  const auto g = spherical_grip<grip::Grasp<N>>(N);
  const auto w = weight_and_shake();
  for (auto _ : state) {
    // As a user would: dynamic matrices, H and b assembled entry by entry, then LU.
    const int m = 3 * N;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + 6, m + 6);
    Eigen::VectorXd b(m + 6);
    for (int i = 0; i < N; ++i) {
      const auto& c = g.contact(i);
      h.block<3, 3>(0, 3 * i).setIdentity();
      h.block<3, 3>(3, 3 * i) = grip::skew(c.position);
      h.block<3, 3>(6 + 3 * i, 3 * i).setIdentity();
      h.block<3, 3>(6 + 3 * i, m).setIdentity();
      h.block<3, 3>(6 + 3 * i, m) *= -1.0;
      h.block<3, 3>(6 + 3 * i, m + 3) = grip::skew(c.position);
      b.segment<3>(6 + 3 * i) = c.squeeze * c.normal;
    }
    b.head<6>() = -w;
    Eigen::VectorXd x = Eigen::PartialPivLU<Eigen::MatrixXd>(h).solve(b);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["n"] = N;
}

template <int N>
void paper_solve_kkt(benchmark::State& state) {
  const auto g = spherical_grip<grip::Grasp<N>>(N);
  const auto w = weight_and_shake();
  for (auto _ : state) {
    auto sol = grip::solve_kkt(g, w);
    benchmark::DoNotOptimize(sol.forces.data());
  }
  state.counters["n"] = N;
}

template <int N>
void range_space_fixed(benchmark::State& state) {
  const auto g = spherical_grip<grip::Grasp<N>>(N);
  const auto w = weight_and_shake();
  for (auto _ : state) {
    auto sol = grip::solve_range_space(g, w);
    benchmark::DoNotOptimize(sol.forces.data());
  }
  state.counters["n"] = N;
  state.counters["ns_per_contact"] =
      benchmark::Counter(double(N), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

template <int N>
void range_space_bounded(benchmark::State& state) {
  const auto g = spherical_grip<grip::Grasp<grip::Dynamic, grip::HardFinger, double, 64>>(N);
  const auto w = weight_and_shake();
  for (auto _ : state) {
    auto sol = grip::solve_range_space(g, w);
    benchmark::DoNotOptimize(sol.forces.data());
  }
  state.counters["n"] = N;
  state.counters["ns_per_contact"] =
      benchmark::Counter(double(N), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

template <int N>
void range_space_float(benchmark::State& state) {
  grip::Grasp<N, grip::HardFinger, float> g;
  const auto gd = spherical_grip<grip::Grasp<N>>(N);
  for (int i = 0; i < N; ++i) {
    grip::Contact<float> c;
    c.position = gd.contact(i).position.template cast<float>();
    c.normal = gd.contact(i).normal.template cast<float>();
    c.squeeze = float(gd.contact(i).squeeze);
    (void)g.set(i, c);
  }
  const grip::Wrench<float> w = weight_and_shake().cast<float>();
  for (auto _ : state) {
    auto sol = grip::solve_range_space(g, w);
    benchmark::DoNotOptimize(sol.forces.data());
  }
  state.counters["n"] = N;
}

}  // namespace

#define GRIP_TABLE2(N)                         \
  BENCHMARK_TEMPLATE(naive_partial_piv_lu, N); \
  BENCHMARK_TEMPLATE(paper_solve_kkt, N);      \
  BENCHMARK_TEMPLATE(range_space_fixed, N);    \
  BENCHMARK_TEMPLATE(range_space_bounded, N);  \
  BENCHMARK_TEMPLATE(range_space_float, N)
GRIP_TABLE2(3);
GRIP_TABLE2(5);
GRIP_TABLE2(10);
GRIP_TABLE2(15);
GRIP_TABLE2(20);
GRIP_TABLE2(32);
GRIP_TABLE2(64);
