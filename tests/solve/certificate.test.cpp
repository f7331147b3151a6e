// Certificates of grasps whose G has rank < 6 (include/grip/solve/detail/certificate.hpp,
// range_certificate): a load with a part outside G's range slips, proved in closed form, and
// solve_constrained ends Infeasible with that certificate, bounded or not, in float and double.
// Checked against a hand derivation (one fingertip under a twist about its normal) and against
// the certificate's definition evaluated here in double from the contacts' data.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <grip/grip.hpp>

#include "solve/constrained_support.hpp"
#include "support/equilibrium_norm.hpp"

using namespace grip;

namespace {

// G_i^T y of a hard finger at p: a force f there does work f.y_f + (p x f).y_m = f.(y_f + y_m x p).
Vector3<double> dual_of(const Contact<double>& c, const Wrench<double>& y) {
  return y.head<3>() + y.tail<3>().cross(c.position);
}

// The definition of ConstrainedSolution::certificate, in double: y.w_ext > 0, every unbounded
// contact's G_i^T y within `slack` (y.w_ext) / |w_ext|_L of its dual cone (as a margin), and the
// bounded contacts' deficit sum_i c_i max(0, -margin_i) below y.w_ext.
template <class GraspT>
bool certifies(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w, const Wrench<double>& y, double slack) {
  const Wrench<double> wd = w.template cast<double>();
  const double yw = y.dot(wd);
  if (!(yw > 0)) return false;
  const double wn = grip_test::norm_l(wd, grip_test::grasp_lever_length(g));
  double deficit = 0;
  for (int i = 0; i < g.size(); ++i) {
    const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
    const double m = grip_test::dual_margin(c, dual_of(c, y));
    if (c.max_normal_force < std::numeric_limits<double>::infinity()) {
      deficit += c.max_normal_force * std::max(0.0, -m);
    } else if (m < -slack * yw / wn * (1 + c.friction)) {
      return false;
    }
  }
  return deficit < yw;
}

Contact<double> fingertip(double mu, double bound = std::numeric_limits<double>::infinity()) {
  Contact<double> c;
  c.position = Vector3<double>(0, 0, -0.02);  // under the object's centre, pushing up
  c.normal = Vector3<double>(0, 0, 1);
  c.friction = mu;
  c.squeeze = 1;
  c.weight = 1;
  c.max_normal_force = bound;
  return c;
}

}  // namespace

TEST_CASE("One fingertip: a twist about its normal slips, a load along it is held") {
  // A force f at p = (0, 0, -r) has the moment p x f = (r f_y, -r f_x, 0): no moment about z. So
  // w = (0, 0, -F, 0, 0, tau) slips for every tau != 0, whatever the friction or the bound, and
  // the certificates are the y with G^T y = 0 (y_f = p x y_m) and y.w = tau y_mz > 0. With
  // tau = 0 the one balancing force is f = (0, 0, F) (its moment must vanish: f along p), inside
  // the cone; with a bound below F it slips too.
  for (const double bound : {std::numeric_limits<double>::infinity(), 25.0}) {
    Grasp<Dynamic, HardFinger, double, 4> g;
    g.add(fingertip(0.5, bound));
    for (const double tau : {1e-3, -0.2, 0.05}) {
      const Wrench<double> w = (Wrench<double>() << 0, 0, -4, 0, 0, tau).finished();
      const auto sol = solve_constrained(g, w);
      CAPTURE(bound);
      CAPTURE(tau);
      REQUIRE(sol.status == Status::Infeasible);
      const Wrench<double>& y = sol.certificate;
      CHECK(y(5) * tau > 0);
      CHECK(dual_of(g.contact(0), y).norm() <= 1e-9 * y.norm());
      CHECK(y.dot(w) > 0);
      CHECK(certifies(g, w, y, 1e-6));
      // The least-residual forces balance the load's force part: f = (0, 0, 4) is the only force
      // whose moment is zero, and the residual is the twist alone.
      CHECK(sol.forces(2) == doctest::Approx(4).epsilon(1e-5));
      CHECK(sol.residual == doctest::Approx(std::abs(tau)).epsilon(1e-5));
    }
    const Wrench<double> held = (Wrench<double>() << 0, 0, -4, 0, 0, 0).finished();
    const auto ok = solve_constrained(g, held);
    CHECK(ok.status == Status::Ok);
    CHECK(ok.forces(2) == doctest::Approx(4).epsilon(1e-9));
  }
  Grasp<Dynamic, HardFinger, double, 4> weak;
  weak.add(fingertip(0.5, 3.0));
  const Wrench<double> heavy = (Wrench<double>() << 0, 0, -4, 0, 0, 0).finished();
  const auto sol = solve_constrained(weak, heavy);
  REQUIRE(sol.status == Status::Infeasible);
  CHECK(certifies(weak, heavy, sol.certificate, 1e-6));
}

