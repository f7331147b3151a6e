// Device-side stages of a haptic frame: PhalanxActuators clipping each phalanx against rendering
// the closest net wrench (net_wrench_command.hpp), and ChannelGuard over 14 channels.
//
//   Actuators/clip       PhalanxActuators::render, each phalanx clipped on its own (the default)
//   Actuators/net_wrench the same with net_wrench: the bounded least-squares command
//   Vectors/...          VectorForces::render, scaling each phalanx or net_wrench (net_wrench_vector.hpp)
//   Guard                ChannelGuard<double, 14>::update at 1 kHz, 200 Hz device updates
//   Passivity            PassivityController<double, 14>::update, every channel short of energy
//   GloveSession/...     example 10's glove (one 20 N cable per finger) on example 6's session:
//                        the felt forces of its 6500 frames recorded once, then rendered by
//                        clipping or by net_wrench; counter net_error_ratio over the session
//
// 256 random felt-force sets (about 60 % of the 19 bodies in contact, forces of up to 14 N,
// limits of 0 to 6 N, random actuation directions) in a loop; the time per call. Counter
// `net_error_ratio`: the weighted net-wrench error of clipping over that of net_wrench, summed
// over the sets (what the best command gains); goal for the frame: net_wrench at most 20 % of a
// 1 ms frame.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "../examples/06_haptic_loop/session.hpp"

#include <grip/pipeline/channel_guard.hpp>
#include <grip/pipeline/frame_solver.hpp>
#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/passivity_controller.hpp>

namespace {
using grip::FeltForces;
using V3 = grip::Vector3<double>;

std::vector<FeltForces<double>> felt_sets() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), p(0, 1);
  std::vector<FeltForces<double>> sets(256);
  for (auto& f : sets) {
    for (int b = 0; b < grip::hand_body_count; ++b) {
      const auto i = static_cast<std::size_t>(b);
      f.in_contact[i] = p(rng) < 0.6;
      f.point[i] = 0.08 * V3(u(rng), u(rng), u(rng));
      f.force[i] = f.in_contact[i] ? V3(8 * u(rng), 8 * u(rng), 8 * u(rng)) : V3::Zero();
    }
    for (int k = 0; k < grip::hand_phalanx_count; ++k)
      f.direction[static_cast<std::size_t>(k)] = V3(u(rng), u(rng), u(rng)).normalized();
  }
  return sets;
}

grip::PhalanxActuators<double> device(bool net) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> p(0, 6);
  grip::PhalanxActuators<double> d;
  for (auto& l : d.limit) l = p(rng);
  d.net_wrench = net;
  return d;
}

double weighted(const grip::Wrench<double>& w, double lever) {
  return std::sqrt(w.head<3>().squaredNorm() + w.tail<3>().squaredNorm() / (lever * lever));
}

void Actuators(benchmark::State& state) {
  const bool net = state.range(0) != 0;
  const auto sets = felt_sets();
  const auto dev = device(net);
  const grip::HandPosture<double> posture{};
  const grip::HandJoints<double> velocity = grip::HandJoints<double>::Zero();
  grip::PhalanxActuators<double>::Command out;
  std::size_t k = 0;
  for (auto _ : state) {
    dev.render(sets[k], posture, velocity, out);
    benchmark::DoNotOptimize(out.force.data());
    k = (k + 1) % sets.size();
  }
  // The gain in net-wrench error over clipping, on the same sets.
  double clip = 0, best = 0;
  const auto clipper = device(false), fitter = device(true);
  grip::PhalanxActuators<double>::Command c, b;
  for (const auto& f : sets) {
    clipper.render(f, posture, velocity, c);
    fitter.render(f, posture, velocity, b);
    const double lever = grip::felt_net_wrench(f.force, f.point, f.in_contact).lever;
    clip += weighted(c.unrendered, lever);
    best += weighted(b.unrendered, lever);
  }
  state.counters["net_error_ratio"] = clip / best;
}
BENCHMARK(Actuators)->Arg(0)->Arg(1)->ArgName("net_wrench");

