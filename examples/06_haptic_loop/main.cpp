// The closed haptic loop, end to end: a scripted glove-and-tracker session at 1 kHz drives
// grip's per-frame pipeline (contacts, squeeze, external wrench, optimal forces, monitor,
// per-phalanx feedback, device). Prints a report; writes haptic_loop.csv and haptic_loop.svg
// to the current directory or to the directory given as an argument.
//   haptic_loop [DIR] [--device=actuators|vector|torques|brakes]
// chooses the device policy (device_policy.hpp): one actuator per phalanx (the paper's glove,
// the default), a 3-D force per phalanx, an exoskeleton's joint torques (printed per joint),
// or passive brakes on the joints.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "session.hpp"

#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/frame_solver.hpp>

// The optimum inside the exact friction cones, warm-started from the previous frame.
using FrameSolver = grip::ConstrainedFrameSolver<haptic_session::S>;
constexpr const char* solver_name = "solve_constrained (exact cones, warm-started)";

namespace {

using namespace haptic_session;
constexpr int n_phalanx = grip::hand_phalanx_count;
const char* const phalanx_names[n_phalanx] = {"thumb prox", "thumb dist",  "index prox", "index mid",  "index dist",
                                              "long prox",  "long mid",    "long dist",  "ring prox",  "ring mid",
                                              "ring dist",  "little prox", "little mid", "little dist"};
const char* const joint_names[grip::hand_dof_count] = {
    "thumb CMC flex", "thumb CMC abd", "thumb MCP",  "thumb IP",   "index abd",  "index MCP", "index PIP",
    "index DIP",      "long abd",      "long MCP",   "long PIP",   "long DIP",   "ring abd",  "ring MCP",
    "ring PIP",       "ring DIP",      "little abd", "little MCP", "little PIP", "little DIP"};

// What the run reports of its device: frames in which it clipped, and for the joint devices
// the torques per joint (the mean over the hold phase and the peak).
struct DeviceReport {
  int clipped_frames = 0;
  std::array<double, grip::hand_dof_count> hold_sum{}, peak{};
  int hold_frames = 0;
};

void record_torques(const grip::HandJoints<S>& torque, bool holding, DeviceReport& r) {
  for (int j = 0; j < grip::hand_dof_count; ++j) {
    const double tau = torque(j);
    r.peak[static_cast<std::size_t>(j)] = std::max(r.peak[static_cast<std::size_t>(j)], std::abs(tau));
    if (holding) r.hold_sum[static_cast<std::size_t>(j)] += tau;
  }
  r.hold_frames += holding ? 1 : 0;
}

struct Sample {
  S t;
  int phase;
  bool held;
  V3 position;
  Eigen::Quaternion<S> orientation;
  V3 velocity;
  int contacts, sliding, clamped;
  S magnitude[n_phalanx];  // |feedback force| (N)
  S command[n_phalanx];    // along the actuation direction, clamped (N)
  S lift;                  // vertical force of the fingers on the object (N)
};

void write_csv(const std::string& path, const std::vector<Sample>& samples) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::printf("cannot write %s\n", path.c_str());
    return;
  }
  std::fprintf(f, "t,phase,held,x,y,z,qw,qx,qy,qz,vx,vy,vz,contacts,sliding,clamped,fingers_vertical");
  for (int k = 0; k < n_phalanx; ++k) std::fprintf(f, ",F%d_norm,F%d_cmd", k, k);
  std::fprintf(f, "\n");
  for (const Sample& s : samples) {
    std::fprintf(f, "%.3f,%s,%d,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f,%d,%d,%d,%.4f", s.t,
                 phases[s.phase].name, s.held ? 1 : 0, s.position.x(), s.position.y(), s.position.z(),
                 s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z(), s.velocity.x(),
                 s.velocity.y(), s.velocity.z(), s.contacts, s.sliding, s.clamped, s.lift);
    for (int k = 0; k < n_phalanx; ++k) std::fprintf(f, ",%.4f,%.4f", s.magnitude[k], s.command[k]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

// An SVG plot, written by hand: top panel |F| per phalanx (colour = finger, dash = phalanx),
// bottom panel the fingers' total vertical force on the object and the object's height.
void write_svg(const std::string& path, const std::vector<Sample>& samples) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::printf("cannot write %s\n", path.c_str());
    return;
  }
  const double W = 1200, H = 760, left = 70, right = 180, top1 = 40, h1 = 400, top2 = 510, h2 = 200;
  const double pw = W - left - right;
  double fmax = 1;
  for (const Sample& s : samples)
    for (int k = 0; k < n_phalanx; ++k) fmax = std::max(fmax, s.magnitude[k]);
  fmax = std::ceil(fmax / 5) * 5;
  double lmin = 0, lmax = 1;
  for (const Sample& s : samples) {
    lmin = std::min(lmin, s.lift);
    lmax = std::max(lmax, s.lift);
  }
  lmin = std::floor(lmin / 5) * 5;
  lmax = std::ceil(lmax / 5) * 5;
  auto X = [&](double t) { return left + pw * t / duration; };
  auto Y1 = [&](double v) { return top1 + h1 * (1 - v / fmax); };
  auto Y2 = [&](double v) { return top2 + h2 * (1 - (v - lmin) / (lmax - lmin)); };
  std::fprintf(
      f,
      "<svg xmlns='http://www.w3.org/2000/svg' width='%.0f' height='%.0f' font-family='sans-serif' font-size='12'>\n",
      W, H);
  std::fprintf(f, "<rect width='100%%' height='100%%' fill='white'/>\n");
  std::fprintf(f,
               "<text x='%.0f' y='22' font-size='16'>grip haptic loop: feedback force on each phalanx, 1 kHz scripted "
               "session (0.4 kg cylinder)</text>\n",
               left);
  for (int i = 0; i < phase_count; ++i) {  // phase bands
    const double x0 = X(phases[i].begin), x1 = X(phases[i].end);
    std::fprintf(f, "<rect x='%.1f' y='%.0f' width='%.1f' height='%.0f' fill='%s'/>\n", x0, top1, x1 - x0,
                 top2 + h2 - top1, i % 2 ? "#f4f4f4" : "#ffffff");
    std::fprintf(f, "<text x='%.1f' y='%.0f' text-anchor='middle' fill='#555'>%s</text>\n", 0.5 * (x0 + x1), top1 + 14,
                 phases[i].name);
  }
  for (int j = 0; j <= 5; ++j) {  // axes, grid
    const double v = fmax * j / 5, y = Y1(v);
    std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='#ddd'/>\n", left, left + pw, y, y);
    std::fprintf(f, "<text x='%.0f' y='%.1f' text-anchor='end'>%.0f</text>\n", left - 6, y + 4, v);
  }
  for (int j = 0; j <= 4; ++j) {
    const double v = lmin + (lmax - lmin) * j / 4, y = Y2(v);
    std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='#ddd'/>\n", left, left + pw, y, y);
    std::fprintf(f, "<text x='%.0f' y='%.1f' text-anchor='end'>%.0f</text>\n", left - 6, y + 4, v);
  }
  for (int j = 0; j <= 13; ++j) {
    const double t = 0.5 * j;
    if (t > duration) break;
    std::fprintf(f, "<text x='%.1f' y='%.0f' text-anchor='middle'>%.1f</text>\n", X(t), top2 + h2 + 16, t);
  }
  std::fprintf(f, "<text x='%.0f' y='%.0f' text-anchor='middle'>time (s)</text>\n", left + pw / 2, top2 + h2 + 34);
  std::fprintf(f,
               "<text x='18' y='%.0f' transform='rotate(-90 18 %.0f)' text-anchor='middle'>|feedback force| per "
               "phalanx (N)</text>\n",
               top1 + h1 / 2, top1 + h1 / 2);
  std::fprintf(f,
               "<text x='18' y='%.0f' transform='rotate(-90 18 %.0f)' text-anchor='middle'>fingers' lift (N)</text>\n",
               top2 + h2 / 2, top2 + h2 / 2);
  std::fprintf(f, "<rect x='%.0f' y='%.0f' width='%.0f' height='%.0f' fill='none' stroke='black'/>\n", left, top1, pw,
               h1);
  std::fprintf(f, "<rect x='%.0f' y='%.0f' width='%.0f' height='%.0f' fill='none' stroke='black'/>\n", left, top2, pw,
               h2);
  const char* colour[5] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd"};
  const char* dash[3] = {"", "stroke-dasharray='2,2'", "stroke-dasharray='6,3'"};
  const int stride = 4;  // one point every 4 ms
  for (int k = 0; k < n_phalanx; ++k) {
    const int finger = static_cast<int>(grip::phalanx_finger(k)), kind = static_cast<int>(grip::phalanx_kind(k));
    std::fprintf(f, "<polyline fill='none' stroke='%s' stroke-width='1.2' %s points='", colour[finger], dash[kind]);
    for (std::size_t i = 0; i < samples.size(); i += stride)
      std::fprintf(f, "%.1f,%.1f ", X(samples[i].t), Y1(samples[i].magnitude[k]));
    std::fprintf(f, "'/>\n");
    const double ly = top1 + 10 + 16 * k;
    std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.0f' y2='%.0f' stroke='%s' stroke-width='2' %s/>\n", left + pw + 10,
                 left + pw + 40, ly, ly, colour[finger], dash[kind]);
    std::fprintf(f, "<text x='%.0f' y='%.0f'>%s</text>\n", left + pw + 46, ly + 4, phalanx_names[k]);
  }
  std::fprintf(f, "<polyline fill='none' stroke='black' stroke-width='1.2' points='");
  for (std::size_t i = 0; i < samples.size(); i += stride)
    std::fprintf(f, "%.1f,%.1f ", X(samples[i].t), Y2(samples[i].lift));
  std::fprintf(f, "'/>\n");
  const double yw = Y2(mass * 9.81);
  std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='#888' stroke-dasharray='4,4'/>\n", left,
               left + pw, yw, yw);
  std::fprintf(f, "<text x='%.0f' y='%.1f' fill='#555'>m g = %.2f N</text>\n", left + pw + 6, yw + 4, mass * 9.81);
  std::fprintf(f, "</svg>\n");
  std::fclose(f);
}

}  // namespace

