// net_wrench_vector_command: hand-solved cases, the optimality conditions of the ball-constrained
// problem on random hands against a problem set up here from the file comment's definition, a
// second method (projected gradient), bad input and no heap; VectorForces with net_wrench.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/net_wrench_vector.hpp>

#include "support/allocation_counter.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace net_wrench_vector_tests {
using namespace grip;
using V3 = Vector3<double>;
constexpr int m = hand_phalanx_count;
using X = Eigen::Matrix<double, 3 * m, 1>;  // the 14 forces stacked

struct Input {
  std::array<V3, hand_body_count> force{}, point{};
  std::array<bool, hand_body_count> touch{};
  std::array<double, m> limit{};
  Input() {
    force.fill(V3::Zero());
    point.fill(V3::Zero());
    limit.fill(10.0);
  }
  NetWrenchVectorCommand<double> solve() const { return net_wrench_vector_command(force, point, touch, limit); }
};

// The problem, written out here: 1/2 |T A F - T w*|^2 + 1/2 eps |F - F0|^2 over |F_k| <= c_k.
struct Problem {
  Eigen::Matrix<double, 6, 3 * m> ta;
  Wrench<double> tw;
  X f0;
  std::array<double, m> c{};
  double eps{0};
  explicit Problem(const Input& in) {
    V3 o = V3::Zero();
    int n = 0;
    for (int b = 0; b < hand_body_count; ++b)
      if (in.touch[size_t(b)]) o += in.point[size_t(b)], ++n;
    if (n > 0) o /= n;
    double lever = 0.01;
    for (int b = 0; b < hand_body_count; ++b)
      if (in.touch[size_t(b)]) lever = std::max(lever, (in.point[size_t(b)] - o).norm());
    Wrench<double> want = Wrench<double>::Zero();
    for (int b = 0; b < hand_body_count; ++b) {
      want.head<3>() += in.force[size_t(b)];
      want.tail<3>() += (in.point[size_t(b)] - o).cross(in.force[size_t(b)]);
    }
    tw = want;
    tw.tail<3>() /= lever;
    double bmax = 1;
    for (int k = 0; k < m; ++k) {
      const size_t i = size_t(k);
      c[i] = in.touch[i] ? in.limit[i] : 0.0;
      for (int a = 0; a < 3; ++a) {
        Wrench<double> col;
        col << V3::Unit(a), (in.point[i] - o).cross(V3::Unit(a)) / lever;
        ta.col(3 * k + a) = col;
      }
      const double nf = in.force[i].norm();
      f0.segment<3>(3 * k) = nf > c[i] ? V3(in.force[i] * (c[i] / nf)) : in.force[i];
      if (c[i] > 0) bmax = std::max(bmax, 1 + (in.point[i] - o).squaredNorm() / (lever * lever));
    }
    eps = 1e-6 * bmax;
  }
  double cost(const X& f) const { return 0.5 * (ta * f - tw).squaredNorm() + 0.5 * eps * (f - f0).squaredNorm(); }
  X gradient(const X& f) const { return ta.transpose() * (ta * f - tw) + eps * (f - f0); }
  X project(X f) const {
    for (int k = 0; k < m; ++k) {
      const double n = f.segment<3>(3 * k).norm();
      if (n > c[size_t(k)]) f.segment<3>(3 * k) *= c[size_t(k)] / n;
    }
    return f;
  }
};

X stacked(const std::array<V3, m>& a) {
  X x;
  for (int k = 0; k < m; ++k) x.segment<3>(3 * k) = a[size_t(k)];
  return x;
}

Input random_input(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), pos(0, 1);
  Input in;
  for (int b = 0; b < hand_body_count; ++b) {
    const size_t i = size_t(b);
    in.touch[i] = pos(rng) < 0.6;
    in.point[i] = 0.08 * V3(u(rng), u(rng), u(rng));
    in.force[i] = in.touch[i] ? V3(8 * u(rng), 8 * u(rng), 8 * u(rng)) : V3::Zero();
  }
  for (int k = 0; k < m; ++k) in.limit[size_t(k)] = 6 * pos(rng);
  return in;
}

