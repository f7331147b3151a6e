// Friction-cone monitoring for the textbook (paper, section 5: conditions 4-5 are monitored).
//
// Part 1: a box pinched between two soft fingertips (two hard fingers could not resist a
// twist about the line joining them: rank 5). The held weight grows; for each load the
// optimal forces (range-space solver) are checked against the exact cones and the margins
// printed until the pinch slips; the resolution step then tells what the fingers transmit
// and the wrench left unbalanced on the box.
//
// Part 2: the power grip of the paper's Table 1 on a cylinder (radius 35 mm): 12 finger
// phalanges squeezing with Table 1's shares of the grip force, opposed by two thumb phalanges
// and the palm. As the held weight grows, which phalanges slip or separate first?
#include <cmath>
#include <cstdio>

#include <grip/grip.hpp>

namespace {

using S = double;

void pinch() {
  std::printf("== Two-finger pinch of a box (half-width 30 mm), soft fingers, mu = 0.6, mu_t = 5 mm\n");
  std::printf("   squeeze 5 N per finger; load = weight W (N) with its centre 10 mm off the grip axis\n\n");
  using G = grip::Grasp<2, grip::SoftFinger, S>;
  G g;
  for (int side = 0; side < 2; ++side) {
    grip::Contact<S> c;
    const S sx = side == 0 ? S(1) : S(-1);
    c.position = grip::Vector3<S>(sx * 0.03, 0, 0);
    c.normal = grip::Vector3<S>(-sx, 0, 0);
    c.friction = 0.6;
    c.torsional_friction = 0.005;
    c.squeeze = 5.0;
    if (g.set(side, c) != grip::Status::Ok) return;
  }
  std::printf("   W (N) | finger | f_n (N) | |f_t| (N) | m (N mm) | margin (N) | relative | mode\n");
  for (int step = 0; step <= 40; ++step) {
    const S weight = 0.25 * step;
    grip::Wrench<S> w = grip::Wrench<S>::Zero();
    w(2) = -weight;         // gravity
    w(3) = -0.01 * weight;  // (0, 10 mm, 0) x (0, 0, -W): moment about x
    const auto sol = grip::solve_range_space(g, w);
    const auto st = grip::monitor_grasp(g, sol.forces);
    for (int i = 0; i < 2; ++i) {
      const auto& cs = st.contact(i);
      std::printf("  %6.2f | %6d | %7.3f | %9.3f | %8.3f | %10.3f | %8.3f | %s\n", weight, i, cs.normal_force,
                  cs.tangential_force.norm(), 1000 * cs.moment, cs.margin, cs.relative_margin,
                  grip::to_string(cs.mode));
    }
    if (!st.stable) {
      const auto r = grip::resolve(g, sol.forces, st, w);
      std::printf("\n   The pinch slips at W = %.2f N (smallest margin %.3f N at finger %d).\n", weight, st.min_margin,
                  st.min_margin_index);
      std::printf(
          "   Kinetic friction transmitted, unbalanced wrench on the box: F = (%.3f, %.3f, %.3f) N,"
          " M = (%.4f, %.4f, %.4f) N m\n\n",
          r.unbalanced(0), r.unbalanced(1), r.unbalanced(2), r.unbalanced(3), r.unbalanced(4), r.unbalanced(5));
      return;
    }
  }
}

const char* finger_name(int f) {
  static const char* names[] = {"thumb", "index", "long", "ring", "little", "palm"};
  return names[f];
}
const char* phalanx_name(int p) {
  static const char* names[] = {"proximal", "middle", "distal"};
  return names[p];
}

void power_grip() {
  constexpr int n = 15;  // 12 finger phalanges, 2 thumb phalanges, 1 palm
  using G = grip::Grasp<n, grip::HardFinger, S>;
  const S radius = 0.035, mu = 0.5, grip_force = 40.0;
  const auto table = grip::cylindrical_power_grip<S>();
  const S pi = 3.141592653589793;
  G g;
  int finger[n], phalanx[n];
  int k = 0;
  // The cylinder's axis is z (vertical). The palm touches it at azimuth 180 degrees; the
  // fingers wrap round from the palm: proximal at -120, middle at -60, distal at 0 degrees;
  // index to little stacked from z = +30 mm to -30 mm. The thumb wraps the other way (120 and 60
  // degrees).
  auto add = [&](int f, int p, S azimuth_deg, S z, S squeeze) {
    const S a = azimuth_deg * pi / 180;
    const grip::Vector3<S> u(std::cos(a), std::sin(a), 0);
    grip::Contact<S> c;
    c.position = radius * u + grip::Vector3<S>(0, 0, z);
    c.normal = -u;
    c.friction = mu;
    c.squeeze = squeeze;
    finger[k] = f;
    phalanx[k] = p;
    (void)g.set(k++, c);
  };
  const S azimuth[3] = {-120, -60, 0};
  for (int f = 1; f <= 4; ++f)
    for (int p = 0; p < 3; ++p)
      add(f, p, azimuth[p], 0.03 - 0.02 * (f - 1),
          table(static_cast<grip::Finger>(f), static_cast<grip::Phalanx>(p)) * grip_force);
  // Thumb and palm squeeze chosen so that all squeezing forces balance (pure internal force):
  // the finger phalanges push with -sum d_p u(azimuth_p) F = (-0.381, 0.398) F in (x, y), which
  // the thumb phalanges (0.23 F each, along -u(120) and -u(60)) and the palm (0.381 F along +x)
  // cancel: 0.381 + 0.5 (0.23) - 0.5 (0.23) = 0.381, -0.866 (0.23 + 0.23) = -0.398.
  // Moments balance too when thumb and palm sit at the height of the fingers' squeeze centroid,
  // z = 5.2 mm (sum s_i z_i u_i = 0 for the finger phalanges' shares and heights).
  add(0, 0, 120, 0.0052, 0.23 * grip_force);   // thumb proximal
  add(0, 2, 60, 0.0052, 0.23 * grip_force);    // thumb distal
  add(5, 0, 180, 0.0052, 0.381 * grip_force);  // palm
  std::printf("== Table 1 power grip of a cylinder (radius 35 mm), mu = %.1f, grip force %.0f N\n", mu, grip_force);
  std::printf("   held weight W (N) | sliding | separating | smallest margin (N) | newly slipping or separating\n");
  bool was_bad[n] = {};
  int first_count = -1;
  for (int step = 0; step <= 60; ++step) {
    const S weight = 1.0 * step;
    grip::Wrench<S> w = grip::Wrench<S>::Zero();
    w(2) = -weight;
    const auto sol = grip::solve_range_space(g, w);
    const auto st = grip::monitor_grasp(g, sol.forces);
    if (!st.ok()) return;
    std::printf("   %18.1f | %7d | %10d | %19.3f |", weight, st.sliding_count, st.separating_count, st.min_margin);
    int newly = 0;
    for (int i = 0; i < n; ++i) {
      const bool bad = !st.is_sticking(i);
      if (bad && !was_bad[i]) {
        std::printf(" %s %s (%s)", finger_name(finger[i]), finger[i] == 5 ? "" : phalanx_name(phalanx[i]),
                    grip::to_string(st.mode(i)));
        ++newly;
      }
      was_bad[i] = bad;
    }
    std::printf("\n");
    if (newly > 0 && first_count < 0) first_count = newly;
    if (st.sliding_count + st.separating_count == n) break;
  }
  if (first_count > 0) std::printf("\n   %d contact(s) lose their grip first.\n", first_count);
}

}  // namespace

int main() {
  pinch();
  power_grip();
  return 0;
}
