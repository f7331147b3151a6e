// net_wrench_command: the phalanx pushes whose net wrench comes closest to the felt one, against
// hand-solved cases, the problem's optimality conditions (derived here from the documented
// problem), projected-gradient descent as a second method, and clipping.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <grip/pipeline/device_policy.hpp>
#include <grip/pipeline/net_wrench_command.hpp>

#include "support/allocation_counter.hpp"

// Named, not anonymous: the unity build puts several test files in one translation unit.
namespace net_wrench_command_tests {
using namespace grip;
using V3 = Vector3<double>;

struct Input {
  std::array<V3, hand_body_count> force{}, point{};
  std::array<bool, hand_body_count> touch{};
  std::array<V3, hand_phalanx_count> dir{};
  std::array<double, hand_phalanx_count> limit{};
  Input() {
    force.fill(V3::Zero());
    point.fill(V3::Zero());
    dir.fill(V3(0, 0, 1));
    limit.fill(10.0);
  }
  NetWrenchCommand<double> solve() const { return net_wrench_command(force, point, touch, dir, limit); }
};

/// The documented problem, written out here: A, w*, T, f_0, eps and the bounds.
struct Problem {
  Eigen::Matrix<double, 6, hand_phalanx_count> ta;  // T A
  Wrench<double> tw;                                // T w*
  Wrench<double> want;                              // w* (about o)
  Wrench<double> t;                                 // T's diagonal
  Eigen::Matrix<double, hand_phalanx_count, 1> f0, hi;
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
    want.setZero();
    for (int b = 0; b < hand_body_count; ++b) {
      want.head<3>() += in.force[size_t(b)];
      want.tail<3>() += (in.point[size_t(b)] - o).cross(in.force[size_t(b)]);
    }
    t = Wrench<double>::Ones();
    t.tail<3>() /= lever;
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const size_t i = size_t(k);
      Wrench<double> col;
      col << in.dir[i], (in.point[i] - o).cross(in.dir[i]);
      ta.col(k) = t.cwiseProduct(col);
      hi(k) = in.touch[i] ? in.limit[i] : 0.0;
      f0(k) = std::clamp(in.force[i].dot(in.dir[i]), 0.0, hi(k));
    }
    tw = t.cwiseProduct(want);
    eps = 1e-6 * std::max((ta.transpose() * ta).diagonal().maxCoeff(), 1.0);
  }
  double cost(const Eigen::Matrix<double, hand_phalanx_count, 1>& f) const {
    return 0.5 * (ta * f - tw).squaredNorm() + 0.5 * eps * (f - f0).squaredNorm();
  }
  Eigen::Matrix<double, hand_phalanx_count, 1> gradient(const Eigen::Matrix<double, hand_phalanx_count, 1>& f) const {
    return ta.transpose() * (ta * f - tw) + eps * (f - f0);
  }
};

Eigen::Matrix<double, hand_phalanx_count, 1> as_vector(const std::array<double, hand_phalanx_count>& a) {
  Eigen::Matrix<double, hand_phalanx_count, 1> v;
  for (int k = 0; k < hand_phalanx_count; ++k) v(k) = a[size_t(k)];
  return v;
}

Input random_input(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> pos(0, 1);
  Input in;
  for (int b = 0; b < hand_body_count; ++b) {
    const size_t i = size_t(b);
    in.touch[i] = pos(rng) < 0.6;
    in.point[i] = 0.08 * V3(u(rng), u(rng), u(rng));
    in.force[i] = in.touch[i] ? V3(8 * u(rng), 8 * u(rng), 8 * u(rng)) : V3::Zero();
  }
  for (int k = 0; k < hand_phalanx_count; ++k) {
    in.dir[size_t(k)] = V3(u(rng), u(rng), u(rng)).normalized();
    in.limit[size_t(k)] = 6 * pos(rng);
  }
  return in;
}

TEST_CASE("two phalanges at one point: the one below its limit takes what the other cannot") {
  Input in;
  in.touch[2] = in.touch[3] = true;  // index proximal and middle, at the origin, pushing along z
  in.force[2] = V3(0, 0, 8);
  in.limit[2] = in.limit[3] = 5;
  const auto c = in.solve();
  REQUIRE(c.status == Status::Ok);
  // Hand-solved: minimise (8 - f2 - f3)^2 over [0, 5]^2, ties toward (5, 0): f2 = 5, f3 = 3 (to
  // the tie-breaker's 1e-6 relative pull).
  CHECK(c.force[2] == doctest::Approx(5.0).epsilon(1e-12));
  CHECK(c.force[3] == doctest::Approx(3.0).epsilon(1e-5));
  CHECK(c.unrendered.norm() <= 1e-4);
  for (int k = 0; k < hand_phalanx_count; ++k)
    if (k != 2 && k != 3) CHECK(c.force[size_t(k)] == 0.0);  // out of contact: nothing
}

TEST_CASE("one phalanx within its limit renders its force, and beyond it the rest is reported") {
  Input in;
  in.touch[4] = true;
  in.point[4] = V3(0.1, 0.02, 0);
  in.force[4] = V3(0, 0, 4);
  in.limit[4] = 10;
  auto c = in.solve();
  CHECK(c.force[4] == doctest::Approx(4.0).epsilon(1e-12));
  CHECK(c.unrendered.norm() <= 1e-12);
  in.limit[4] = 3;
  c = in.solve();
  CHECK(c.force[4] == doctest::Approx(3.0).epsilon(1e-12));
  CHECK(c.unrendered.head<3>().isApprox(V3(0, 0, 1), 1e-12));  // the 1 N it cannot push
  CHECK(c.point.isApprox(in.point[4]));
}

