// A grasp whose contacts cannot resist some wrench at all (two hard fingers: no moment about
// the line through them, rank(G) = 5), under a load with a small component along that
// direction: the instance a MuJoCo Allegro hand produced (grip.mujoco, the palm and one
// finger under a 100 g object). It must end Infeasible within the default bound, with a
// certificate checked here by its definition, not IterationLimit.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/grasp/grasp.hpp>
#include <grip/solve/solve_constrained.hpp>

using namespace grip;

TEST_CASE("solve_constrained: a load the contacts cannot resist at all is Infeasible within the bound") {
  Grasp<Dynamic, HardFinger, double, 4> g;
  const double p[2][3] = {{-1.9405508196872132e-03, 6.6777759638597293e-05, -1.9919597727070970e-02},
                          {2.5056276147797606e-02, 6.3167443467213323e-05, -9.8441745102534617e-03}};
  const double a[2][3] = {{1.7799304369402281e-06, -1.2683380692789884e-06, 9.9999999999761158e-01},
                          {-7.3003323867808845e-01, 2.1122024399895219e-05, 6.8341164021330614e-01}};
  const double s[2] = {0.2432455912714594, 0.13002259871510535};
  for (int i = 0; i < 2; ++i) {
    Contact<double> c;
    c.position = Vector3<double>(p[i][0], p[i][1], p[i][2]);
    c.normal = Vector3<double>(a[i][0], a[i][1], a[i][2]);
    c.friction = 0.7;
    c.squeeze = s[i];
    REQUIRE(g.add(c) == Status::Ok);
  }
  Wrench<double> w;
  w << 1.3865182383088503e-01, 1.5709742410670996e-03, -1.0162255946495355e+00, -3.5858037502742788e-05,
      1.6272868363466611e-03, -1.0376000697332261e-05;
  // The load's moment about the contacts' line, which no contact force can give.
  const Vector3<double> line = (g.contact(1).position - g.contact(0).position).normalized();
  const double unresisted = (w.tail<3>() - g.contact(0).position.cross(w.head<3>())).dot(line);
  REQUIRE(std::abs(unresisted) > 1e-7);  // N m: 5.4e-7
  const ConstrainedSettings<double> settings;
  const auto r = solve_constrained(g, w, settings);
  CHECK(r.status == Status::Infeasible);
  CHECK(r.iterations <= settings.max_iterations);
  // The certificate by definition: y . w_ext > 0, and for each contact G_i^T y = (v_n a + v_t)
  // in the dual cone |v_t| <= v_n / mu, within the documented slack.
  const Wrench<double>& y = r.certificate;
  const double yw = y.dot(w);
  CHECK(yw > 0);
  for (int i = 0; i < 2; ++i) {
    const Contact<double>& c = g.contact(i);
    const Vector3<double> v = HardFinger::wrench_transpose(c, y);
    const double vn = v.dot(c.normal), vt = (v - vn * c.normal).norm();
    CHECK(c.friction * vt - vn <= 2 * settings.certificate_tolerance * c.friction * yw);
  }
}