TEST_CASE("3-D forces: two phalanges at one point, the one below its limit takes what the other cannot") {
  Input in;
  in.touch[2] = in.touch[3] = true;  // index proximal and middle, at the origin
  in.force[2] = V3(0, 6.4, 4.8);     // 8 N
  in.limit[2] = in.limit[3] = 5;
  const auto c = in.solve();
  REQUIRE(c.status == Status::Ok);
  // Hand-solved: F2 + F3 = (0, 6.4, 4.8) exactly, ties toward F2 = its own scaled to 5 N and
  // F3 = 0: F2 = 5/8 of it, F3 = 3/8 (to the tie-breaker's 1e-6 relative pull).
  CHECK((c.force[2] - V3(0, 4.0, 3.0)).norm() <= 1e-5);
  CHECK((c.force[3] - V3(0, 2.4, 1.8)).norm() <= 1e-5);
  CHECK(c.unrendered.norm() <= 1e-5);
  for (int k = 0; k < m; ++k)
    if (k != 2 && k != 3) CHECK(c.force[size_t(k)] == V3::Zero());  // out of contact: nothing
}

TEST_CASE("3-D forces: one phalanx within its limit renders its force, beyond it the rest is reported") {
  Input in;
  in.touch[4] = true;
  in.point[4] = V3(0.1, 0.02, 0);
  in.force[4] = V3(0, 3, 4);
  in.limit[4] = 10;
  auto c = in.solve();
  CHECK((c.force[4] - V3(0, 3, 4)).norm() <= 1e-12);
  CHECK(c.unrendered.norm() <= 1e-12);
  in.limit[4] = 2.5;  // half of 5 N
  c = in.solve();
  CHECK((c.force[4] - V3(0, 1.5, 2)).norm() <= 1e-9);
  CHECK(c.unrendered.head<3>().isApprox(V3(0, 1.5, 2), 1e-9));
  CHECK(c.point.isApprox(in.point[4]));
}

TEST_CASE("3-D forces on random hands: the optimality conditions hold, and no method does better") {
  std::mt19937 rng(57);
  double clip_total = 0, best_total = 0;
  int most = 0;
  for (int trial = 0; trial < 300; ++trial) {
    CAPTURE(trial);
    const Input in = random_input(rng);
    const auto c = in.solve();
    REQUIRE(c.status == Status::Ok);
    most = std::max(most, c.iterations);
    const Problem p(in);
    const X f = stacked(c.force);
    const X g = p.gradient(f);
    const double scale = (1 + p.tw.norm()) * (1 + *std::max_element(p.c.begin(), p.c.end()));
    const double tol = 1e-8 * scale;
    for (int k = 0; k < m; ++k) {
      const size_t i = size_t(k);
      const V3 fk = f.segment<3>(3 * k), gk = g.segment<3>(3 * k);
      CHECK(fk.norm() <= p.c[i] * (1 + 1e-12));  // within its ball
      if (p.c[i] == 0) continue;
      // KKT of min over the ball: g_k = 0 inside; g_k = -mu F_k, mu >= 0, on the sphere.
      if (fk.norm() < p.c[i] * (1 - 1e-9)) {
        CHECK(gk.norm() <= tol);
      } else {
        const double mu = -gk.dot(fk) / fk.squaredNorm();
        CHECK(mu >= -tol / p.c[i]);
        CHECK((gk + mu * fk).norm() <= tol);
      }
    }
    // A second method on every 20th hand: accelerated projected gradient (FISTA) from the
    // scaled forces, on the problem's Hessian and linear term formed here.
    if (trial % 20 == 0) {
      const Eigen::Matrix<double, 3 * m, 3 * m> h =
          p.ta.transpose() * p.ta + p.eps * Eigen::Matrix<double, 3 * m, 3 * m>::Identity();
      const X b = p.ta.transpose() * p.tw + p.eps * p.f0;
      const double step = 1.0 / h.norm();
      X x = p.f0, y = x;
      double t = 1;
      for (int it = 0; it < 2000; ++it) {
        const X next = p.project(y - step * (h * y - b));
        const double tn = 0.5 * (1 + std::sqrt(1 + 4 * t * t));
        y = next + ((t - 1) / tn) * (next - x);
        x = next;
        t = tn;
      }
      CHECK(p.cost(f) <= p.cost(x) + 1e-10 * (1 + p.cost(x)));
    }
    CHECK(p.cost(f) <= p.cost(p.f0) + 1e-12);  // never worse than scaling each on its own
    // The reported unrendered force is that of w* - A F.
    const Wrench<double> r = p.tw - p.ta * f;
    CHECK((r.head<3>() - c.unrendered.head<3>()).norm() <= 1e-9 * scale);
    clip_total += (p.ta * p.f0 - p.tw).norm();
    best_total += (p.ta * f - p.tw).norm();
  }
  MESSAGE("weighted net-wrench error summed: scaling ", clip_total, ", best ", best_total, "; most iterations ", most);
  CHECK(best_total < clip_total);
}

