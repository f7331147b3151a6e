// The driver of bench/m4_cycles.py: solve_constrained on five float hard fingers, compiled for
// a Cortex-M4F exactly as cmake/check_embedded.sh compiles examples/07_embedded, and run under
// qemu-arm, whose instruction trace m4_cycles.py turns into Cortex-M4F cycles. Not a Google
// Benchmark: nothing here is timed on the host.
//
// Each solve is bracketed by m4_begin() and m4_end() (kept out of line, so that the trace shows
// them); after m4_end() one line reports it: "solve <instance> <deadline> <passes> <status>
// <fast_path>". Instances: grasps of five contacts on a sphere of 4 cm with loads of 0.5 to
// 200 N in random directions (many slip, as in bench_constrained's Deadline), and grasps whose
// unconstrained optimum is inside every cone (the fast path).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
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

/// A grasp the fast path answers (`inside`) or one it does not, with a load of 0.5 to 200 N.
Instance make_instance(std::mt19937& rng, bool inside) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> n01(0.0f, 1.0f);
  for (;;) {
    Instance in;
    for (int i = 0; i < 5; ++i)
      (void)in.grasp.set(i, on_sphere(std::acos(1.0f - 2.0f * u01(rng)), 6.2831853f * u01(rng),
                                      0.3f + 0.7f * u01(rng), inside ? 6.0f : 0.3f));
    const float size = inside ? 5.0f : 0.5f * std::pow(400.0f, u01(rng));
    for (int k = 0; k < 6; ++k) in.w_ext(k) = (k < 3 ? 1.0f : 0.03f) * n01(rng);
    in.w_ext.head<3>() *= size / in.w_ext.head<3>().norm();
    in.w_ext.tail<3>() *= size;
    if (grip::solve_constrained(in.grasp, in.w_ext).fast_path == inside) return in;
  }
}

__attribute__((noinline)) grip::ConstrainedSolution<G5> solve(const Instance& in,
                                                              const grip::ConstrainedSettings<float>& st) {
  m4_begin();
  const grip::ConstrainedSolution<G5> s = grip::solve_constrained(in.grasp, in.w_ext, st);
  m4_end();
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 24;
  std::mt19937 rng(2026);
  // No deadline, then 1, 4 and 32 passes (bench_constrained's Deadline: the slope between 1
  // and 4, which every solve reaches, is the cost of a pass; 4 to 32 over the solves that
  // need 32, the costliest passes).
  const int deadlines[4] = {std::numeric_limits<int>::max(), 1, 4, 32};
  for (int k = 0; k < count; ++k) {
    const Instance in = make_instance(rng, k % 4 == 0);
    for (int d : deadlines) {
      grip::ConstrainedSettings<float> st;
      st.max_passes = d;
      const grip::ConstrainedSolution<G5> s = solve(in, st);
      std::printf("solve %d %d %d %d %d\n", k, d == std::numeric_limits<int>::max() ? 0 : d, s.passes,
                  static_cast<int>(s.status), s.fast_path ? 1 : 0);
    }
  }
  return 0;
}
