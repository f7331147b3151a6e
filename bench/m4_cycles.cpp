// The driver of bench/m4_cycles.py: solve_constrained on five float hard fingers, compiled for
// a Cortex-M4F exactly as cmake/check_embedded.sh compiles examples/07_embedded, and run under
// qemu-arm, whose instruction trace m4_cycles.py turns into Cortex-M4F cycles. Not a Google
// Benchmark: nothing here is timed on the host.
//
// Each solve is bracketed by m4_begin() and m4_end() (kept out of line, so that the trace shows
// them); after m4_end() one line reports it: "solve <instance> <newton_passes> <max_iterations>
// <passes> <iterations> <status> <fast_path> <refined>". Instances: grasps of five contacts on a
// sphere of 4 cm with loads of 0.5 to 200 N in random directions (most hold), one in four of them
// drawn until it slips (Infeasible), and one in four whose unconstrained optimum is inside every
// cone (the fast path). Each is solved cold (no warm start) with the default settings, then,
// unless the fast path answers it, with the settings of m4_cycles.py's cost model:
// newton_passes 1 and 8 at max_iterations 1 (the slope is a Newton pass), max_iterations 2 and
// 12 at newton_passes 0 (the slope is an interior-point iteration).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <grip/grasp/grasp.hpp>
#include <grip/solve/solve_constrained.hpp>

extern "C" __attribute__((noinline)) void m4_begin() { __asm__ volatile(""); }
extern "C" __attribute__((noinline)) void m4_end() { __asm__ volatile(""); }

namespace {

using G5 = grip::Grasp<5, grip::HardFinger, float>;

struct Instance {
  G5 grasp;
  grip::Wrench<float> w_ext;
};

grip::Contact<float> on_sphere(float theta, float phi, float mu, float squeeze) {
  grip::Contact<float> c;
  const grip::Vector3<float> u(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  c.position = 0.04f * u;
  c.normal = -u;
  c.friction = mu;
  c.squeeze = squeeze;
  return c;
}

enum class Kind { fast_path, random_load, slipping };

/// A grasp the fast path answers, one it does not with a load of 0.5 to 200 N, or such a grasp
/// that slips.
Instance make_instance(std::mt19937& rng, Kind kind) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> n01(0.0f, 1.0f);
  const bool inside = kind == Kind::fast_path;
  for (;;) {
    Instance in;
    for (int i = 0; i < 5; ++i)
      (void)in.grasp.set(i, on_sphere(std::acos(1.0f - 2.0f * u01(rng)), 6.2831853f * u01(rng), 0.3f + 0.7f * u01(rng),
                                      inside ? 6.0f : 0.3f));
    const float size = inside ? 5.0f : 0.5f * std::pow(400.0f, u01(rng));
    for (int k = 0; k < 6; ++k) in.w_ext(k) = (k < 3 ? 1.0f : 0.03f) * n01(rng);
    in.w_ext.head<3>() *= size / in.w_ext.head<3>().norm();
    in.w_ext.tail<3>() *= size;
    // The fast path alone (max_iterations 1, no Newton pass) tells the first two kinds cheaply
    // under qemu; a grasp that Newton's method solves in 8 passes holds.
    grip::ConstrainedSettings<float> probe;
    probe.newton_passes = kind == Kind::slipping ? 8 : 0;
    probe.max_iterations = 1;
    const grip::ConstrainedSolution<G5> s = grip::solve_constrained(in.grasp, in.w_ext, probe);
    if (s.fast_path != inside) continue;
    if (kind != Kind::slipping) return in;
    if (!s.refined && grip::solve_constrained(in.grasp, in.w_ext).status == grip::Status::Infeasible) return in;
  }
}

__attribute__((noinline)) grip::ConstrainedSolution<G5> solve(const Instance& in,
                                                              const grip::ConstrainedSettings<float>& st) {
  m4_begin();
  const grip::ConstrainedSolution<G5> s = grip::solve_constrained(in.grasp, in.w_ext, st);
  m4_end();
  return s;
}

void run(const Instance& in, int k, int newton_passes, int max_iterations) {
  grip::ConstrainedSettings<float> st;
  st.newton_passes = newton_passes;
  st.max_iterations = max_iterations;
  const grip::ConstrainedSolution<G5> s = solve(in, st);
  std::printf("solve %d %d %d %d %d %d %d %d\n", k, newton_passes, max_iterations, s.passes, s.iterations,
              static_cast<int>(s.status), s.fast_path ? 1 : 0, s.refined ? 1 : 0);
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 24;
  std::mt19937 rng(2026);
  const grip::ConstrainedSettings<float> defaults;
  for (int k = 0; k < count; ++k) {
    const Kind kind = k % 4 == 0 ? Kind::fast_path : k % 4 == 1 ? Kind::slipping : Kind::random_load;
    const Instance in = make_instance(rng, kind);
    run(in, k, defaults.newton_passes, defaults.max_iterations);
    if (kind == Kind::fast_path) continue;  // the fast path: the same work whatever the settings
    run(in, k, 1, 1);
    run(in, k, 8, 1);
    run(in, k, 0, 2);
    run(in, k, 0, 12);
  }
  return 0;
}
