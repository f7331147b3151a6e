// grip inside MuJoCo: grip's whole hand written as MJCF (grip/mujoco/hand_mjcf.hpp), a box on
// a table, and a glove session like example 6's (its minimum-jerk ramps, timing and shake):
// the hand closes on the box, lifts it 15 cm, holds it, shakes it at 4 Hz, sets it down and
// lets go. MuJoCo simulates; after every step grip's adapter
// (grip/mujoco/adapter.hpp) turns MuJoCo's hand-box contacts and the box's motion into a grasp
// and its external wrench and solves for the optimal force on each phalanx. Prints what each
// finger feels per phase, grip's forces beside MuJoCo's own contact forces at the same
// contacts; writes mujoco_hand.csv and mujoco_hand.svg to the current directory or to the
// directory given as argv[1]. Exits 0 when the box is held from the lift to the release and
// grip's felt sum equals MuJoCo's hand contact forces up to MuJoCo's own imbalance on the box
// (its constraint solver stops at a tolerance: M qacc is then not exactly the sum of the forces).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "../06_haptic_loop/session.hpp"  // ramp(): the session's minimum-jerk profile

#include <grip/mujoco/adapter.hpp>
#include <grip/mujoco/hand_mjcf.hpp>
#include <grip/solve/solve_constrained.hpp>

