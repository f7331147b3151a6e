// Example 6's session on a modelled commercial-class glove: one cable per finger, pulling its
// fingertip open with at most 20 N, updated at 200 Hz in 100 steps (0.2 N), 5 ms behind the
// host. Two questions, one figure (glove_device.svg; the data in glove_device.csv):
//  1. What net force does the hand feel? Clipping each cable to its own phalanx's share against
//     the command whose net wrench comes closest to the felt one (PhalanxActuators::net_wrench),
//     both beside the net force the object asks for (its weight and inertia), and the closest
//     command through the channel guard at 200 Hz in 0.2 N steps.
//  2. Is the channel safe? The index finger pressing on the object's surface, rendered as a
//     spring 5 times stiffer than the channel can render stably, through a model of the finger
//     and the channel (DeviceChannelModel): the energy the channel gives the finger, without and
//     with the passivity controller in the glove's firmware, whose loop runs at 1 kHz (the
//     commands still come at 200 Hz).
//   glove_device [DIR]
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../06_haptic_loop/session.hpp"

#include <grip/pipeline/channel_guard.hpp>
#include <grip/pipeline/device_model.hpp>
#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/frame_solver.hpp>
#include <grip/pipeline/net_wrench_command.hpp>

namespace {

using namespace haptic_session;
using Glove = grip::PhalanxActuators<S>;
constexpr int n_phalanx = grip::hand_phalanx_count;

// The glove: one cable per finger, on the distal phalanx, 20 N; nothing on the other phalanges.
Glove glove(bool net_wrench) {
  Glove g;
  g.limit.fill(S(0));
  for (const grip::Finger f :
       {grip::Finger::Thumb, grip::Finger::Index, grip::Finger::Long, grip::Finger::Ring, grip::Finger::Little})
    g.limit[static_cast<std::size_t>(grip::phalanx_index(f, grip::Phalanx::Distal))] = S(20);
  g.net_wrench = net_wrench;
  return g;
}

constexpr S channel_rate = 200;  // Hz
constexpr S channel_step = 0.2;  // N: 100 steps of 20 N
constexpr S channel_delay = 0.005;
constexpr S firmware_rate = 1000;  // Hz: the glove's own loop, which runs the passivity controller

struct Sample {
  S t;
  int phase;
  S felt_z, clip_z, best_z, glove_z;  // vertical net force on the hand (N)
};

// The net force of a command's pushes (N, world).
V3 pushed(const std::array<S, n_phalanx>& force, const grip::FeltForces<S>& felt) {
  V3 sum = V3::Zero();
  for (std::size_t k = 0; k < static_cast<std::size_t>(n_phalanx); ++k) sum += force[k] * felt.direction[k];
  return sum;
}

S weighted(const grip::Wrench<S>& w, S lever) {
  return std::sqrt(w.head<3>().squaredNorm() + (lever > 0 ? w.tail<3>().squaredNorm() / (lever * lever) : S(0)));
}

// Part 2: the index finger on a wall of stiffness k through the modelled channel for the
// session's duration: the host computes the wall at 1 kHz and sends a command at the channel's
// 200 Hz; the glove's firmware applies the newest at 1 kHz, with the controller.
struct EnergyRun {
  std::vector<S> energy;  // J, per frame
  S least{0};
  S late{0};  // the largest |x - x_eq| over the last 0.5 s (m)
};

EnergyRun press(S k, bool passivity) {
  grip::FingerImpedance<S> finger;  // 10 g, 2 N s/m, 100 N/m
  finger.rest = 0.005;              // the person presses 5 mm into the surface
  grip::DeviceChannelSettings<S> c;
  c.delay = channel_delay;
  c.update_rate = firmware_rate;
  c.step = channel_step;
  c.min_force = -20;  // the cable pulls the fingertip open (out of the surface) only
  c.max_force = 0;
  c.passivity = passivity;
  c.max_damping = S(0.75) * 2 * finger.mass * firmware_rate;  // within the held damper's 2 m / T
  grip::DeviceChannelModel<S> model(finger, c, -0.002, 0.0);
  EnergyRun run;
  const S x_eq = finger.stiffness * finger.rest / (finger.stiffness + k);
  const int frames = static_cast<int>(duration * rate);
  for (int i = 0; i < frames; ++i) {
    const S t = i / rate, x = model.position();
    if (i % static_cast<int>(rate / channel_rate) == 0) (void)model.send(t, x > 0 ? -k * x : S(0));
    (void)model.advance(t + 1 / rate);
    run.energy.push_back(model.energy());
    run.least = std::min(run.least, model.energy());
    if (i >= frames - 500) run.late = std::max(run.late, std::abs(model.position() - x_eq));
  }
  return run;
}

void write_csv(const std::string& path, const std::vector<Sample>& s, const EnergyRun& off, const EnergyRun& on) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return;
  std::fprintf(f, "t,phase,felt_z,clip_z,best_z,glove_z,energy_off,energy_on\n");
  for (std::size_t i = 0; i < s.size(); ++i) {
    std::fprintf(f, "%.3f,%s,%.5f,%.5f,%.5f,%.5f,%.6f,%.6f\n", s[i].t, phases[s[i].phase].name, s[i].felt_z,
                 s[i].clip_z, s[i].best_z, s[i].glove_z, off.energy[i], on.energy[i]);
  }
  std::fclose(f);
}

