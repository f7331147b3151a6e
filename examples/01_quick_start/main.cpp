// Quick start: three fingers hold a 0.5 kg ball. Exits 0 when every step succeeds.
#include <cmath>
#include <cstdio>

#include <grip/grip.hpp>

int main() {
  grip::Grasp<3> grasp;  // 3 hard fingers (point contacts with friction), double, no heap
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / 3.0;
    grip::Contact<double> c;
    c.position << 0.04 * std::cos(a), 0.04 * std::sin(a), 0.0;  // m, from the centre of mass
    c.normal = -c.position.normalized();                        // unit, into the object
    c.friction = 0.8;                                           // Coulomb mu
    c.squeeze = 2.0;                                            // N: how hard the finger presses
    if (grasp.set(i, c) != grip::Status::Ok) return 1;          // NaN, non-unit normal: refused
  }
  grip::Wrench<double> w_ext;  // on the object: [force; moment about the centre of mass]
  w_ext << 0.0, 0.0, -0.5 * 9.81, 0.0, 0.0, 0.0;

  // The paper's optimum: the forces closest to the squeeze s_i a_i that balance w_ext,
  // then its eq. 4-5: does each finger stick inside its friction cone?
  const auto sol = grip::solve_range_space(grasp, w_ext);
  const auto modes = grip::classify_grasp(grasp, sol.forces);
  std::printf("closest to the squeeze: %s, %d of 3 fingers slide\n", grip::to_string(sol.status), modes.sliding_count);
  // The optimum with every force inside its friction cone.
  const auto exact = grip::solve_constrained(grasp, w_ext);
  std::printf("inside the friction cones: %s\n", grip::to_string(exact.status));
  for (int i = 0; i < 3; ++i)  // f_i pushes on the ball; finger i feels -f_i
    std::printf("  finger %d pushes [%6.3f %6.3f %6.3f] N\n", i, exact.forces(3 * i), exact.forces(3 * i + 1),
                exact.forces(3 * i + 2));
  return sol.ok() && modes.ok() && exact.ok() ? 0 : 2;
}
