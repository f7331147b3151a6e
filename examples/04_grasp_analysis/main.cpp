// Textbook grasp analysis: three classic grasps, one table of metrics.
//   two soft fingers pinching a box, three hard fingers on a disc, the paper's Table 1
//   cylindrical power grip (four fingers x three phalanges against thumb and palm).
#include <cmath>
#include <cstdio>

#include <grip/analysis/batch.hpp>
#include <grip/analysis/internal_forces.hpp>
#include <grip/analysis/max_wrench.hpp>
#include <grip/hand/squeeze.hpp>

namespace {

constexpr double kPi = 3.141592653589793;

grip::Contact<double> contact(const grip::Vector3<double>& r, const grip::Vector3<double>& a, double mu, double mu_t,
                              double squeeze) {
  grip::Contact<double> c;
  c.position = r;
  c.normal = a.normalized();
  c.friction = mu;
  c.torsional_friction = mu_t;
  c.squeeze = squeeze;
  return c;
}

template <class GraspT>
void row(const char* name, const GraspT& g, double rho) {
  grip::BatchSettings<double> s;
  s.lever_length = rho;
  s.epsilon_linf = true;
  static grip::EpsilonWorkspace<double> ws;  // 10.6 MB: off the stack
  const auto m = grip::evaluate_grasp<8>(g, s, ws);
  grip::Wrench<double> down = grip::Wrench<double>::Zero();
  down(2) = -1.0;  // gravity-like load
  const auto lift = grip::max_resistible_wrench(g, down, 10.0);
  const auto sq = grip::squeeze_split(g);
  std::printf("%-26s %3d %9.4f %9.3g %9.4f %7s %8.4f %8.4f %8.4f %8.3f %6.3f\n", name, g.size(), m.quality.sigma_min,
              m.quality.volume, m.quality.isotropy, m.closure ? "yes" : "no", m.closure_margin, m.epsilon_l1.epsilon,
              m.epsilon_linf.epsilon, lift.scale, sq.kept_fraction);
}

}  // namespace

int main() {
  using V = grip::Vector3<double>;
  const double rho = 0.05;  // torque scale: moments compared as forces at 5 cm
  std::printf(
      "torque scale rho = %.3f m; epsilon with 8-sided pyramids; lift = largest -z load (N)\n"
      "resisted with at most 10 N total normal force; kept = share of the F2 squeeze that is internal\n\n",
      rho);
  std::printf("%-26s %3s %9s %9s %9s %7s %8s %8s %8s %8s %6s\n", "grasp", "n", "sigmin", "volume", "isotropy",
              "closure", "margin", "eps_L1", "eps_Linf", "lift N", "kept");

  // 1. Two soft fingers pinching a 6 cm box on opposite faces (mu 0.8, mu_t 5 mm).
  grip::Grasp<2, grip::SoftFinger> box;
  (void)box.set(0, contact(V(0.03, 0, 0), V(-1, 0, 0), 0.8, 0.005, 5.0));
  (void)box.set(1, contact(V(-0.03, 0, 0), V(1, 0, 0), 0.8, 0.005, 5.0));
  row("two soft fingers, box", box, rho);

  // 2. Three hard fingers at 120 degrees on the rim of a 4 cm disc (mu 0.5).
  grip::Grasp<3, grip::HardFinger> disc;
  for (int i = 0; i < 3; ++i) {
    const double t = 2 * kPi / 3 * i;
    (void)disc.set(
        i, contact(V(0.04 * std::cos(t), 0.04 * std::sin(t), 0), V(-std::cos(t), -std::sin(t), 0), 0.5, 0.0, 3.0));
  }
  row("three hard fingers, disc", disc, rho);

  // 3. Table 1 power grip on a cylinder (radius 2 cm, axis y): 12 finger phalanges on one
  // side spread along the axis, each squeezing with s = d K dr (K = 2000 N/m, dr = 5 mm),
  // and the thumb plus palm opposite as two contacts carrying the balancing squeeze.
  grip::Grasp<grip::Dynamic, grip::HardFinger, double, 16> power;
  const auto table = grip::cylindrical_power_grip<double>();
  const double R = 0.02, K = 2000.0, dr = 0.005;
  double total = 0;
  for (int f = 1; f <= 4; ++f) {
    for (int p = 0; p < 3; ++p) {
      const double d = table(static_cast<grip::Finger>(f), static_cast<grip::Phalanx>(p));
      const double ang = kPi / 2 + (p - 1) * 0.7;  // phalanges wrap around the cylinder
      const double y = 0.03 - 0.02 * (f - 1);      // fingers side by side along the axis
      const V out(std::cos(ang), 0, std::sin(ang));
      (void)power.add(contact(R * out + V(0, y, 0), -out, 0.6, 0.0, grip::squeeze(d, K, dr)));
      total += grip::squeeze(d, K, dr);
    }
  }
  (void)power.add(contact(V(0, 0.02, -R), V(0, 0, 1), 0.6, 0.0, 0.5 * total));   // thumb
  (void)power.add(contact(V(0, -0.02, -R), V(0, 0, 1), 0.6, 0.0, 0.5 * total));  // palm
  row("Table 1 power grip", power, rho);
  return 0;
}
