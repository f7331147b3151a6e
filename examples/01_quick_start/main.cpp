// Quick start: three fingers hold a 0.5 kg ball. grip finds the contact forces closest to the
// fingers' squeeze that hold the ball, checks them against the friction cones, and then finds
// the best forces inside the cones. Exits 0 when every step succeeds.
#include <cmath>
#include <cstdio>

#include <grip/grip.hpp>

int main() {
  constexpr double pi = 3.14159265358979323846;
  grip::Grasp<3> grasp;  // 3 hard fingers (point contacts with friction), double, no heap
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * pi * i / 3.0;
    grip::Contact<double> c;
    c.position << 0.04 * std::cos(a), 0.04 * std::sin(a), 0.0;  // m, from the centre of mass
    c.normal = -c.position.normalized();                        // unit, INTO the object
    c.friction = 0.8;                                           // Coulomb mu
    c.squeeze = 2.0;                                            // N: how hard the finger presses
    if (grasp.set(i, c) != grip::Status::Ok) return 1;          // NaN, non-unit normal...: refused
  }

  // The external wrench ON the object, [force; moment about the centre of mass]: its weight.
  grip::Wrench<double> w_ext;
  w_ext << 0.0, 0.0, -0.5 * 9.81, 0.0, 0.0, 0.0;

  // The paper's optimum: forces x closest to the squeeze targets with G x + w_ext = 0.
  const auto sol = grip::solve_range_space(grasp, w_ext);
  // Does each finger stick inside its friction cone (the paper's eq. 4-5)?
  const auto modes = grip::classify_grasp(grasp, sol.forces);
  // The optimum with every force inside its exact friction cone.
  const auto exact = grip::solve_constrained(grasp, w_ext);

  std::printf("range space: %s, residual %.1e N; grasp %s\n", grip::to_string(sol.status), sol.residual,
              modes.stable ? "stable" : "slips");
  for (int i = 0; i < grasp.size(); ++i) {
    const grip::Vector3<double> f = sol.forces.segment<3>(3 * i);
    std::printf("  finger %d pushes [%6.3f %6.3f %6.3f] N and feels the opposite\n", i, f.x(), f.y(), f.z());
  }
  std::printf("inside the cones: %s, F2 = %.4f N^2\n", grip::to_string(exact.status), exact.objective);
  return sol.ok() && modes.ok() && exact.ok() ? 0 : 2;
}