TEST_CASE_TEMPLATE("One or two fingertips under random loads: every solve decided, bounded or not", S, double, float) {
  // One fingertip (rank 3) or two (rank 5) at random points of a 4 cm sphere, under random loads
  // with and without moments and under loads that forces inside the cones balance (at most 5 N
  // each): Ok or Infeasible every time (never IterationLimit), each
  // certificate true to its definition, and a bound far above every force the loads need
  // (1000 N) changes no verdict.
  std::mt19937 rng(20261205u);
  std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 1);
  const double slack = double(ConstrainedSettings<S>{}.certificate_tolerance) * 4;
  int slips = 0, holds = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const int n = 1 + trial % 2;
    Grasp<Dynamic, HardFinger, S, 4> free, capped, weak;
    for (int i = 0; i < n; ++i) {
      Contact<S> c;
      const Vector3<double> p = 0.02 * Vector3<double>(u(rng), u(rng), u(rng));
      c.position = p.cast<S>();
      c.normal = (-p.normalized()).cast<S>();
      c.friction = S(0.3 + 0.7 * pos(rng));
      c.squeeze = S(2 * pos(rng));
      c.weight = S(1 + pos(rng));
      free.add(c);
      c.max_normal_force = S(1000);
      capped.add(c);
      c.max_normal_force = S(1 + 30 * pos(rng));
      weak.add(c);
    }
    Wrench<S> w;
    for (int j = 0; j < 6; ++j) w(j) = S(u(rng) * (j < 3 ? 5.0 : 0.1));
    if (trial % 4 == 2) w.template tail<3>().setZero();
    if (trial % 4 == 3) {  // a load the contacts balance: minus the wrench of forces inside their cones
      w.setZero();
      for (int i = 0; i < n; ++i) {
        const Contact<S>& ci = free.contact(i);
        const TangentBasis<S> t = TangentBasis<S>::from_normal(ci.normal);
        const S fn = S(0.5 + 4.5 * pos(rng));
        const Vector3<S> f = fn * (ci.normal + S(0.5) * ci.friction * (S(u(rng)) * t.t1 + S(u(rng)) * t.t2));
        w -= HardFinger::wrench(ci, f);
      }
    }
    const auto a = solve_constrained(free, w);
    const auto b = solve_constrained(capped, w);
    const auto c = solve_constrained(weak, w);
    CAPTURE(trial);
    for (const auto* s : {&a, &b, &c}) {
      REQUIRE((s->status == Status::Ok || s->status == Status::Infeasible));
      CHECK(s->forces.allFinite());
    }
    CHECK(b.status == a.status);
    if (a.status == Status::Infeasible) {
      ++slips;
      CHECK(certifies(free, w, a.certificate.template cast<double>(), slack));
      CHECK(certifies(capped, w, b.certificate.template cast<double>(), slack));
    } else {
      ++holds;
    }
    if (c.status == Status::Infeasible) CHECK(certifies(weak, w, c.certificate.template cast<double>(), slack));
    if (trial % 4 == 3) CHECK(a.status == Status::Ok);
  }
  CHECK(slips > 500);
  CHECK(holds >= 1500 / 4);
}