namespace {

using haptic_session::S;
using haptic_session::V3;
constexpr double half_x = 0.02, half_y = 0.05, half_z = 0.03, box_mass = 0.3;  // a 4 x 10 x 6 cm box
const char* const finger_names[5] = {"thumb", "index", "long", "ring", "little"};
constexpr double duration = 5.0;  // s

struct Phase {
  const char* name;
  double begin, end;
};
constexpr Phase phases[] = {{"close", 0.0, 0.7}, {"lift", 0.7, 1.5},     {"hold", 1.5, 2.2},
                            {"shake", 2.2, 3.4}, {"set down", 3.4, 4.2}, {"let go", 4.2, 5.0}};
constexpr int phase_count = 6;
int phase_at(double t) {
  for (int i = 0; i < phase_count; ++i)
    if (t < phases[i].end) return i;
  return phase_count - 1;
}

using haptic_session::ramp;
// The box's rest position on the table, and where the script carries it.
V3 start_position() { return V3(-0.15, 0, 0.03); }
V3 object_path(double t) {
  V3 p = start_position();
  p.z() += 0.15 * (ramp(t, 0.7, 1.5) - ramp(t, 3.4, 4.2));             // lift 15 cm, set down
  const double shake = ramp(t, 2.2, 2.45) * (1 - ramp(t, 3.15, 3.4));  // 4 Hz, 1.5 cm
  p.z() += 0.015 * shake * std::sin(2 * 3.141592653589793 * 4 * (t - 2.2));
  return p;
}
// Hand closure: 1 = closed on the box, 0 = open.
double closure(double t) { return ramp(t, 0.15, 0.6) * (1 - ramp(t, 4.3, 4.7)); }

// The scene: grip's hand welded to its tracker target, a table (top at z = 0, edge at x = 0)
// and the box on it. Skin on a grippy box: mu = 1.5.
std::string scene_xml(const grip::HandDimensions<double>& dims, const Eigen::Isometry3d& wrist) {
  grip::mujoco::HandMjcf o;
  o.model = "grip_hand_box";
  o.wrist = wrist;
  o.servo_gain = 2.0;
  o.condim = 3;
  o.friction = 1.5;
  const V3 p = start_position();
  char box[400];
  std::snprintf(box, sizeof box,
                "<body name=\"box\" pos=\"%.6f %.6f %.6f\"><freejoint/>"
                "<geom type=\"box\" size=\"%g %g %g\" mass=\"%g\" rgba=\"0.8 0.5 0.2 1\"/></body>",
                p.x(), p.y(), p.z(), half_x, half_y, half_z, box_mass);
  o.worldbody = std::string("<geom name=\"table\" type=\"box\" pos=\"-0.4 0 -0.375\" size=\"0.4 0.5 0.375\"/>") + box;
  o.extra = "<option cone=\"elliptic\" impratio=\"10\"/>";
  std::string xml;
  return grip::mujoco::hand_mjcf(dims, o, xml) == grip::Status::Ok ? xml : std::string();
}

struct Sample {
  double t, box_z, grip_sum_z, mujoco_sum_z, weight;
  int phase, contacts;
  bool ok;
  std::array<double, 5> grip{}, mujoco{};  // |force| each finger feels (N)
};

void write_svg(const std::string& path, const std::vector<Sample>& samples) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return;
  const double W = 900, H = 520, left = 60, right = 20, top = 30, panel = 200, gap = 50;
  const double t_end = samples.empty() ? 1 : samples.back().t;
  const char* colours[5] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::fprintf(f,
               "<svg xmlns='http://www.w3.org/2000/svg' width='%.0f' height='%.0f' font-family='sans-serif' "
               "font-size='12'>\n<rect width='100%%' height='100%%' fill='white'/>\n",
               W, H);
  const auto x_of = [&](double t) { return left + (W - left - right) * t / t_end; };
  // Panel 1: each finger's felt force, grip (solid) and MuJoCo (dotted).
  double fmax = 1;
  for (const Sample& s : samples)
    for (int k = 0; k < 5; ++k)
      fmax = std::max({fmax, s.grip[static_cast<std::size_t>(k)], s.mujoco[static_cast<std::size_t>(k)]});
  const auto y1 = [&](double v) { return top + panel * (1 - v / fmax); };
  std::fprintf(f,
               "<text x='%.0f' y='18'>force each finger feels (N): grip (solid), MuJoCo's contact forces (dotted); max "
               "%.1f N</text>\n",
               left, fmax);
  for (int k = 0; k < 5; ++k)
    for (int which = 0; which < 2; ++which) {
      std::fprintf(f, "<polyline fill='none' stroke='%s' stroke-width='1.2'%s points='", colours[k],
                   which ? " stroke-dasharray='2,2'" : "");
      for (std::size_t i = 0; i < samples.size(); i += 10) {
        const Sample& s = samples[i];
        std::fprintf(f, "%.1f,%.1f ", x_of(s.t),
                     y1(which ? s.mujoco[static_cast<std::size_t>(k)] : s.grip[static_cast<std::size_t>(k)]));
      }
      std::fprintf(f, "'/>\n");
    }
  for (int k = 0; k < 5; ++k)
    std::fprintf(f, "<text x='%.0f' y='%.0f' fill='%s'>%s</text>\n", W - right - 60, top + 15 + 15 * k, colours[k],
                 finger_names[k]);
  // Panel 2: the vertical force the whole hand feels against -m g.
  const double top2 = top + panel + gap;
  // From -2 m g to +m g: while the box is on the table the hand also feels the table's push
  // through it, clipped here to the panel.
  const double mg = box_mass * 9.81, zmin = -2 * mg, zmax = mg;
  const auto y2 = [&](double v) { return top2 + panel * (zmax - std::clamp(v, zmin, zmax)) / (zmax - zmin); };
  std::fprintf(f,
               "<text x='%.0f' y='%.0f'>vertical force the hand feels (N): grip (black), MuJoCo (grey dotted), -m g "
               "(red)</text>\n",
               left, top2 - 8);
  for (const double v : {zmin, -mg, 0.0, zmax})
    std::fprintf(f, "<text x='%.0f' y='%.1f' text-anchor='end' font-size='10'>%.2f</text>\n", left - 4, y2(v) + 3, v);
  std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='#ddd'/>\n", left, W - right, y2(0), y2(0));
  std::fprintf(f, "<line x1='%.0f' x2='%.0f' y1='%.1f' y2='%.1f' stroke='red' stroke-dasharray='4,3'/>\n", left,
               W - right, y2(-box_mass * 9.81), y2(-box_mass * 9.81));
  for (int which = 0; which < 2; ++which) {
    std::fprintf(f, "<polyline fill='none' stroke='%s' stroke-width='1.2'%s points='", which ? "#888" : "black",
                 which ? " stroke-dasharray='2,2'" : "");
    for (std::size_t i = 0; i < samples.size(); i += 5)
      std::fprintf(f, "%.1f,%.1f ", x_of(samples[i].t), y2(which ? samples[i].mujoco_sum_z : samples[i].grip_sum_z));
    std::fprintf(f, "'/>\n");
  }
  for (const Phase& ph : phases) {
    std::fprintf(f, "<line x1='%.1f' x2='%.1f' y1='%.0f' y2='%.0f' stroke='#ccc'/>\n", x_of(ph.begin), x_of(ph.begin),
                 top, top2 + panel);
    std::fprintf(f, "<text x='%.1f' y='%.0f' font-size='10'>%s</text>\n", x_of(ph.begin) + 2, top2 + panel + 14,
                 ph.name);
  }
  std::fprintf(f, "<text x='%.0f' y='%.0f'>time (s), 0 to %.1f</text>\n</svg>\n", W / 2 - 40, H - 8, t_end);
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = argc > 1 ? std::string(argv[1]) + "/" : std::string();
  grip::HandDimensions<double> dims = grip::HandDimensions<double>::standard();
  // As in example 6's session: the thumb's CMC under the long finger, so that the thumb
  // opposes the fingers across the box.
  dims.thumb_cmc.y() = -0.005;
  const double L = dims.hand_length;
  // Palm down over the box's top face (3 mm into it), the box under the proximal phalanges.
  const V3 offset(0.10, 0, -(half_z + 0.055 * L - 0.003));
  const auto wrist_at = [&](double t) {
    Eigen::Isometry3d w = Eigen::Isometry3d::Identity();
    w.translation() = object_path(t) - offset;
    return w;
  };
  const std::string xml = scene_xml(dims, wrist_at(0));
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("grip_mujoco_hand_" + std::to_string(::getpid()) + ".xml");
  {
    std::ofstream out(path);
    out << xml;
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.string().c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  if (!m) {
    std::printf("MuJoCo could not load the scene: %s\n", error);
    return 1;
  }
  mjData* d = mj_makeData(m);
  const int target = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "hand_target")];

  // The glove: the whole hand closing past the box (the servos squeeze it, kp times the
  // angle left), the thumb's CMC abducted to oppose the fingers.
  grip::HandJoints<double> closed = grip::HandJoints<double>::Zero();
  closed(1) = 1.0;
  closed(2) = 0.6;
  closed(3) = 0.6;
  for (int f = 1; f < 5; ++f) {
    closed(4 * f + 1) = 1.2;
    closed(4 * f + 2) = 1.5;
    closed(4 * f + 3) = 1.0;
  }

  grip::mujoco::Adapter<grip::HardFinger, double, 96> adapter;
  const auto names = grip::mujoco::grip_hand_body_names();
  grip::mujoco::AdapterSettings<double> settings;
  for (auto& row : settings.contact.stiffness) row.fill(1.5e4);  // K_i (N/m), as example 6's session
  if (adapter.bind(m, "box", names.data(), static_cast<int>(names.size()), settings) != grip::Status::Ok) {
    std::printf("bind: %s\n", grip::mujoco::to_string(adapter.problem()));
    return 1;
  }
  const int box = adapter.object();
  const double dt = m->opt.timestep;
  const int steps = static_cast<int>(std::lround(duration / dt));
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(steps));
  grip::FeltForces<double> felt;
  int failed = 0, held_frames = 0, hold_window = 0, slipping = 0, solved = 0;
  double worst_sum = 0;        // largest |grip's felt sum - MuJoCo's| over the solved steps (N)
  double worst_imbalance = 0;  // largest |m a - the forces MuJoCo applies| on the box (N)
  double worst_beyond = 0;     // largest |grip's felt sum - MuJoCo's| beyond that imbalance (N)
  std::vector<double> m_qacc(static_cast<std::size_t>(m->nv));
  const int box_dof = m->jnt_dofadr[m->body_jntadr[box]];
  for (int i = 0; i < steps; ++i) {
    const double t = i * dt;
    const Eigen::Isometry3d w = wrist_at(t);
    for (int k = 0; k < 3; ++k) d->mocap_pos[3 * target + k] = w.translation()(k);
    const double c = closure(t);
    for (int j = 0; j < grip::hand_dof_count; ++j) d->ctrl[j] = c * closed(j);
    mj_step(m, d);
    Sample s{};
    s.t = t;
    s.phase = phase_at(t);
    s.box_z = d->xipos[3 * box + 2];
    const grip::Status up = adapter.update(m, d);
    const grip::Status st =
        adapter.solve([](const auto& g, const auto& x) { return grip::solve_constrained(g, x); }, felt);
    s.ok = st == grip::Status::Ok;
    s.contacts = adapter.grasp().size();
    // Failed: MuJoCo's state could not be read. A grasp that cannot hold inside the friction
    // cones (Infeasible) is an answer: the hand would slip.
    if (up != grip::Status::Ok) ++failed;
    slipping += s.contacts > 0 && st == grip::Status::Infeasible ? 1 : 0;
    const Eigen::Vector3d com(d->xipos + 3 * box);
    std::array<Eigen::Vector3d, 5> g{}, mj{};
    for (auto& v : g) v.setZero();
    for (auto& v : mj) v.setZero();
    for (int k = 0; k < grip::hand_body_count; ++k)
      g[static_cast<std::size_t>(grip::phalanx_finger(k))] += felt.force[static_cast<std::size_t>(k)];
    for (int n = 0; n < adapter.grasp().size(); ++n) {
      const grip::Wrench<double> on_box = grip::mujoco::contact_wrench_on(m, d, adapter.mujoco_contact(n), box, com);
      mj[static_cast<std::size_t>(grip::phalanx_finger(adapter.grip_body(n)))] -= on_box.head<3>();
    }
    Eigen::Vector3d gs = Eigen::Vector3d::Zero(), ms = Eigen::Vector3d::Zero();
    for (int f = 0; f < 5; ++f) {
      s.grip[static_cast<std::size_t>(f)] = g[static_cast<std::size_t>(f)].norm();
      s.mujoco[static_cast<std::size_t>(f)] = mj[static_cast<std::size_t>(f)].norm();
      gs += g[static_cast<std::size_t>(f)];
      ms += mj[static_cast<std::size_t>(f)];
    }
    if (s.ok && adapter.ignored() == 0) {
      // MuJoCo's imbalance on the box: the free joint's translational rows of
      // M qacc + bias - passive - applied - actuator - constraint (world axes, N).
      mj_mulM(m, d, m_qacc.data(), d->qacc);
      Eigen::Vector3d imbalance;
      for (int k = 0; k < 3; ++k) {
        const int j = box_dof + k;
        imbalance(k) = m_qacc[static_cast<std::size_t>(j)] + d->qfrc_bias[j] - d->qfrc_passive[j] - d->qfrc_applied[j] -
                       d->qfrc_actuator[j] - d->qfrc_constraint[j];
      }
      worst_sum = std::max(worst_sum, (gs - ms).norm());
      worst_imbalance = std::max(worst_imbalance, imbalance.norm());
      worst_beyond = std::max(worst_beyond, (gs - ms).norm() - imbalance.norm());
      ++solved;
    }
    s.grip_sum_z = gs.z();
    s.mujoco_sum_z = ms.z();
    samples.push_back(s);
    // Held: in the air (2 cm above the table) from the end of the lift to the release.
    if (t >= 1.5 && t < 3.4) {
      ++hold_window;
      held_frames += s.box_z > half_z + 0.02 ? 1 : 0;
    }
  }

  std::printf("grip's whole hand in MuJoCo %s: a %.0f g box, %d steps of %.0f ms\n", mj_versionString(), 1e3 * box_mass,
              steps, 1e3 * dt);
  std::printf("mean force each finger feels per phase (N): grip / MuJoCo\n%-9s", "phase");
  for (const char* n : finger_names) std::printf(" %15s", n);
  std::printf(" %9s\n", "contacts");
  for (int p = 0; p < phase_count; ++p) {
    std::array<double, 5> gm{}, mm{};
    double contacts = 0;
    int count = 0;
    for (const Sample& s : samples)
      if (s.phase == p) {
        for (std::size_t f = 0; f < 5; ++f) gm[f] += s.grip[f], mm[f] += s.mujoco[f];
        contacts += s.contacts;
        ++count;
      }
    std::printf("%-9s", phases[p].name);
    for (std::size_t f = 0; f < 5; ++f) std::printf("   %5.2f / %5.2f", gm[f] / count, mm[f] / count);
    std::printf(" %9.1f\n", contacts / count);
  }
  std::printf("box held in the air through lift, hold and shake: %d of %d steps\n", held_frames, hold_window);
  const Sample& down = samples[static_cast<std::size_t>(std::lround(phases[4].end / dt)) - 1];
  std::printf("set down: the box's centre %.1f mm above where it started\n", 1e3 * (down.box_z - start_position().z()));
  std::printf("steps solved Ok: %d; infeasible (the grasp would slip): %d; failed: %d\n", solved, slipping, failed);
  std::printf("felt sum, grip against MuJoCo's hand contact forces: at most %.2e N apart\n", worst_sum);
  std::printf("MuJoCo's own imbalance on the box: at most %.2e N; the felt sums' gap beyond it: at most %.2e N\n",
              worst_imbalance, std::max(worst_beyond, 0.0));
  std::ofstream csv(dir + "mujoco_hand.csv");
  csv << "t,phase,box_z,contacts,ok,grip_thumb,grip_index,grip_long,grip_ring,grip_little,mujoco_thumb,mujoco_index,"
         "mujoco_long,mujoco_ring,mujoco_little,grip_sum_z,mujoco_sum_z\n";
  for (const Sample& s : samples) {
    csv << s.t << ',' << phases[s.phase].name << ',' << s.box_z << ',' << s.contacts << ',' << s.ok;
    for (double v : s.grip) csv << ',' << v;
    for (double v : s.mujoco) csv << ',' << v;
    csv << ',' << s.grip_sum_z << ',' << s.mujoco_sum_z << '\n';
  }
  write_svg(dir + "mujoco_hand.svg", samples);
  std::printf("wrote %smujoco_hand.csv and %smujoco_hand.svg\n", dir.c_str(), dir.c_str());
  mj_deleteData(d);
  mj_deleteModel(m);
  return held_frames == hold_window && failed == 0 && worst_beyond < 1e-6 ? 0 : 1;
}
