// The whole haptic frame (collision, external wrench, solve, monitor, feedback) over the
// scripted session of examples/06_haptic_loop, frame by frame: median, p99 and worst frame.
// Target: >= 20 kHz on one core, i.e. a median frame <= 50 us. Baseline in the same run: the
// same frames solved by the paper's Gaussian elimination on H (KktFrameSolver).
// The whole hand (BM_WholeHandFrame_*): a power grasp of the cylinder in the palm, 19
// contacts with the palm's, each frame from a 22-sensor glove's readings through the 20-joint
// kinematics, collision with the palm, solve, monitor and a device policy (joint torques: the
// Jacobians); baseline in the same run, the paper's hand (14 angles, no palm, one actuator
// per phalanx) closed on the same object.
// By what the grasp does (BM_FrameTimeHistogram: holding, shaking, slipping frames, with the
// device's limits in the problem and clipped after it), and the solver alone on the session's
// recorded solves (BM_SolveReplay: the same problems for every version of the solver).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <grip/geometry/shape.hpp>
#include <grip/pipeline/octree_scene.hpp>

#include "../examples/06_haptic_loop/session.hpp"

#include <grip/hand/glove.hpp>
#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/frame_solver.hpp>

namespace {

using namespace haptic_session;

struct Inputs {
  std::vector<grip::WristState<S>> wrist;
  std::vector<grip::JointAngles<S>> angles;
  Inputs() {
    const Script script;
    const int frames = static_cast<int>(duration * rate);
    for (int i = 0; i < frames; ++i) {
      wrist.push_back(script.wrist(i / rate));
      angles.push_back(script.angles(i / rate));
    }
  }
};
const Inputs& inputs() {
  static const Inputs in;
  return in;
}

constexpr int octree_capacity = 16384;
const grip::SphericalOctree<S, octree_capacity>& cylinder_octree() {
  static grip::SphericalOctree<S, octree_capacity> octree;
  static bool built = false;
  if (!built) {
    octree.build(grip::Shape<S>(grip::make_cylinder<S>(radius, half_length)), 3);
    built = true;
  }
  return octree;
}

using CylinderShape = grip::Shape<S, 1>;
const CylinderShape& cylinder_shape() {
  static const CylinderShape shape(grip::make_cylinder<S>(radius, half_length));
  return shape;
}

grip::OctreeScene<S, octree_capacity, CylinderShape> octree_scene() {
  grip::OctreeScene<S, octree_capacity, CylinderShape> sc;
  sc.octree = &cylinder_octree();
  sc.field = &cylinder_shape();
  sc.obstacles = scene().obstacles;
  grip::add_rim_points(sc.surface, radius, half_length, 8);
  return sc;
}

// The session's settings with the device's limits inside the problem (bound_by_device, the
// default) or clipped after the solve (false).
grip::HapticSettings<S> session_settings(bool bound_by_device = true) {
  grip::HapticSettings<S> st = settings();
  st.bound_by_device = bound_by_device;
  return st;
}

template <class SceneT, class Solver>
void run_session(benchmark::State& state, const SceneT& sc, bool bound_by_device = true) {
  using Pipeline = grip::HapticPipeline<S, SceneT, Solver>;
  const Inputs& in = inputs();
  const int frames = static_cast<int>(in.wrist.size());
  auto pipeline = std::make_unique<Pipeline>(session_settings(bound_by_device), sc, object());
  grip::HapticFrame<S> frame;
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  int i = 0, held = 0;
  long iterations = 0;
  for (auto _ : state) {
    if (i == frames) {
      state.PauseTiming();
      pipeline = std::make_unique<Pipeline>(session_settings(bound_by_device), sc, object());
      i = 0;
      state.ResumeTiming();
    }
    const auto t0 = std::chrono::steady_clock::now();
    pipeline->step(in.wrist[static_cast<std::size_t>(i)], in.angles[static_cast<std::size_t>(i)], frame);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(frame);
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    held += frame.held ? 1 : 0;
    iterations += frame.iterations;
    ++i;
  }
  std::sort(us.begin(), us.end());
  const auto at = [&](double q) { return us[static_cast<std::size_t>(q * static_cast<double>(us.size() - 1))]; };
  state.counters["median_us"] = at(0.5);
  state.counters["p99_us"] = at(0.99);
  state.counters["worst_us"] = us.back();
  state.counters["median_kHz"] = 1e3 / at(0.5);
  state.counters["iters_per_frame"] = static_cast<double>(iterations) / static_cast<double>(us.size());
  state.counters["held_frac"] = static_cast<double>(held) / static_cast<double>(us.size());
}

const int session_frames = static_cast<int>(duration * rate);

void BM_Frame_AnalyticContacts_RangeSpace(benchmark::State& s) {
  run_session<grip::CylinderScene<S>, grip::RangeSpaceFrameSolver>(s, scene());
}
void BM_Frame_AnalyticContacts_Kkt_baseline(benchmark::State& s) {
  run_session<grip::CylinderScene<S>, grip::KktFrameSolver>(s, scene());
}
void BM_Frame_OctreeCollision_RangeSpace(benchmark::State& s) {
  run_session<grip::OctreeScene<S, octree_capacity, CylinderShape>, grip::RangeSpaceFrameSolver>(s, octree_scene());
}
void BM_Frame_OctreeCollision_Kkt_baseline(benchmark::State& s) {
  run_session<grip::OctreeScene<S, octree_capacity, CylinderShape>, grip::KktFrameSolver>(s, octree_scene());
}

// ConstrainedFrameSolver as the pipeline constructs it: warm-started, the device's limits in the
// problem (bound_by_device); then with them left to the device, which clips.
void BM_Frame_AnalyticContacts_Constrained_warm(benchmark::State& s) {
  run_session<grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>>(s, scene());
}
void BM_Frame_OctreeCollision_Constrained_warm(benchmark::State& s) {
  run_session<grip::OctreeScene<S, octree_capacity, CylinderShape>, grip::ConstrainedFrameSolver<S>>(s, octree_scene());
}
void BM_Frame_AnalyticContacts_Constrained_clipped(benchmark::State& s) {
  run_session<grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>>(s, scene(), false);
}
// Frame times by what the grasp is doing (cylinder scene, constrained solver, warm), with the
// device's limits in the problem (the default) and clipped after it: each frame is timed as the
// least of three runs from a copy of the pipeline's state (its own cost, without the machine's
// interruptions), and put in one class by its own outcome: slipping (the solve is not Ok, or a
// contact slides), shaking (the script's "shake" phase, held), holding (held, any other phase);
// the rest (closing, free flight) is not drawn. Counters: each class's median and p99 (us) per
// variant, and slip_p99_over_hold_p50. With GRIP_HISTOGRAM_SVG=<file> it also writes the
// histograms as an SVG (docs/images/frame_times.svg).
struct FrameClassTimes {
  std::vector<double> us[3];  // holding, shaking, slipping
};

template <class Pipeline>
FrameClassTimes classify_session(bool bound_by_device) {
  const Inputs& in = inputs();
  Pipeline pipeline(session_settings(bound_by_device), scene(), object());
  FrameClassTimes out;
  grip::HapticFrame<S> frame;
  for (std::size_t i = 0; i < in.wrist.size(); ++i) {
    double least = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      Pipeline copy = pipeline;
      const auto t0 = std::chrono::steady_clock::now();
      copy.step(in.wrist[i], in.angles[i], frame);
      const auto t1 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(frame);
      least = std::min(least, std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    pipeline.step(in.wrist[i], in.angles[i], frame);
    const bool slipping = frame.contacts > 0 && (frame.solve_status != grip::Status::Ok || frame.sliding > 0);
    const bool shaking = std::string(phases[phase_at(static_cast<S>(i) / rate)].name) == "shake";
    if (slipping)
      out.us[2].push_back(least);
    else if (frame.held && shaking)
      out.us[1].push_back(least);
    else if (frame.held)
      out.us[0].push_back(least);
  }
  for (auto& v : out.us) std::sort(v.begin(), v.end());
  return out;
}

double quantile(const std::vector<double>& sorted, double q) {
  return sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

// Three panels (holding, shaking, slipping) of frame-time histograms on a log axis from 1 us to
// 1 ms, 12 bins per decade, as the fraction of the class's frames; blue: the device's limits in
// the problem, grey: clipped after it.
void write_histograms(const char* path, const FrameClassTimes& bounded, const FrameClassTimes& clipped) {
  std::FILE* f = std::fopen(path, "w");
  if (f == nullptr) return;
  const double W = 900, left = 70, right = 230, top = 50, ph = 150, gap = 40, pw = W - left - right;
  const double H = top + 3 * ph + 2 * gap + 50;
  const int bins = 36;
  const char* names[3] = {"holding", "shaking", "slipping"};
  const auto X = [&](double us) { return left + pw * (std::log10(std::max(us, 1.0)) / 3.0); };
  std::fprintf(
      f,
      "<svg xmlns='http://www.w3.org/2000/svg' width='%.0f' height='%.0f' font-family='sans-serif' font-size='12'>\n",
      W, H);
  std::fprintf(f, "<rect width='100%%' height='100%%' fill='white'/>\n");
  std::fprintf(f,
               "<text x='%.0f' y='24' font-size='15'>grip haptic loop: frame times, solve_constrained with the device "
               "limits in the problem and clipped after it</text>\n",
               left);
  const double yb = top + 3 * ph + 2 * gap;  // the bottom of the last panel
  for (int d = 0; d <= 3; ++d) {
    const double x = X(std::pow(10.0, d));
    std::fprintf(f, "<line x1='%.1f' x2='%.1f' y1='%.0f' y2='%.0f' stroke='#ccc'/>\n", x, x, top, yb);
    std::fprintf(f, "<text x='%.1f' y='%.0f' text-anchor='middle'>%s</text>\n", x, yb + 16,
                 d == 0   ? "1"
                 : d == 1 ? "10"
                 : d == 2 ? "100"
                          : "1000");
  }
  std::fprintf(f,
               "<text x='%.0f' y='%.0f' text-anchor='middle'>frame time (us, log scale); bar height: fraction of the "
               "class's frames</text>\n",
               left + pw / 2, yb + 34);
  for (int c = 0; c < 3; ++c) {
    const double y0 = top + c * (ph + gap);
    double hist[2][bins] = {};
    const FrameClassTimes* v[2] = {&clipped, &bounded};
    double peak = 0.05;
    for (int k = 0; k < 2; ++k) {
      const std::vector<double>& t = v[k]->us[c];
      for (double us : t) {
        const int b = std::min(bins - 1, std::max(0, static_cast<int>(std::log10(std::max(us, 1.0)) * 12.0)));
        hist[k][b] += 1.0 / static_cast<double>(t.size());
      }
      for (int b = 0; b < bins; ++b) peak = std::max(peak, hist[k][b]);
    }
    std::fprintf(f, "<rect x='%.0f' y='%.0f' width='%.0f' height='%.0f' fill='none' stroke='black'/>\n", left, y0, pw,
                 ph);
    for (int k = 0; k < 2; ++k)
      for (int b = 0; b < bins; ++b) {
        if (hist[k][b] <= 0) continue;
        const double x0 = left + pw * b / bins, x1 = left + pw * (b + 1) / bins, h = ph * hist[k][b] / peak;
        std::fprintf(
            f, "<rect x='%.1f' y='%.1f' width='%.1f' height='%.1f' fill='%s' fill-opacity='%s' stroke='%s'/>\n", x0,
            y0 + ph - h, x1 - x0, h, k == 0 ? "#999" : "#1f77b4", k == 0 ? "0.5" : "0.6", k == 0 ? "#666" : "#1f77b4");
      }
    std::fprintf(f, "<text x='%.0f' y='%.0f' font-size='13'>%s</text>\n", left + 6, y0 + 16, names[c]);
    for (int k = 0; k < 2; ++k) {
      const std::vector<double>& t = v[k]->us[c];
      std::fprintf(f, "<text x='%.0f' y='%.0f' fill='%s'>%s: %zu frames</text>\n", left + pw + 12, y0 + 18 + 44 * k,
                   k == 0 ? "#555" : "#1f77b4", k == 0 ? "clipped" : "limits in the problem", t.size());
      std::fprintf(f, "<text x='%.0f' y='%.0f' fill='%s'>median %.1f us, p99 %.1f us</text>\n", left + pw + 12,
                   y0 + 34 + 44 * k, k == 0 ? "#555" : "#1f77b4", quantile(t, 0.5), quantile(t, 0.99));
    }
  }
  std::fprintf(f, "</svg>\n");
  std::fclose(f);
}

void BM_FrameTimeHistogram(benchmark::State& state) {
  using Pipeline = grip::HapticPipeline<S, grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>>;
  FrameClassTimes bounded, clipped;
  for (auto _ : state) {
    bounded = classify_session<Pipeline>(true);
    clipped = classify_session<Pipeline>(false);
  }
  const char* names[3] = {"hold", "shake", "slip"};
  for (int c = 0; c < 3; ++c) {
    state.counters[std::string(names[c]) + "_count"] = static_cast<double>(bounded.us[c].size());
    state.counters[std::string(names[c]) + "_p50_us"] = quantile(bounded.us[c], 0.5);
    state.counters[std::string(names[c]) + "_p99_us"] = quantile(bounded.us[c], 0.99);
    state.counters[std::string(names[c]) + "_p50_us_clipped"] = quantile(clipped.us[c], 0.5);
    state.counters[std::string(names[c]) + "_p99_us_clipped"] = quantile(clipped.us[c], 0.99);
  }
  state.counters["slip_p99_over_hold_p50"] = quantile(bounded.us[2], 0.99) / quantile(bounded.us[0], 0.5);
  if (const char* path = std::getenv("GRIP_HISTOGRAM_SVG")) write_histograms(path, bounded, clipped);
}
// The solver alone on the session's own frames (BM_SolveReplay): the pipeline runs the cylinder
// scene once with ConstrainedFrameSolver, and a recording solver keeps every frame's problem
// (grasp, w_ext, and the warm start the pipeline handed that solve: multipliers or certificate). Then each recorded
// problem is solved again from the same warm start, timed as the least of three solves, and classed by its answer: held
// (Ok) or slipping (anything else). The same problems for every version of the solver, free of the session's path
// (which moves with any change of a frame). Counters: per class the count, median, p99 and worst (us), the worst
// interior-point iterations, and slip_p99_over_held_p50.
struct RecordedSolve {
  using GraspType = grip::HapticPipeline<S, grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>>::GraspType;
  GraspType grasp;
  grip::Wrench<S> w_ext;
  grip::ConstrainedWarmStart<S> start;  // the multipliers or certificate of the previous solve
};

struct RecordingFrameSolver : grip::ConstrainedFrameSolver<S> {
  std::vector<RecordedSolve>* log{nullptr};
  template <class GraspT>
  grip::Solution<GraspT> operator()(const GraspT& grasp, const grip::Wrench<S>& w_ext) {
    static_assert(std::is_same<GraspT, RecordedSolve::GraspType>::value, "the pipeline's grasp type");
    if (log != nullptr && grasp.size() > 0) log->push_back({grasp, w_ext, warm});
    return grip::ConstrainedFrameSolver<S>::operator()(grasp, w_ext);
  }
};

const std::vector<RecordedSolve>& recorded_session() {
  static std::vector<RecordedSolve> log;
  if (log.empty()) {
    using Pipeline = grip::HapticPipeline<S, grip::CylinderScene<S>, RecordingFrameSolver>;
    const Inputs& in = inputs();
    auto pipeline = std::make_unique<Pipeline>(settings(), scene(), object());
    pipeline->solver().log = &log;
    grip::HapticFrame<S> frame;
    for (std::size_t i = 0; i < in.wrist.size(); ++i) pipeline->step(in.wrist[i], in.angles[i], frame);
  }
  return log;
}

void BM_SolveReplay(benchmark::State& state) {
  const std::vector<RecordedSolve>& log = recorded_session();
  const grip::ConstrainedSettings<S> st;
  std::vector<double> us[2];  // held, slipping
  int iterations[2] = {0, 0};
  for (auto _ : state) {
    for (const RecordedSolve& r : log) {
      int cls = 0;
      double least = std::numeric_limits<double>::infinity();
      for (int rep = 0; rep < 3; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto sol = grip::solve_constrained(r.grasp, r.w_ext, st, r.start);
        const auto t1 = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(sol.forces.data());
        least = std::min(least, std::chrono::duration<double, std::micro>(t1 - t0).count());
        cls = sol.status == grip::Status::Ok ? 0 : 1;
        iterations[cls] = std::max(iterations[cls], sol.iterations);
      }
      us[cls].push_back(least);
    }
  }
  const char* cls_names[2] = {"held", "slip"};
  for (int c = 0; c < 2; ++c) {
    std::vector<double>& t = us[c];
    std::sort(t.begin(), t.end());
    const std::string k = cls_names[c];
    state.counters[k + "_count"] = static_cast<double>(t.size());
    state.counters[k + "_p50_us"] = quantile(t, 0.5);
    state.counters[k + "_p99_us"] = quantile(t, 0.99);
    state.counters[k + "_worst_us"] = t.empty() ? 0.0 : t.back();
    state.counters[k + "_worst_iterations"] = iterations[c];
  }
  state.counters["slip_p99_over_held_p50"] = quantile(us[1], 0.99) / quantile(us[0], 0.5);
}

// The whole hand's power grasp: the hand palm down, the cylinder across the palm (1 mm into
// it), the fingers closed on it with the thumb's CMC in opposition (0.5, 0.6 rad).
struct PowerGrasp {
  grip::HapticSettings<S> settings;
  grip::CylinderScene<S> scene;
  grip::RigidBody<S> object;
  grip::WristState<S> wrist;
  grip::HandJoints<S> joints{grip::HandJoints<S>::Zero()};
  grip::JointAngles<S> angles{grip::JointAngles<S>::Zero()};  // the paper hand's, closed alike
  grip::Glove22<S> glove;
  grip::Glove22<S>::Readings readings;
  PowerGrasp() {
    settings.stiffness.fill(1.5e4);
    settings.palm_stiffness = 1.5e4;
    scene.radius = radius;
    scene.half_length = half_length;
    object = haptic_session::object();
    const S L = settings.hand.hand_length;
    wrist.pose.translation() = object.position - V3(S(0.27) * L, 0, -(radius + S(0.055) * L - S(0.001)));
    grip::HandJoints<S> start = grip::HandJoints<S>::Zero();
    start(0) = S(0.5);
    start(1) = S(0.6);
    joints = grip::close_hand_in_scene(scene, settings.hand, wrist.pose, object, S(0.002), S(0.03), start).angles;
    angles = grip::close_hand_in_scene<S>(scene, settings.hand, wrist.pose, object, S(0.002), S(0.03)).angles;
    readings = glove.readings(joints);
  }
};
const PowerGrasp& power_grasp() {
  static const PowerGrasp g;
  return g;
}

// Each iteration: a fresh copy of the pipeline after its first frame (not timed), then one
// frame timed by the clock; `whole`: the glove mapping and the 20 joints, else the 14 angles.
template <class Device, bool whole>
void run_grasp(benchmark::State& state) {
  const PowerGrasp& g = power_grasp();
  using Pipeline = grip::HapticPipeline<S, grip::CylinderScene<S>, grip::RangeSpaceFrameSolver, Device>;
  Pipeline first(g.settings, g.scene, g.object);
  grip::HapticFrame<S> frame;
  if constexpr (whole)
    first.step(g.wrist, g.joints, frame);
  else
    first.step(g.wrist, g.angles, frame);
  std::vector<double> us;
  for (auto _ : state) {
    state.PauseTiming();
    auto p = std::make_unique<Pipeline>(first);
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (whole) {
      grip::HandJoints<S> q;
      g.glove.map(g.readings, g.settings.hand.limits, q);
      p->step(g.wrist, q, frame);
    } else {
      p->step(g.wrist, g.angles, frame);
    }
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(frame);
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  std::sort(us.begin(), us.end());
  state.counters["median_us"] = us[us.size() / 2];
  state.counters["median_kHz"] = 1e3 / us[us.size() / 2];
  state.counters["contacts"] = frame.contacts;
  state.counters["held"] = frame.held ? 1 : 0;
}
void BM_WholeHandFrame_JointTorques(benchmark::State& s) { run_grasp<grip::JointTorques<S>, true>(s); }
void BM_WholeHandFrame_Actuators(benchmark::State& s) { run_grasp<grip::PhalanxActuators<S>, true>(s); }
void BM_PaperHandFrame_baseline(benchmark::State& s) { run_grasp<grip::PhalanxActuators<S>, false>(s); }
BENCHMARK(BM_WholeHandFrame_JointTorques)->Iterations(20000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WholeHandFrame_Actuators)->Iterations(20000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PaperHandFrame_baseline)->Iterations(20000)->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_FrameTimeHistogram)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SolveReplay)->Iterations(1)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_Frame_AnalyticContacts_Constrained_warm)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_OctreeCollision_Constrained_warm)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_AnalyticContacts_Constrained_clipped)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_AnalyticContacts_RangeSpace)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_AnalyticContacts_Kkt_baseline)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_OctreeCollision_RangeSpace)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Frame_OctreeCollision_Kkt_baseline)->Iterations(2 * session_frames)->Unit(benchmark::kMicrosecond);

}  // namespace