// A polyline of y(x) in a panel: x in [x0, x1], y in [y0, y1] mapped onto the panel's box.
struct Panel {
  double left, top, width, height, x0, x1, y0, y1;
  double px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + (y1 - std::fmin(std::fmax(y, y0), y1)) / (y1 - y0) * height; }
};

void polyline(std::FILE* f, const Panel& p, const std::vector<double>& x, const std::vector<double>& y,
              const char* colour, double w) {
  std::fprintf(f, "<polyline fill='none' stroke='%s' stroke-width='%.1f' points='", colour, w);
  for (std::size_t i = 0; i < x.size(); i += 2) std::fprintf(f, "%.1f,%.1f ", p.px(x[i]), p.py(y[i]));
  std::fprintf(f, "'/>\n");
}

void axes(std::FILE* f, const Panel& p, const char* title, const char* unit, double ystep, double xstep) {
  std::fprintf(f, "<rect x='%.0f' y='%.0f' width='%.0f' height='%.0f' fill='none' stroke='#888'/>\n", p.left, p.top,
               p.width, p.height);
  std::fprintf(f, "<text x='%.0f' y='%.0f' font-weight='bold'>%s</text>\n", p.left, p.top - 8, title);
  for (double y = std::ceil(p.y0 / ystep) * ystep; y <= p.y1 + 1e-9; y += ystep)
    std::fprintf(f, "<text x='%.0f' y='%.0f' text-anchor='end'>%g</text>\n", p.left - 4, p.py(y) + 4, y);
  for (double x = p.x0; x <= p.x1 + 1e-9; x += xstep)
    std::fprintf(f, "<text x='%.0f' y='%.0f' text-anchor='middle'>%g</text>\n", p.px(x), p.top + p.height + 14, x);
  std::fprintf(f, "<text x='%.0f' y='%.0f' text-anchor='middle'>t (s)</text>\n", p.left + p.width / 2,
               p.top + p.height + 30);
  std::fprintf(f, "<text x='%.0f' y='%.0f' transform='rotate(-90 %.0f %.0f)' text-anchor='middle'>%s</text>\n",
               p.left - 38, p.top + p.height / 2, p.left - 38, p.top + p.height / 2, unit);
}

void legend(std::FILE* f, double x, double y, const char* colour, const char* text) {
  std::fprintf(f, "<line x1='%.0f' y1='%.0f' x2='%.0f' y2='%.0f' stroke='%s' stroke-width='2'/>", x, y - 4, x + 18,
               y - 4, colour);
  std::fprintf(f, "<text x='%.0f' y='%.0f'>%s</text>\n", x + 22, y, text);
}