TEST_CASE("random hands: the optimality conditions hold, and no method does better") {
  std::mt19937 rng(53);
  double clip_total = 0, best_total = 0;
  for (int trial = 0; trial < 300; ++trial) {
    CAPTURE(trial);
    const Input in = random_input(rng);
    const auto c = in.solve();
    REQUIRE(c.status == Status::Ok);
    const Problem p(in);
    const auto f = as_vector(c.force);
    // Feasible, and the unrendered wrench is w* - A f.
    for (int k = 0; k < hand_phalanx_count; ++k) {
      CHECK(f(k) >= 0.0);
      CHECK(f(k) <= p.hi(k));
    }
    // KKT of the box problem: the gradient vanishes on free pushes, points inward at bounds.
    const auto g = p.gradient(f);
    const double tol = 1e-9 * (1 + p.tw.norm()) * (1 + p.hi.maxCoeff());
    for (int k = 0; k < hand_phalanx_count; ++k) {
      if (p.hi(k) == 0.0) continue;
      if (f(k) > 0 && f(k) < p.hi(k)) CHECK(std::abs(g(k)) <= tol);
      if (f(k) == 0.0) CHECK(g(k) >= -tol);
      if (f(k) == p.hi(k)) CHECK(g(k) <= tol);
    }
    // A second method on every 20th hand: accelerated projected gradient (FISTA) from the
    // clipped pushes.
    if (trial % 20 == 0) {
      using Xc = Eigen::Matrix<double, hand_phalanx_count, 1>;
      const double step = 1.0 / ((p.ta.transpose() * p.ta).norm() + p.eps);
      Xc x = p.f0, y = x;
      double t = 1;
      for (int it = 0; it < 2000; ++it) {
        const Xc next = (y - step * p.gradient(y)).cwiseMax(0.0).cwiseMin(p.hi);
        const double tn = 0.5 * (1 + std::sqrt(1 + 4 * t * t));
        y = next + ((t - 1) / tn) * (next - x);
        x = next;
        t = tn;
      }
      CHECK(p.cost(f) <= p.cost(x) + 1e-10 * (1 + p.cost(x)));
    }
    // Never worse than clipping each phalanx on its own.
    CHECK(p.cost(f) <= p.cost(p.f0) + 1e-12);
    clip_total += (p.ta * p.f0 - p.tw).norm();
    best_total += (p.ta * f - p.tw).norm();
  }
  MESSAGE("weighted net-wrench error, summed over the trials: clipping ", clip_total, ", best ", best_total);
  CHECK(best_total < clip_total);
}

TEST_CASE("bad input gives InvalidInput and zero pushes, with no heap") {
  Input in;
  in.touch[2] = true;
  in.force[2] = V3(0, 0, std::nan(""));
  auto c = in.solve();
  CHECK(c.status == Status::InvalidInput);
  CHECK(c.force[2] == 0.0);
  in.force[2] = V3(0, 0, 1);
  in.limit[5] = -1;
  CHECK(in.solve().status == Status::InvalidInput);
  std::mt19937 rng(7);
  const Input r = random_input(rng);
  grip_test::NoHeapScope scope;
  const auto d = r.solve();
  CHECK(scope.allocations() == 0);
  CHECK(d.status == Status::Ok);
}

TEST_CASE("PhalanxActuators: clipping or the closest net wrench, and what each leaves unrendered") {
  std::mt19937 rng(91);
  for (int trial = 0; trial < 100; ++trial) {
    CAPTURE(trial);
    const Input in = random_input(rng);
    FeltForces<double> felt;
    felt.force = in.force;
    felt.point = in.point;
    felt.in_contact = in.touch;
    felt.direction = in.dir;
    PhalanxActuators<double> device;
    device.limit = in.limit;
    const HandPosture<double> posture{};
    const HandJoints<double> velocity = HandJoints<double>::Zero();
    PhalanxActuators<double>::Command clip, best;
    REQUIRE(device.render(felt, posture, velocity, clip) == Status::Ok);
    device.net_wrench = true;
    REQUIRE(device.render(felt, posture, velocity, best) == Status::Ok);
    const Problem p(in);
    const auto solved = in.solve();
    for (int k = 0; k < hand_phalanx_count; ++k) {
      const size_t i = size_t(k);
      CHECK(clip.force[i] == std::clamp(in.force[i].dot(in.dir[i]), 0.0, in.limit[i]));  // each on its own
      CHECK(best.force[i] == solved.force[i]);
    }
    // Unrendered: w* - A f for the pushes of phalanges in contact, from the problem written out here.
    Eigen::Matrix<double, hand_phalanx_count, 1> fc = as_vector(clip.force), fb = as_vector(best.force);
    for (int k = 0; k < hand_phalanx_count; ++k)
      if (!in.touch[size_t(k)]) fc(k) = fb(k) = 0;
    const Wrench<double> tclip = p.tw - p.ta * fc, tbest = p.tw - p.ta * fb;
    const double scale = 1e-12 * (1 + p.tw.norm());
    CHECK((p.t.cwiseProduct(clip.unrendered) - tclip).norm() <= scale);
    CHECK((p.t.cwiseProduct(best.unrendered) - tbest).norm() <= scale);
    CHECK(tbest.norm() <= tclip.norm() + 1e-9);
  }
}

}  // namespace net_wrench_command_tests
