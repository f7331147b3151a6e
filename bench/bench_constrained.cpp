// solve_constrained (exact friction cones) beside solve_range_space (no cones) in one run.
//
// Instances: n hard fingers at random points of a 4 cm sphere (mu = 0.5, squeeze 0.3 N),
// holding a 0.5 kg object: w_ext = gravity (0, 0, -4.905 N) plus a random inertial/collision
// wrench (|F| ~ 1 N, |M| ~ 0.01 N m). Instances are kept only if the unconstrained optimum
// violates at least one cone (active cones) and the constrained problem is feasible.
//
// Benchmarks (per n = 3, 5, 10, 15, 20, 32, 64):
//   Constrained/n      cold solve over a pool of 64 instances (counter: iterations per solve)
//   RangeSpace/n       solve_range_space on the same pool (the baseline)
//   ConstrainedWarm/n  warm start from the multipliers of a slightly perturbed previous frame
//   FastPath/n, RangeSpace/n/false: instances whose unconstrained optimum is strictly inside
//   FastPathRatio/n    both over those instances in one loop: counter fast_over_range
//   Distribution/n     one pass over 100,000 fresh instances, each solve timed with
//                      std::chrono: counters median_us, p99_us, p9999_us, worst_us,
//                      worst_over_median, median_iter, worst_iter, worst_passes,
//                      range_median_us (and their ratio); each instance is solved twice more
//                      and least3_* take the least of its three times (the instance's own
//                      cost: the single-solve worst is set by the machine's interruptions,
//                      tens of microseconds on the 2-core VM); warm_*: the same instances
//                      warm-started from the multipliers of their previous frame (contacts
//                      moved by 1 mm, load changed by 2 %), least of three solves likewise;
//                      warm_not_ok counts warm solves whose status is not Ok (every instance
//                      is feasible: its cold solve says Ok)
//   Loads/n            100,000 fresh grasps the fast path does not answer, loads of 0.5 to
//                      200 N in random directions (many slip), least of three cold solves
//                      each: counters slip_frac (the Infeasible ones), limit_count (must be
//                      0), median_us, p99_us, p9999_us, worst_us and their ratios to the
//                      median, the same of the slipping ones (slip_*), and interior-point
//                      iterations (median and worst of the slipping ones, worst of all);
//                      Loads<n, true>: every normal force bounded by 20 N; Loads<n, false,
//                      true>: loads 1e-6 to 0.1 times the squeezing forces; Loads<n, true,
//                      true>: both (a haptic device's limits under a light load)
//   SlipFrames/n       pairs of slipping frames (n = 3, 5): the second solved cold and from
//                      the first's certificate (see SlipFrames below)
//   Bound/n            the bound of a solve: 64 grasps the fast path does not answer (many
//                      slip): ns_per_iteration (an interior-point iteration, the slope between
//                      max_iterations 2 and 12 with newton_passes 0), ns_per_pass (a Newton
//                      pass, the slope between newton_passes 1 and 8), fixed_ns, and
//                      bound_us = fixed + the default settings' passes and iterations against
//                      least3_worst_us, the slowest grasp at the defaults (least of three)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include <grip/grasp/grasp.hpp>
#include <grip/solve/solve_constrained.hpp>
#include <grip/solve/solve_range_space.hpp>

