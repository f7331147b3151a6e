// Batch evaluation on several threads gives, grasp by grasp, exactly the serial results.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <vector>

#include <grip/analysis/batch.hpp>

#include "support/fixtures.hpp"
#include "support/test_scale.hpp"

using namespace grip;

TEST_CASE("evaluate_batch on 2 and 3 threads equals the serial evaluate_grasp, bit for bit") {
  using G = Grasp<Dynamic, HardFinger, double, 6>;
  std::mt19937 rng(41);
  std::vector<G> grasps;
  const int count = grip_test::scaled(24, 6);  // at least two grasps per thread and a remainder
  for (int i = 0; i < count; ++i) grasps.push_back(grip_test::random_grasp<G>(rng, 3 + i % 4));
  BatchSettings<double> s;
  s.lever_length = 0.05;
  s.epsilon_linf = true;
  auto ws = std::make_unique<EpsilonWorkspace<double>>();
  std::vector<GraspMetrics<double>> serial;
  for (const auto& g : grasps) serial.push_back(evaluate_grasp<4>(g, s, *ws));
  for (int threads : {2, 3}) {
    s.threads = threads;
    std::vector<GraspMetrics<double>> par(grasps.size());
    REQUIRE(evaluate_batch<4>(grasps.data(), static_cast<int>(grasps.size()), par.data(), s) == Status::Ok);
    for (std::size_t i = 0; i < grasps.size(); ++i) {
      CHECK(par[i].status == serial[i].status);
      CHECK(par[i].closure == serial[i].closure);
      CHECK(std::memcmp(&par[i].closure_margin, &serial[i].closure_margin, sizeof(double)) == 0);
      CHECK(std::memcmp(par[i].quality.singular_values.data(), serial[i].quality.singular_values.data(),
                        6 * sizeof(double)) == 0);
      CHECK(std::memcmp(&par[i].epsilon_l1.epsilon, &serial[i].epsilon_l1.epsilon, sizeof(double)) == 0);
      CHECK(std::memcmp(&par[i].epsilon_linf.epsilon, &serial[i].epsilon_linf.epsilon, sizeof(double)) == 0);
    }
  }
  // Bad input: null storage.
  CHECK(evaluate_batch<4>(grasps.data(), 3, static_cast<GraspMetrics<double>*>(nullptr), s) == Status::InvalidInput);
  CHECK(evaluate_batch<4>(grasps.data(), 0, static_cast<GraspMetrics<double>*>(nullptr), s) == Status::Ok);
}

template struct grip::GraspMetrics<float>;
template struct grip::BatchSettings<double>;
