// A user's program: three fingers hold a 0.5 kg ball. Exits 0 when grip solves it.
#include <grip/grip.hpp>

#include <cmath>

int main() {
  grip::Grasp<3> grasp;
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / 3.0;
    grip::Contact<double> c;
    c.position << 0.04 * std::cos(a), 0.04 * std::sin(a), 0.0;
    c.normal = -c.position.normalized();
    c.friction = 0.8;
    c.squeeze = 2.0;
    if (grasp.set(i, c) != grip::Status::Ok) return 1;
  }
  grip::Wrench<double> w_ext;
  w_ext << 0, 0, -0.5 * 9.81, 0, 0, 0;
  const auto sol = grip::solve_range_space(grasp, w_ext);
  return sol.ok() && sol.residual < 1e-9 ? 0 : 2;
}