namespace {

using grip::Contact;
using grip::Wrench;

template <int N>
using G = grip::Grasp<N, grip::HardFinger, double>;

template <int N>
struct Instance {
  G<N> grasp;
  Wrench<double> w_ext;
  Wrench<double> warm;  // multipliers of the previous (perturbed) frame
};

Contact<double> on_sphere(double theta, double phi, double mu, double squeeze) {
  Contact<double> c;
  const grip::Vector3<double> u(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  c.position = 0.04 * u;
  c.normal = -u;
  c.friction = mu;
  c.torsional_friction = 0.005;
  c.squeeze = squeeze;
  return c;
}

/// A random instance; `active` asks for an unconstrained optimum outside some cone (else
/// strictly inside all). Also solves the previous frame (contacts moved by 1 mm, load changed
/// by 2%) for the warm start.
template <int N>
Instance<N> make_instance(std::mt19937& rng, bool active) {
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> n01(0, 1);
  for (;;) {
    Instance<N> in;
    G<N> prev;
    double th[N], ph[N];
    for (int i = 0; i < N; ++i) {
      th[i] = std::acos(1 - 2 * u01(rng));
      ph[i] = 6.283185307179586 * u01(rng);
      (void)in.grasp.set(i, on_sphere(th[i], ph[i], 0.5, active ? 0.3 : 6.0));
      (void)prev.set(i, on_sphere(th[i] + 0.025 * n01(rng), ph[i] + 0.025 * n01(rng), 0.5, active ? 0.3 : 6.0));
    }
    in.w_ext << n01(rng), n01(rng), -4.905 + n01(rng), 0.01 * n01(rng), 0.01 * n01(rng), 0.01 * n01(rng);
    const auto rs = grip::solve_range_space(in.grasp, in.w_ext);
    if (rs.status != grip::Status::Ok) continue;
    bool inside = true;
    for (int i = 0; i < N; ++i)
      inside =
          inside &&
          grip::CoulombCone<double>::from_contact(in.grasp.contact(i)).margin(rs.forces.template segment<3>(3 * i)) > 0;
    if (inside == active) continue;
    const auto sol = grip::solve_constrained(in.grasp, in.w_ext);
    if (sol.status != grip::Status::Ok) continue;
    const auto p = grip::solve_constrained(prev, Wrench<double>(in.w_ext * 1.02));
    if (p.status != grip::Status::Ok) continue;
    in.warm = p.multipliers;
    return in;
  }
}

template <int N>
const std::vector<Instance<N>>& pool(bool active) {
  static std::vector<Instance<N>> a, f;
  std::vector<Instance<N>>& v = active ? a : f;
  if (v.empty()) {
    std::mt19937 rng(active ? 1000 + N : 2000 + N);
    for (int k = 0; k < 64; ++k) v.push_back(make_instance<N>(rng, active));
  }
  return v;
}

/// The q-quantile of v (sorted in a copy); 0 for an empty v.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::size_t(q * double(v.size() - 1))];
}

/// Counters <prefix>median_us, <prefix>p99_us, <prefix>p9999_us and <prefix>worst_us of `us`.
void report_times(benchmark::State& state, const std::string& prefix, const std::vector<double>& us) {
  state.counters[prefix + "median_us"] = quantile(us, 0.5);
  state.counters[prefix + "p99_us"] = quantile(us, 0.99);
  state.counters[prefix + "p9999_us"] = quantile(us, 0.9999);
  state.counters[prefix + "worst_us"] = quantile(us, 1.0);
}

template <int N>
void Constrained(benchmark::State& state) {
  const auto& p = pool<N>(true);
  std::size_t k = 0;
  long iters = 0, solves = 0;
  for (auto _ : state) {
    const auto& in = p[k++ % p.size()];
    const auto s = grip::solve_constrained(in.grasp, in.w_ext);
    benchmark::DoNotOptimize(s.forces.data());
    iters += s.iterations;
    ++solves;
  }
  state.counters["iterations"] = double(iters) / double(solves);
}

template <int N>
void ConstrainedWarm(benchmark::State& state) {
  const auto& p = pool<N>(true);
  const grip::ConstrainedSettings<double> st;
  std::size_t k = 0;
  long iters = 0, solves = 0;
  for (auto _ : state) {
    const auto& in = p[k++ % p.size()];
    const auto s = grip::solve_constrained(in.grasp, in.w_ext, st, in.warm);
    benchmark::DoNotOptimize(s.forces.data());
    iters += s.iterations;
    ++solves;
  }
  state.counters["iterations"] = double(iters) / double(solves);
}

template <int N, bool Active>
void RangeSpace(benchmark::State& state) {
  const auto& p = pool<N>(Active);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& in = p[k++ % p.size()];
    const auto s = grip::solve_range_space(in.grasp, in.w_ext);
    benchmark::DoNotOptimize(s.forces.data());
  }
}

template <int N>
void FastPath(benchmark::State& state) {
  const auto& p = pool<N>(false);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& in = p[k++ % p.size()];
    const auto s = grip::solve_constrained(in.grasp, in.w_ext);
    benchmark::DoNotOptimize(s.forces.data());
  }
}