void write_svg(const std::string& path, const std::vector<Sample>& s, const EnergyRun& off, const EnergyRun& on) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return;
  std::fprintf(f,
               "<svg xmlns='http://www.w3.org/2000/svg' width='820' height='700' font-family='sans-serif' "
               "font-size='12'>\n<rect width='820' height='700' fill='white'/>\n");
  const Panel top{70, 40, 720, 300, 0, duration, -16, 4};
  axes(f, top, "Vertical net force on the hand: what the object asks for and what the glove renders", "N", 4, 0.5);
  std::vector<double> t, felt, clip, best, gl;
  for (const Sample& x : s) {
    t.push_back(x.t);
    felt.push_back(x.felt_z);
    clip.push_back(x.clip_z);
    best.push_back(x.best_z);
    gl.push_back(x.glove_z);
  }
  std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='#999' stroke-dasharray='4 3'/>\n", top.px(0),
               top.px(duration), top.py(-mass * 9.81), top.py(-mass * 9.81));
  polyline(f, top, t, felt, "black", 1.5);
  polyline(f, top, t, clip, "#d62728", 1.2);
  polyline(f, top, t, gl, "#9ecae1", 2.5);
  polyline(f, top, t, best, "#1f77b4", 1.2);
  legend(f, 70, 392, "black", "felt (the object's weight and inertia)");
  legend(f, 330, 392, "#d62728", "clipping each cable");
  legend(f, 500, 392, "#1f77b4", "closest net wrench");
  legend(f, 70, 410, "#9ecae1", "closest net wrench through the 200 Hz channel, 0.2 N steps, 5 ms behind");
  std::fprintf(f, "<text x='%.0f' y='%.0f' fill='#666'>-m g</text>\n", top.px(duration) - 32, top.py(-mass * 9.81) - 5);
  // The energy axis: from the least energy, rounded down to a step of a power of ten times 1, 2
  // or 5 that gives four to ten ticks.
  const double span = std::fmax(-std::fmin(off.least, on.least), 1e-6);
  double estep = std::pow(10.0, std::floor(std::log10(span)));
  if (span / estep < 2)
    estep /= 5;
  else if (span / estep < 4)
    estep /= 2;
  const double emin = -std::ceil(span / estep) * estep;
  const Panel bottom{70, 470, 720, 160, 0, duration, emin, estep / 2};
  axes(f, bottom, "Index finger on a surface 5 times stiffer than the channel renders stably: the channel's energy",
       "J", estep, 0.5);
  std::vector<double> te, eoff(off.energy.begin(), off.energy.end()), eon(on.energy.begin(), on.energy.end());
  for (std::size_t i = 0; i < off.energy.size(); ++i) te.push_back(double(i) / rate);
  polyline(f, bottom, te, eoff, "#d62728", 1.5);
  polyline(f, bottom, te, eon, "#2ca02c", 1.5);
  legend(f, 70, 682, "#d62728", "without the passivity controller");
  legend(f, 310, 682, "#2ca02c", "with it, in the glove's 1 kHz firmware");
  std::fprintf(f, "</svg>\n");
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? std::string(argv[1]) + "/" : std::string();
  const Script script;
  // The simulation is the hand's own (the object held by the hand, not by the glove): the
  // solver is not bound by the glove, which renders what it can.
  grip::HapticSettings<S> st = settings();
  st.bound_by_device = false;
  grip::HapticPipeline<S, grip::CylinderScene<S>, grip::ConstrainedFrameSolver<S>, Glove> pipeline(st, scene(),
                                                                                                   object());
  pipeline.device() = glove(false);
  const Glove best_glove = glove(true);
  grip::ChannelGuardSettings<S> gs;
  gs.update_rate = channel_rate;
  gs.step = channel_step;
  gs.slew_rate = 2000;    // N/s
  gs.onset_time = 0.01;   // s
  gs.stale_after = 0.05;  // s
  gs.max_command = 20;
  grip::ChannelGuard<S, n_phalanx> guard(gs);
  const int delay_frames = static_cast<int>(std::lround(channel_delay * rate));
  std::vector<std::array<S, n_phalanx>> sent;  // the guard's commands, for the channel's delay

  const int frames = static_cast<int>(duration * rate);
  std::vector<Sample> samples;
  grip::HapticFrame<S> frame;
  Glove::Command best;
  int failed = 0, touching = 0;
  S err_clip = 0, err_best = 0, hold_clip = 0, hold_best = 0, hold_glove = 0;
  int hold_frames = 0;
  for (int i = 0; i < frames; ++i) {
    const S t = i / rate;
    if (pipeline.step(script.wrist(t), script.angles(t), frame) != grip::Status::Ok) ++failed;
    const grip::FeltForces<S>& felt = pipeline.felt();
    const Glove::Command& clip = pipeline.device_command();
    (void)best_glove.render(felt, pipeline.posture(), pipeline.joint_velocity(), best);
    const auto w = grip::felt_net_wrench(felt.force, felt.point, felt.in_contact);
    std::array<S, n_phalanx> want = best.force;
    (void)guard.update(t, want, true);
    sent.push_back(guard.command());
    const std::array<S, n_phalanx>& arrived =
        sent[static_cast<std::size_t>(std::max(0, static_cast<int>(sent.size()) - 1 - delay_frames))];
    Sample s;
    s.t = t;
    s.phase = phase_at(t);
    s.felt_z = w.wrench.z();
    s.clip_z = pushed(clip.force, felt).z();
    s.best_z = pushed(best.force, felt).z();
    s.glove_z = pushed(arrived, felt).z();
    samples.push_back(s);
    if (frame.contacts > 0) {
      ++touching;
      err_clip += weighted(clip.unrendered, w.lever);
      err_best += weighted(best.unrendered, w.lever);
    }
    if (phases[s.phase].name == std::string("hold")) {
      ++hold_frames;
      hold_clip += std::abs(s.clip_z - s.felt_z);
      hold_best += std::abs(s.best_z - s.felt_z);
      hold_glove += std::abs(s.glove_z - s.felt_z);
    }
  }

  // Part 2. The channel's stable stiffness for a held spring on the finger: 2 b / (T + 2 d).
  const grip::FingerImpedance<S> finger;
  const S stable = 2 * finger.damping / (1 / channel_rate + 2 * channel_delay);
  const EnergyRun off = press(5 * stable, false), on = press(5 * stable, true);

  std::printf(
      "glove: one cable per finger (distal phalanx), 20 N, %.0f Hz, %.1f N steps, %.0f ms delay, firmware at %.0f "
      "Hz\n",
      channel_rate, channel_step, channel_delay * 1e3, firmware_rate);
  std::printf("session: %d frames, %d with contact, failed frames: %d\n", frames, touching, failed);
  std::printf("net-wrench error over the frames with contact (N, moments over the lever):\n");
  std::printf("  clipping each cable: %.1f\n  closest net wrench:  %.1f\n  clipping / closest:  %.2f\n", err_clip,
              err_best, err_best > 0 ? err_clip / err_best : 0.0);
  std::printf(
      "hold phase, mean |vertical net force error| (N): clipping %.2f, closest %.2f, closest through the "
      "channel %.2f (m g = %.2f N)\n",
      hold_clip / hold_frames, hold_best / hold_frames, hold_glove / hold_frames, mass * 9.81);
  std::printf("index finger on a surface of %.0f N/m (5 times the channel's stable %.0f N/m):\n", 5 * stable, stable);
  std::printf("  without the passivity controller: least energy %.4f J, late oscillation %.2f mm\n", off.least,
              off.late * 1e3);
  std::printf("  with it:                          least energy %.4f J, late oscillation %.2f mm\n", on.least,
              on.late * 1e3);
  // What the scenario implies: in the hold the object asks for m g alone, which five cables of
  // 20 N along the fingertips' opening directions can render, to the channel's steps and lag;
  // clipping renders each fingertip's squeeze instead. The controller takes back energy the
  // channel gives, within its damper's range.
  std::printf("the closest command renders m g in the hold within 0.5 N through the channel: %s\n",
              hold_glove / hold_frames < 0.5 ? "yes" : "no");
  std::printf("the passivity controller gives the finger less energy: %s\n", on.least > off.least ? "yes" : "no");
  std::printf("with it the finger settles within a force step's spring travel (%.2f mm): %s\n",
              channel_step / (5 * stable) * 1e3, on.late < channel_step / (5 * stable) ? "yes" : "no");
  write_csv(dir + "glove_device.csv", samples, off, on);
  write_svg(dir + "glove_device.svg", samples, off, on);
  std::printf("wrote %sglove_device.csv and %sglove_device.svg\n", dir.c_str(), dir.c_str());
  return failed == 0 ? 0 : 1;
}
