// The paper's Table 1 cylindrical power grip: a 0.4 kg cylinder (radius 35 mm, axis
// vertical) held by the twelve phalanges of the four fingers, opposed by the thumb and the
// palm. Solves min F2 s.t. equilibrium (the paper's section 5) for the weight alone and for a
// shake, and prints what each phalanx must feel (-f_i) and how close it is to slipping.
#include <cmath>
#include <cstdio>

#include <grip/grip.hpp>

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double radius = 0.035;     // m
constexpr double mass = 0.4;         // kg
constexpr double grip_force = 30.0;  // N: K dr summed over the hand, scaled by each d_i (eq. 8)
constexpr double mu = 0.8;           // skin on a dry cylinder

constexpr int palm = 5;  // Site::finger of the palm

struct Site {
  const char* name;
  double azimuth_deg;  // around the axis; the palm is at 180 degrees
  double height;       // m along the axis
  int finger;          // grip::Finger, or `palm`
  grip::Phalanx phalanx;
};

// Four fingers wrap from the palm around the far side (proximal, middle, distal at 110, 40,
// -30 degrees), index highest; the thumb wraps the other way; the palm pushes at 180 degrees.
// Each site's share d_i is the cylindrical power grip's (grasp_type.hpp): Table 1 for the
// fingers, grip's choice for the thumb and the palm (Table 1 gives none), which oppose them.
using P = grip::Phalanx;
const Site sites[] = {
    {"index proximal", 110, 0.030, 1, P::Proximal},  {"index middle", 40, 0.030, 1, P::Middle},
    {"index distal", -30, 0.030, 1, P::Distal},      {"long proximal", 110, 0.010, 2, P::Proximal},
    {"long middle", 40, 0.010, 2, P::Middle},        {"long distal", -30, 0.010, 2, P::Distal},
    {"ring proximal", 110, -0.010, 3, P::Proximal},  {"ring middle", 40, -0.010, 3, P::Middle},
    {"ring distal", -30, -0.010, 3, P::Distal},      {"little proximal", 110, -0.030, 4, P::Proximal},
    {"little middle", 40, -0.030, 4, P::Middle},     {"little distal", -30, -0.030, 4, P::Distal},
    {"thumb proximal", -150, 0.035, 0, P::Proximal}, {"thumb distal", -105, 0.040, 0, P::Distal},
    {"palm", 180, 0.000, palm, P::Proximal},
};
constexpr int n = sizeof(sites) / sizeof(sites[0]);

void report(const char* title, const grip::Grasp<n>& grasp, const grip::Wrench<double>& w_ext) {
  const auto sol = grip::solve_range_space(grasp, w_ext);
  const auto check = grip::solve_kkt(grasp, w_ext);  // the paper's method, for comparison
  std::printf(
      "\n%s\n  w_ext = [%.2f %.2f %.2f | %.3f %.3f %.3f]  status %s, residual %.1e, "
      "|range-space - KKT| = %.1e\n",
      title, w_ext(0), w_ext(1), w_ext(2), w_ext(3), w_ext(4), w_ext(5), grip::to_string(sol.status), sol.residual,
      (sol.forces - check.forces).norm());
  std::printf("  %-16s %8s %8s %8s %10s  %s\n", "phalanx", "s_i (N)", "f_n (N)", "|f_t| N", "|f_t|/mu f_n",
              "felt by the hand -f (N)");
  for (int i = 0; i < n; ++i) {
    const auto& c = grasp.contact(i);
    const grip::Vector3<double> f = sol.forces.segment<3>(3 * i);
    const double fn = f.dot(c.normal);
    const double ft = (f - fn * c.normal).norm();
    const double ratio = fn > 0 ? ft / (c.friction * fn) : 1e9;
    std::printf("  %-16s %8.2f %8.2f %8.2f %10.2f%s  [%6.2f %6.2f %6.2f]\n", sites[i].name, c.squeeze, fn, ft, ratio,
                ratio > 1 ? " SLIP" : "     ", -f.x(), -f.y(), -f.z());
  }
}

}  // namespace

int main() {
  constexpr auto table = grip::contribution_table<double>(grip::GraspType::CylindricalPower);
  grip::Grasp<n> grasp;
  for (int i = 0; i < n; ++i) {
    const Site& site = sites[i];
    const double share = site.finger == palm ? table.palm : table(static_cast<grip::Finger>(site.finger), site.phalanx);
    const double a = site.azimuth_deg * pi / 180.0;
    grip::Contact<double> c;
    c.position << radius * std::cos(a), radius * std::sin(a), site.height;
    c.normal << -std::cos(a), -std::sin(a), 0.0;  // into the cylinder
    c.friction = mu;
    c.squeeze = share * grip_force;
    if (grasp.set(i, c) != grip::Status::Ok) {
      std::printf("bad contact %d\n", i);
      return 1;
    }
  }
  std::printf("Cylindrical power grip (paper's Table 1): %d contacts on a %.0f mm cylinder of %.1f kg\n", n,
              radius * 1e3, mass);

  const grip::Vector3<double> g(0, 0, -9.81);
  grip::Wrench<double> w = grip::Wrench<double>::Zero();
  w.head<3>() = mass * g;  // gravity: the only external wrench
  report("1. holding still: the weight", grasp, w);

  const grip::Vector3<double> a(6.0, 0.0, 15.0);  // a shake: up and towards the finger tips
  w.head<3>() = mass * g - mass * a;              // inertial term -m a joins gravity
  report("2. shaking: weight plus inertia -m a, a = (6, 0, 15) m/s^2", grasp, w);

  grip::Wrench<double> tilt = grip::Wrench<double>::Zero();
  tilt.head<3>() = mass * g;
  tilt(4) = 0.15;  // a collision applies 0.15 N m about y
  report("3. a knock: weight plus a moment of 0.15 N m about y", grasp, tilt);
  return 0;
}