template <class Device>
int run(const std::string& dir, const char* device_name, bool joint_device) {
  const Script script;
  grip::HapticPipeline<S, grip::CylinderScene<S>, FrameSolver, Device> pipeline(settings(), scene(), object());
  // The phalanx devices take the session's limits (settings().device_limit, the actuators'
  // own); the joint devices 1.5 N m per joint (a small exoskeleton motor or brake).
  if constexpr (std::is_same<Device, grip::VectorForces<S>>::value) pipeline.device().limit = settings().device_limit;
  if (joint_device) pipeline.device().limit.fill(S(1.5));
  DeviceReport device;
  const int frames = static_cast<int>(duration * rate);
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(frames));
  std::vector<double> micros;
  micros.reserve(static_cast<std::size_t>(frames));
  grip::HapticFrame<S> frame;
  int slip_events = 0, slip_frames = 0, clamped_frames = 0, failed = 0;
  bool was_held = false;
  std::array<std::array<double, 3>, phase_count> phase_stats{};  // mean total |F|, peak total |F|, frames
  double peak[n_phalanx] = {}, sum[n_phalanx] = {};
  for (int i = 0; i < frames; ++i) {
    const S t = i / rate;
    const grip::WristState<S> wrist = script.wrist(t);
    const grip::JointAngles<S> angles = script.angles(t);
    const auto t0 = std::chrono::steady_clock::now();
    const grip::Status st = pipeline.step(wrist, angles, frame);
    const auto t1 = std::chrono::steady_clock::now();
    micros.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    if (st != grip::Status::Ok) ++failed;
    Sample s;
    s.t = t;
    s.phase = phase_at(t);
    s.held = frame.held;
    s.position = pipeline.object().position;
    s.orientation = pipeline.object().orientation;
    s.velocity = pipeline.object().linear_velocity;
    s.contacts = frame.contacts;
    s.sliding = frame.sliding;
    s.clamped = frame.clamped;
    s.lift = 0;
    double total = 0;
    for (int k = 0; k < n_phalanx; ++k) {
      const auto& p = frame.phalanges[static_cast<std::size_t>(k)];
      s.magnitude[k] = p.force.norm();
      s.command[k] = p.command;
      s.lift -= p.force.z();  // the hand feels -f: the fingers push the object up by -F_z
      total += s.magnitude[k];
      peak[k] = std::max(peak[k], s.magnitude[k]);
      sum[k] += s.magnitude[k];
    }
    auto& ps = phase_stats[static_cast<std::size_t>(s.phase)];
    ps[0] += total;
    ps[1] = std::max(ps[1], total);
    ps[2] += 1;
    if (frame.contacts > 0 && !frame.held) ++slip_frames;
    if (was_held && !frame.held && frame.contacts > 0) ++slip_events;
    was_held = frame.held;
    if (frame.clamped > 0) ++clamped_frames;
    if (pipeline.device_command().clipped > 0) ++device.clipped_frames;
    if constexpr (std::is_same<Device, grip::JointTorques<S>>::value ||
                  std::is_same<Device, grip::JointBrakes<S>>::value)
      record_torques(pipeline.device_command().torque, phases[s.phase].name == std::string("hold"), device);
    samples.push_back(s);
  }

  std::printf(
      "grip haptic loop: %d frames at %.0f Hz (%.1f s), cylinder %.2f kg, r %.0f mm; closed grasp touches %d "
      "phalanges\n",
      frames, rate, duration, mass, radius * 1e3, script.touching);
  std::printf("solver: %s\ndevice: %s\n", solver_name, device_name);
  std::printf("\n%-9s %6s %6s %14s %14s %10s\n", "phase", "from", "to", "mean sum|F| N", "peak sum|F| N",
              "lift N(end)");
  for (int i = 0; i < phase_count; ++i) {
    const auto& ps = phase_stats[static_cast<std::size_t>(i)];
    const int last = std::min(frames - 1, static_cast<int>(phases[i].end * rate) - 1);
    std::printf("%-9s %6.2f %6.2f %14.2f %14.2f %10.2f\n", phases[i].name, phases[i].begin, phases[i].end,
                ps[2] > 0 ? ps[0] / ps[2] : 0.0, ps[1], samples[static_cast<std::size_t>(last)].lift);
  }
  std::printf("\n%-12s %8s %8s\n", "phalanx", "peak N", "mean N");
  for (int k = 0; k < n_phalanx; ++k) std::printf("%-12s %8.2f %8.2f\n", phalanx_names[k], peak[k], sum[k] / frames);
  std::vector<double> sorted = micros;
  std::sort(sorted.begin(), sorted.end());
  const auto pct = [&](double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  std::printf("\nslips: %d events (held -> slipping with fingers on it), %d frames not held while touched\n",
              slip_events, slip_frames);
  std::printf("clamped to the device limit: %d frames; failed frames: %d\n", clamped_frames, failed);
  std::printf("device policy clipped its command in %d frames\n", device.clipped_frames);
  if (joint_device) {
    std::printf("\njoint torques the device applies (N m): mean over the hold phase, peak\n");
    for (int j = 0; j < grip::hand_dof_count; ++j)
      std::printf("%-15s %8.4f %8.4f\n", joint_names[j],
                  device.hold_frames > 0 ? device.hold_sum[static_cast<std::size_t>(j)] / device.hold_frames : 0.0,
                  device.peak[static_cast<std::size_t>(j)]);
  }
  std::printf("frame time (wall clock, this build): median %.2f us, p99 %.2f us, worst %.2f us\n", pct(0.5), pct(0.99),
              sorted.back());
  std::printf("object at the end: (%.3f, %.3f, %.3f) m\n", samples.back().position.x(), samples.back().position.y(),
              samples.back().position.z());
  write_csv(dir + "haptic_loop.csv", samples);
  write_svg(dir + "haptic_loop.svg", samples);
  std::printf("wrote %shaptic_loop.csv and %shaptic_loop.svg\n", dir.c_str(), dir.c_str());
  return failed == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
  std::string dir, device = "actuators";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--device=", 0) == 0)
      device = a.substr(9);
    else
      dir = a + "/";
  }
  if (device == "actuators") return run<grip::PhalanxActuators<S>>(dir, "one actuator per phalanx", false);
  if (device == "vector") return run<grip::VectorForces<S>>(dir, "a 3-D force per phalanx, saturated by norm", false);
  if (device == "torques") return run<grip::JointTorques<S>>(dir, "joint torques (exoskeleton)", true);
  if (device == "brakes") return run<grip::JointBrakes<S>>(dir, "passive brakes on the joints", true);
  std::printf("unknown device '%s': actuators, vector, torques or brakes\n", device.c_str());
  return 2;
}
