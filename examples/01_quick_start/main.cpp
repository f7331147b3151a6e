// Quick start: three fingers hold a 0.5 kg ball. grip finds the contact forces closest to the
// fingers' squeeze that hold the ball (the paper's optimum), checks them against the friction
// cones, and finds the best forces inside the cones. Exits 0 when every step succeeds.
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

  const auto print = [&](const grip::Grasp<3>::ForceVector& x) {
    for (int i = 0; i < grasp.size(); ++i)  // f_i pushes on the ball; finger i feels -f_i
      std::printf("  finger %d pushes [%6.3f %6.3f %6.3f] N\n", i, x(3 * i), x(3 * i + 1), x(3 * i + 2));
  };
  // The paper's optimum: the forces x closest to the targets s_i a_i with G x + w_ext = 0.
  const auto sol = grip::solve_range_space(grasp, w_ext);
  // The paper's eq. 4-5: does each finger stick inside its friction cone?
  const auto modes = grip::classify_grasp(grasp, sol.forces);
  std::printf("closest to the squeeze: %s, residual %.0e N, %d of 3 fingers slide\n", grip::to_string(sol.status),
              sol.residual, modes.sliding_count);
  print(sol.forces);
  // The optimum with every force inside its friction cone.
  const auto exact = grip::solve_constrained(grasp, w_ext);
  std::printf("inside the friction cones: %s, %d iterations\n", grip::to_string(exact.status), exact.iterations);
  print(exact.forces);
  return sol.ok() && modes.ok() && exact.ok() ? 0 : 2;
}