// Fast path against solve_range_space in one loop: alternating batches over the same pool of
// 64 strictly-inside instances, summed, so that the ratio (counter fast_over_range) is taken
// under the same machine state (the separate FastPath and RangeSpace figures drift apart by
// tens of percent between runs on the 2-core VM).
template <int N>
void FastPathRatio(benchmark::State& state) {
  const auto& p = pool<N>(false);
  using clock = std::chrono::steady_clock;
  double t_fast = 0, t_range = 0;
  for (auto _ : state) {
    const auto t0 = clock::now();
    for (const auto& in : p) benchmark::DoNotOptimize(grip::solve_constrained(in.grasp, in.w_ext).forces.data());
    const auto t1 = clock::now();
    for (const auto& in : p) benchmark::DoNotOptimize(grip::solve_range_space(in.grasp, in.w_ext).forces.data());
    const auto t2 = clock::now();
    t_fast += std::chrono::duration<double>(t1 - t0).count();
    t_range += std::chrono::duration<double>(t2 - t1).count();
  }
  const double per = 1e9 / (double(state.iterations()) * double(p.size()));
  state.counters["fast_over_range"] = t_fast / t_range;
  state.counters["fast_ns"] = per * t_fast;
  state.counters["range_ns"] = per * t_range;
}

template <int N>
void Distribution(benchmark::State& state) {
  const int count = 100000;
  std::vector<double> t, tm, tr, tw;
  std::vector<int> it, passes, warm_passes;
  int warm_not_ok = 0;
  const grip::ConstrainedSettings<double> settings;
  using clock = std::chrono::steady_clock;
  const auto us = [](clock::time_point a, clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  for (auto _ : state) {
    t.clear();
    tm.clear();
    tr.clear();
    tw.clear();
    it.clear();
    passes.clear();
    warm_passes.clear();
    warm_not_ok = 0;
    std::mt19937 rng(3000 + N);
    for (int k = 0; k < count; ++k) {
      const Instance<N> in = make_instance<N>(rng, true);
      const auto t0 = clock::now();
      const auto s = grip::solve_constrained(in.grasp, in.w_ext);
      const auto t1 = clock::now();
      benchmark::DoNotOptimize(s.forces.data());
      const auto r = grip::solve_range_space(in.grasp, in.w_ext);
      const auto t2 = clock::now();
      benchmark::DoNotOptimize(r.forces.data());
      // The same instance twice more: the least of the three is its own cost, without the
      // interruptions of the machine (a preempted solve takes tens of microseconds here).
      double least = us(t0, t1);
      for (int rep = 0; rep < 2; ++rep) {
        const auto a = clock::now();
        benchmark::DoNotOptimize(grip::solve_constrained(in.grasp, in.w_ext).forces.data());
        least = std::min(least, us(a, clock::now()));
      }
      // Warm: from the previous frame's multipliers, as a real-time loop starts each frame.
      double warm_least = std::numeric_limits<double>::infinity();
      for (int rep = 0; rep < 3; ++rep) {
        const auto a = clock::now();
        const auto w = grip::solve_constrained(in.grasp, in.w_ext, settings, in.warm);
        warm_least = std::min(warm_least, us(a, clock::now()));
        benchmark::DoNotOptimize(w.forces.data());
        if (rep == 0) {
          warm_passes.push_back(w.passes);
          warm_not_ok += w.status != grip::Status::Ok;
        }
      }
      tw.push_back(warm_least);
      t.push_back(us(t0, t1));
      tm.push_back(least);
      tr.push_back(us(t1, t2));
      it.push_back(s.iterations);
      passes.push_back(s.passes);
    }
  }
  std::vector<double> itd(it.begin(), it.end());
  const double med = quantile(t, 0.5), worst = quantile(t, 1.0);
  state.counters["median_us"] = med;
  state.counters["p99_us"] = quantile(t, 0.99);
  state.counters["p999_us"] = quantile(t, 0.999);
  state.counters["p9999_us"] = quantile(t, 0.9999);
  state.counters["worst_us"] = worst;
  state.counters["worst_over_median"] = worst / med;
  // Per instance the least of three solves: the worst instance against the median one.
  report_times(state, "least3_", tm);
  state.counters["least3_p9999_over_median"] = quantile(tm, 0.9999) / quantile(tm, 0.5);
  state.counters["least3_worst_over_median"] = quantile(tm, 1.0) / quantile(tm, 0.5);
  state.counters["median_iter"] = quantile(itd, 0.5);
  state.counters["worst_iter"] = quantile(itd, 1.0);
  state.counters["worst_passes"] = *std::max_element(passes.begin(), passes.end());
  report_times(state, "warm_least3_", tw);
  state.counters["warm_least3_p9999_over_median"] = quantile(tw, 0.9999) / quantile(tw, 0.5);
  state.counters["warm_worst_passes"] = *std::max_element(warm_passes.begin(), warm_passes.end());
  state.counters["warm_not_ok"] = warm_not_ok;
  state.counters["range_median_us"] = quantile(tr, 0.5);
  state.counters["median_over_range"] = med / quantile(tr, 0.5);
}

// A grasp the fast path does not answer, with a load of 0.5 to 200 N (log-uniform) in a
// random direction and moments of a few centimetres times it: many slip. `light`: loads of
// 0.3 uN to 30 mN instead, 1e-6 to 0.1 times the squeezing forces (0.3 N), as a haptic session's
// wrench left for the fingers decays while they hold on.
template <int N>
Instance<N> make_hard_instance(std::mt19937& rng, bool light = false) {
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> n01(0, 1);
  for (;;) {
    Instance<N> in;
    for (int i = 0; i < N; ++i)
      (void)in.grasp.set(
          i, on_sphere(std::acos(1 - 2 * u01(rng)), 6.283185307179586 * u01(rng), 0.3 + 0.7 * u01(rng), 0.3));
    const double size = light ? 0.3 * std::pow(10.0, -6.0 + 5.0 * u01(rng)) : 0.5 * std::pow(400.0, u01(rng));
    for (int k = 0; k < 6; ++k) in.w_ext(k) = (k < 3 ? 1.0 : 0.03) * n01(rng);
    in.w_ext.template head<3>() *= size / in.w_ext.template head<3>().norm();
    in.w_ext.template tail<3>() *= size;
    if (!grip::solve_constrained(in.grasp, in.w_ext).fast_path) return in;
  }
}

// 100 000 fresh grasps of make_hard_instance per n (about half slip at n = 3, fewer as n
// grows), each solved three times cold, timed by the least of the three: the worst case that a
// loop meets when its grasps may slip. Every solve must end Ok or Infeasible (limit_count 0).
// n = 1 and 2: grasp matrices of rank 3 and 5, whose loads almost all have a part outside the
// range. Bounded: every contact's normal force limited to 20 N (a device's channel). Light: the
// light loads of make_hard_instance.
template <int N, bool Bounded = false, bool Light = false>
void Loads(benchmark::State& state) {
  const int count = 100000;
  using clock = std::chrono::steady_clock;
  const auto us = [](clock::time_point a, clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  std::vector<double> all, slip, hold_iter, slip_iter;
  int limits = 0, worst_iterations = 0;
  for (auto _ : state) {
    all.clear();
    slip.clear();
    hold_iter.clear();
    slip_iter.clear();
    limits = 0;
    worst_iterations = 0;
    std::mt19937 rng(5000 + N);
    for (int k = 0; k < count; ++k) {
      Instance<N> in = make_hard_instance<N>(rng, Light);
      for (int i = 0; Bounded && i < N; ++i) {
        Contact<double> c = in.grasp.contact(i);
        c.max_normal_force = 20.0;
        (void)in.grasp.set(i, c);
      }
      double least = std::numeric_limits<double>::infinity();
      grip::Status status = grip::Status::Ok;
      int iterations = 0;
      for (int rep = 0; rep < 3; ++rep) {
        const auto a = clock::now();
        const auto s = grip::solve_constrained(in.grasp, in.w_ext);
        least = std::min(least, us(a, clock::now()));
        benchmark::DoNotOptimize(s.forces.data());
        status = s.status;
        iterations = s.iterations;
      }
      all.push_back(least);
      limits += status == grip::Status::IterationLimit ? 1 : 0;
      worst_iterations = std::max(worst_iterations, iterations);
      if (status == grip::Status::Infeasible) {
        slip.push_back(least);
        slip_iter.push_back(iterations);
      } else {
        hold_iter.push_back(iterations);
      }
    }
  }
  state.counters["slip_frac"] = double(slip.size()) / double(count);
  state.counters["limit_count"] = limits;
  report_times(state, "", all);
  state.counters["p9999_over_median"] = quantile(all, 0.9999) / quantile(all, 0.5);
  state.counters["worst_over_median"] = quantile(all, 1.0) / quantile(all, 0.5);
  report_times(state, "slip_", slip);
  state.counters["worst_iterations"] = worst_iterations;
  state.counters["slip_median_iterations"] = quantile(slip_iter, 0.5);
  state.counters["slip_worst_iterations"] = quantile(slip_iter, 1.0);
  state.counters["hold_worst_iterations"] = quantile(hold_iter, 1.0);
}

// The bound of a solve (docs/solve.md): 64 grasps the fast path does not answer, loads of 0.5 to
// 200 N (many slip). An interior-point iteration's cost is the slope between max_iterations 2
// and 12 with Newton off; a Newton pass's, the slope between newton_passes 1 and 8 with one
// interior-point iteration allowed. fixed_ns: a solve's cost besides them (the fast path and the
// set-up). bound_us: fixed plus the default settings' 2 newton_passes passes and max_iterations
// iterations, against least3_worst_us, the slowest grasp at the defaults (least of three).
template <int N>
void Bound(benchmark::State& state) {
  static std::vector<Instance<N>> p;
  if (p.empty()) {
    std::mt19937 rng(4000 + N);
    for (int k = 0; k < 64; ++k) p.push_back(make_hard_instance<N>(rng));
  }
  using clock = std::chrono::steady_clock;
  grip::ConstrainedSettings<double> st[4];
  st[0].newton_passes = st[1].newton_passes = 0;
  st[0].max_iterations = 2;
  st[1].max_iterations = 12;
  st[2].newton_passes = 1;
  st[3].newton_passes = 8;
  st[2].max_iterations = st[3].max_iterations = 1;
  double t[4] = {0, 0, 0, 0};
  long iterations[4] = {0, 0, 0, 0}, passes[4] = {0, 0, 0, 0};
  for (auto _ : state) {
    for (int v = 0; v < 4; ++v) {
      const auto t0 = clock::now();
      for (const auto& in : p) {
        const auto s = grip::solve_constrained(in.grasp, in.w_ext, st[v]);
        benchmark::DoNotOptimize(s.forces.data());
        iterations[v] += s.iterations;
        passes[v] += s.passes;
      }
      t[v] += std::chrono::duration<double, std::nano>(clock::now() - t0).count();
    }
  }
  const double solves = double(state.iterations()) * double(p.size());
  const double per_iteration = (t[1] - t[0]) / double(iterations[1] - iterations[0]);
  // Where Newton converges within 8 passes on every grasp (n >= 15), the slope is not a pass's
  // cost (8 passes then skip the iteration that 1 pass leaves): no pass cost is taken off.
  const double slope = (t[3] - t[2]) / double(passes[3] - passes[2]);
  const double per_pass = slope > 0 ? slope : 0.0;
  const double fixed = (t[2] - per_pass * double(passes[2]) - per_iteration * double(iterations[2])) / solves;
  const grip::ConstrainedSettings<double> defaults;
  double worst = 0;
  int worst_iterations = 0;
  for (const auto& in : p) {
    double least = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto a = clock::now();
      const auto s = grip::solve_constrained(in.grasp, in.w_ext);
      least = std::min(least, std::chrono::duration<double, std::micro>(clock::now() - a).count());
      benchmark::DoNotOptimize(s.forces.data());
      worst_iterations = std::max(worst_iterations, s.iterations);
    }
    worst = std::max(worst, least);
  }
  state.counters["ns_per_iteration"] = per_iteration;
  state.counters["ns_per_iteration_per_contact"] = per_iteration / N;
  state.counters["ns_per_pass"] = per_pass;
  state.counters["fixed_ns"] = fixed;
  state.counters["bound_us"] =
      (fixed + 2 * defaults.newton_passes * per_pass + defaults.max_iterations * per_iteration) * 1e-3;
  state.counters["least3_worst_us"] = worst;
  state.counters["worst_iterations"] = worst_iterations;
}

// Pairs of slipping frames (SlipFrames/n): the grasps of Loads/n whose previous frame (contacts
// moved by 1 mm, load changed by 2 %) also slips, 20,000 draws. Each second frame solved cold
// and from the previous frame's certificate (ConstrainedWarmStart), least of three each.
// FromHold: the previous frame holds instead, and the second starts from its multipliers.
// Counters: pairs, reuse_frac (the warm solve made fewer passes than the cold one: the old
// certificate held, or Newton's multipliers from the warm start, reversed, proved the slip),
// cold_* and warm_* medians and p99 (us), and warm_over_cold (the medians' ratio).
template <int N, bool FromHold = false>
void SlipFrames(benchmark::State& state) {
  using clock = std::chrono::steady_clock;
  const auto least3 = [](const auto& solve) {
    double least = std::numeric_limits<double>::infinity();
    for (int rep = 0; rep < 3; ++rep) {
      const auto a = clock::now();
      const auto s = solve();
      least = std::min(least, std::chrono::duration<double, std::micro>(clock::now() - a).count());
      benchmark::DoNotOptimize(s.forces.data());
    }
    return least;
  };
  std::vector<double> cold, warm;
  int reused = 0;
  for (auto _ : state) {
    cold.clear();
    warm.clear();
    reused = 0;
    std::mt19937 rng(7000 + N);
    std::normal_distribution<double> n01(0, 1);
    const grip::ConstrainedSettings<double> st;
    for (int k = 0; k < 20000; ++k) {
      const Instance<N> in = make_hard_instance<N>(rng);
      G<N> before;
      for (int i = 0; i < N; ++i) {
        Contact<double> c = in.grasp.contact(i);
        const grip::Vector3<double> turn = 0.025 * grip::Vector3<double>(n01(rng), n01(rng), n01(rng));
        const Eigen::AngleAxisd r(turn.norm(), turn.normalized());
        c.position = r * c.position;
        c.normal = r * c.normal;
        (void)before.set(i, c);
      }
      const auto previous = grip::solve_constrained(before, Wrench<double>(in.w_ext * 1.02));
      if (previous.status != (FromHold ? grip::Status::Ok : grip::Status::Infeasible)) continue;
      const auto now = grip::solve_constrained(in.grasp, in.w_ext);
      if (now.status != grip::Status::Infeasible) continue;
      grip::ConstrainedWarmStart<double> start;
      if (FromHold) {
        start.multipliers = previous.multipliers;
        start.has_multipliers = grip::detail::all_in_range(previous.multipliers);
      } else {
        start.certificate = previous.certificate;
        start.has_certificate = true;
      }
      reused += grip::solve_constrained(in.grasp, in.w_ext, st, start).passes < now.passes ? 1 : 0;
      cold.push_back(least3([&] { return grip::solve_constrained(in.grasp, in.w_ext, st); }));
      warm.push_back(least3([&] { return grip::solve_constrained(in.grasp, in.w_ext, st, start); }));
    }
  }
  state.counters["pairs"] = static_cast<double>(cold.size());
  state.counters["reuse_frac"] = cold.empty() ? 0.0 : double(reused) / double(cold.size());
  state.counters["cold_median_us"] = quantile(cold, 0.5);
  state.counters["cold_p99_us"] = quantile(cold, 0.99);
  state.counters["warm_median_us"] = quantile(warm, 0.5);
  state.counters["warm_p99_us"] = quantile(warm, 0.99);
  state.counters["warm_over_cold"] = quantile(warm, 0.5) / quantile(cold, 0.5);
}
BENCHMARK_TEMPLATE(SlipFrames, 3)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(SlipFrames, 5)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(SlipFrames, 3, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(SlipFrames, 5, true)->Iterations(1)->Unit(benchmark::kMillisecond);

#define GRIP_BENCH_N(N)                                                              \
  BENCHMARK_TEMPLATE(Constrained, N);                                                \
  BENCHMARK_TEMPLATE(RangeSpace, N, true);                                           \
  BENCHMARK_TEMPLATE(ConstrainedWarm, N);                                            \
  BENCHMARK_TEMPLATE(FastPath, N);                                                   \
  BENCHMARK_TEMPLATE(RangeSpace, N, false);                                          \
  BENCHMARK_TEMPLATE(FastPathRatio, N);                                              \
  BENCHMARK_TEMPLATE(Distribution, N)->Iterations(1)->Unit(benchmark::kMillisecond); \
  BENCHMARK_TEMPLATE(Loads, N)->Iterations(1)->Unit(benchmark::kMillisecond);        \
  BENCHMARK_TEMPLATE(Bound, N)->Unit(benchmark::kMillisecond)

BENCHMARK_TEMPLATE(Loads, 1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 1, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 2)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 2, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 3, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 3, false, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 5, false, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 3, true, true)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(Loads, 5, true, true)->Iterations(1)->Unit(benchmark::kMillisecond);
GRIP_BENCH_N(3);
GRIP_BENCH_N(5);
GRIP_BENCH_N(10);
GRIP_BENCH_N(15);
GRIP_BENCH_N(20);
GRIP_BENCH_N(32);
GRIP_BENCH_N(64);

}  // namespace