void Vectors(benchmark::State& state) {
  const bool net = state.range(0) != 0;
  const auto sets = felt_sets();
  grip::VectorForces<double> dev;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> p(0, 6);
  for (auto& l : dev.limit) l = p(rng);
  dev.net_wrench = net;
  const grip::HandPosture<double> posture{};
  const grip::HandJoints<double> velocity = grip::HandJoints<double>::Zero();
  grip::VectorForces<double>::Command out;
  std::size_t k = 0;
  for (auto _ : state) {
    dev.render(sets[k], posture, velocity, out);
    benchmark::DoNotOptimize(out.force.data());
    k = (k + 1) % sets.size();
  }
  double scaled = 0, best = 0;
  grip::VectorForces<double>::Command c;
  for (const auto& f : sets) {
    const double lever = grip::felt_net_wrench(f.force, f.point, f.in_contact).lever;
    dev.net_wrench = false;
    dev.render(f, posture, velocity, c);
    scaled += weighted(c.unrendered, lever);
    dev.net_wrench = true;
    dev.render(f, posture, velocity, c);
    best += weighted(c.unrendered, lever);
  }
  state.counters["net_error_ratio"] = scaled / best;
}
BENCHMARK(Vectors)->Arg(0)->Arg(1)->ArgName("net_wrench");

void Guard(benchmark::State& state) {
  grip::ChannelGuardSettings<double> s;
  s.slew_rate = 400;
  s.step = 0.2;
  s.onset_time = 0.02;
  s.stale_after = 0.05;
  grip::ChannelGuard<double, 14> g(s);
  std::array<double, 14> want{};
  want.fill(5.0);
  double t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(g.update(t, want, true));
    t += 1e-3;
  }
}
BENCHMARK(Guard);

void Passivity(benchmark::State& state) {
  grip::PassivityController<double, 14> pc;
  std::array<double, 14> force{}, position{};
  force.fill(2.0);  // along the motion below: every channel gives energy, the damper works
  std::size_t k = 0;
  for (auto _ : state) {
    for (std::size_t c = 0; c < 14; ++c) position[c] = 1e-5 * double(k % 64);
    benchmark::DoNotOptimize(pc.update(1e-3, force, position));
    benchmark::DoNotOptimize(pc.command().data());
    ++k;
  }
}
BENCHMARK(Passivity);

// Example 10's glove: 20 N on each distal phalanx, nothing elsewhere.
grip::PhalanxActuators<double> cable_glove(bool net) {
  grip::PhalanxActuators<double> g;
  g.limit.fill(0.0);
  for (int f = 0; f < 5; ++f)
    g.limit[static_cast<std::size_t>(grip::phalanx_index(static_cast<grip::Finger>(f), grip::Phalanx::Distal))] = 20;
  g.net_wrench = net;
  return g;
}

// The felt forces of example 6's session, frames with contact only (run once).
const std::vector<FeltForces<double>>& session_felt() {
  static const std::vector<FeltForces<double>> frames = [] {
    using namespace haptic_session;
    const Script script;
    grip::HapticSettings<S> st = settings();
    st.bound_by_device = false;
    grip::HapticPipeline<S, grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>> pipeline(st, scene(), object());
    grip::HapticFrame<S> frame;
    std::vector<FeltForces<double>> out;
    for (int i = 0; i < static_cast<int>(duration * rate); ++i) {
      (void)pipeline.step(script.wrist(i / rate), script.angles(i / rate), frame);
      if (frame.contacts > 0) out.push_back(pipeline.felt());
    }
    return out;
  }();
  return frames;
}

void GloveSession(benchmark::State& state) {
  const bool net = state.range(0) != 0;
  const auto& frames = session_felt();
  const auto dev = cable_glove(net);
  const grip::HandPosture<double> posture{};
  const grip::HandJoints<double> velocity = grip::HandJoints<double>::Zero();
  grip::PhalanxActuators<double>::Command out;
  std::size_t k = 0;
  for (auto _ : state) {
    dev.render(frames[k], posture, velocity, out);
    benchmark::DoNotOptimize(out.force.data());
    k = (k + 1) % frames.size();
  }
  double clip = 0, best = 0;
  const auto clipper = cable_glove(false), fitter = cable_glove(true);
  grip::PhalanxActuators<double>::Command c, b;
  for (const auto& f : frames) {
    clipper.render(f, posture, velocity, c);
    fitter.render(f, posture, velocity, b);
    const double lever = grip::felt_net_wrench(f.force, f.point, f.in_contact).lever;
    clip += weighted(c.unrendered, lever);
    best += weighted(b.unrendered, lever);
  }
  state.counters["net_error_ratio"] = clip / best;
  state.counters["frames"] = double(frames.size());
}
BENCHMARK(GloveSession)->Arg(0)->Arg(1)->ArgName("net_wrench");

}  // namespace