TEST_CASE("3-D forces: bad input gives InvalidInput and zero forces, with no heap") {
  Input in;
  in.touch[2] = true;
  in.force[2] = V3(0, 0, std::nan(""));
  auto c = in.solve();
  CHECK(c.status == Status::InvalidInput);
  CHECK(c.force[2] == V3::Zero());
  in.force[2] = V3(0, 0, 1);
  in.limit[5] = -1;
  CHECK(in.solve().status == Status::InvalidInput);
  in.limit[5] = std::numeric_limits<double>::infinity();
  CHECK(in.solve().status == Status::InvalidInput);
  std::mt19937 rng(8);
  const Input r = random_input(rng);
  grip_test::NoHeapScope scope;
  const auto d = r.solve();
  CHECK(scope.allocations() == 0);
  CHECK(d.status == Status::Ok);
}

TEST_CASE("VectorForces: scaling or the closest net wrench, and what each leaves unrendered") {
  std::mt19937 rng(93);
  for (int trial = 0; trial < 100; ++trial) {
    CAPTURE(trial);
    Input in = random_input(rng);
    FeltForces<double> felt;
    felt.force = in.force;
    felt.point = in.point;
    felt.in_contact = in.touch;
    VectorForces<double> device;
    device.limit = in.limit;
    device.fingertips_only = trial % 2 == 1;
    VectorForces<double>::Command scaled, best;
    REQUIRE(device.render(felt, HandPosture<double>{}, HandJoints<double>::Zero(), scaled) == Status::Ok);
    device.net_wrench = true;
    REQUIRE(device.render(felt, HandPosture<double>{}, HandJoints<double>::Zero(), best) == Status::Ok);
    // The device's phalanges: every one, or the distal ones only.
    for (int k = 0; k < m; ++k)
      if (device.fingertips_only && phalanx_kind(k) != Phalanx::Distal) in.limit[size_t(k)] = 0;
    const auto direct = in.solve();
    const auto w = felt_net_wrench(in.force, in.point, in.touch);
    Wrench<double> left = w.wrench;
    for (int k = 0; k < m; ++k) {
      const size_t i = size_t(k);
      CHECK((best.force[i] - direct.force[i]).norm() <= 1e-12 * (1 + direct.force[i].norm()));
      left.head<3>() -= scaled.force[i];
      left.tail<3>() -= (in.point[i] - w.point).cross(scaled.force[i]);
    }
    CHECK(best.unrendered.isApprox(direct.unrendered, 1e-12));
    CHECK((scaled.unrendered - left).norm() <= 1e-12 * (1 + left.norm()));
    const double lever2 = w.lever * w.lever;
    const auto weighted = [&](const Wrench<double>& x) {
      return x.head<3>().squaredNorm() + x.tail<3>().squaredNorm() / lever2;
    };
    CHECK(weighted(best.unrendered) <= weighted(scaled.unrendered) * (1 + 1e-9) + 1e-12);
  }
}

}  // namespace net_wrench_vector_tests
