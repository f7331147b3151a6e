#pragma once
/// \file
/// Quality metrics for many candidate grasps at once, on all cores (std::thread).
///
/// This is a set-up / offline tool for grasp-planning experiments, NOT a real-time one:
/// std::thread allocates internally (its state and stack) and may fail to start, which
/// terminates the program in builds without exceptions. The library code itself allocates
/// nothing else: the caller provides the grasps and the result storage, and the workers'
/// EpsilonWorkspaces (10.6 MB each for double) come from one heap allocation made on the
/// calling thread before any worker starts (evaluate_batch returns IterationLimit, nothing
/// written, when it fails), never from a thread's stack (secondary threads get 512 KiB to 8 MB
/// of stack, depending on the system).
///
/// Determinism: every grasp is evaluated by the same function, evaluate_grasp(), on one
/// thread, with no shared accumulation, so per-grasp results are bit-identical to a serial
/// call whatever the number of threads.

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <new>
#include <thread>

#include "grip/analysis/epsilon.hpp"
#include "grip/analysis/force_closure.hpp"
#include "grip/analysis/quality.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"

namespace grip {

/// What evaluate_grasp() computes and how.
template <class Scalar>
struct BatchSettings {
  Scalar lever_length{Scalar(1)};         ///< L (m) for the singular values and epsilon.
  bool force_closure{true};               ///< Run the exact-cone force-closure test.
  bool epsilon_l1{true};                  ///< Compute the L1 Ferrari-Canny epsilon.
  bool epsilon_linf{false};               ///< Compute the L-infinity Ferrari-Canny epsilon.
  ConicAnalysisSettings<Scalar> conic{};  ///< Settings of the force-closure solver.
  /// Worker threads for evaluate_batch: 0 = std::thread::hardware_concurrency() (at least 1),
  /// at most 64 (the calling thread is one of them).
  int threads{0};
};

/// The metrics of one grasp. `status` is Ok when every requested metric was Ok, else the
/// first non-Ok status met (quality, force closure, epsilon L1, epsilon L-inf order).
template <class Scalar>
struct GraspMetrics {
  GraspQuality<Scalar> quality{};       ///< Singular values of G, volume, isotropy.
  bool closure{false};                  ///< Exact-cone force closure (if requested).
  Scalar closure_margin{0};             ///< Its margin (force_closure.hpp).
  Epsilon<Scalar> epsilon_l1{};         ///< Ferrari-Canny L1 (if requested).
  Epsilon<Scalar> epsilon_linf{};       ///< Ferrari-Canny L-infinity (if requested).
  Status status{Status::InvalidInput};  ///< Ok, or the first non-Ok status met (see above).
};

/// All requested metrics of one grasp, K-sided linearised cones for epsilon. No heap.
template <int K, class GraspT, class Workspace>
GraspMetrics<typename GraspT::ScalarType> evaluate_grasp(const GraspT& grasp,
                                                         const BatchSettings<typename GraspT::ScalarType>& settings,
                                                         Workspace& ws) {
  GraspMetrics<typename GraspT::ScalarType> m;
  m.quality = grasp_quality(grasp, settings.lever_length);
  Status st = m.quality.status;
  auto note = [&st](Status s) {
    if (st == Status::Ok && s != Status::Ok) st = s;
  };
  if (settings.force_closure) {
    const auto fc = force_closure(grasp, settings.conic);
    m.closure = fc.closure;
    m.closure_margin = fc.margin;
    note(fc.status);
  }
  if (settings.epsilon_l1) {
    m.epsilon_l1 = ferrari_canny_epsilon<K>(grasp, EpsilonNorm::L1, settings.lever_length, ws);
    note(m.epsilon_l1.status);
  }
  if (settings.epsilon_linf) {
    m.epsilon_linf = ferrari_canny_epsilon<K>(grasp, EpsilonNorm::LInfinity, settings.lever_length, ws);
    note(m.epsilon_linf.status);
  }
  m.status = st;
  return m;
}

/// Evaluates grasps[0..count) into results[0..count) (caller-provided storage) on
/// settings.threads threads, contiguous chunks. Returns InvalidInput (nothing written) for
/// null pointers or count < 0, IterationLimit (nothing written) when the workers' workspaces
/// cannot be allocated, Ok otherwise (per-grasp statuses are in the results).
template <int K, class GraspT>
Status evaluate_batch(const GraspT* grasps, int count, GraspMetrics<typename GraspT::ScalarType>* results,
                      const BatchSettings<typename GraspT::ScalarType>& settings) {
  using S = typename GraspT::ScalarType;
  if (count < 0 || (count > 0 && (grasps == nullptr || results == nullptr))) return Status::InvalidInput;
  if (count == 0) return Status::Ok;
  int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::max(1, std::min({threads, count, 64}));
  const std::unique_ptr<EpsilonWorkspace<S>[]> workspaces(new (std::nothrow) EpsilonWorkspace<S>[detail::idx(threads)]);
  if (workspaces == nullptr) return Status::IterationLimit;
  auto work = [grasps, results, &settings](int begin, int end, EpsilonWorkspace<S>& ws) {
    for (int i = begin; i < end; ++i) results[i] = evaluate_grasp<K>(grasps[i], settings, ws);
  };
  auto chunk_begin = [count, threads](int t) { return static_cast<int>(static_cast<long long>(count) * t / threads); };
  std::array<std::thread, 64> pool;
  for (int t = 1; t < threads; ++t)
    pool[detail::idx(t)] = std::thread(work, chunk_begin(t), chunk_begin(t + 1), std::ref(workspaces[detail::idx(t)]));
  work(chunk_begin(0), chunk_begin(1), workspaces[0]);
  for (int t = 1; t < threads; ++t) pool[detail::idx(t)].join();
  return Status::Ok;
}

}  // namespace grip
