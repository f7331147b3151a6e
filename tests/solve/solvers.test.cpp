// solve_range_space and solve_kkt: equilibrium, agreement, optimality, hand-solved cases.
#include <doctest/doctest.h>

#include <algorithm>

#include <Eigen/Dense>
#include <grip/grasp/objective.hpp>
#include <grip/solve/solve_constrained.hpp>
#include <grip/solve/solve_kkt.hpp>
#include <grip/solve/solve_range_space.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using namespace grip;
using grip_test::tight;

// Every solver instantiated for each model, scalar and size kind.
template Solution<Grasp<4, HardFinger, double>> grip::solve_range_space(const Grasp<4, HardFinger, double>&,
                                                                        const Wrench<double>&);
template Solution<Grasp<4, SoftFinger, float>> grip::solve_kkt(const Grasp<4, SoftFinger, float>&,
                                                               const Wrench<float>&);
template Solution<Grasp<Dynamic, FrictionlessPoint, double, 9>> grip::solve_kkt(
    const Grasp<Dynamic, FrictionlessPoint, double, 9>&, const Wrench<double>&);

namespace {

// An independent reference: the dense KKT system solved by Eigen's full-pivoting LU
// (heap-allocating MatrixX, fine in a test), from G, W and t written out here.
template <class GraspT>
Eigen::VectorXd reference_solve(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w_ext) {
  const Eigen::MatrixXd G = g.grasp_matrix().template cast<double>();
  const Eigen::VectorXd t = g.target().template cast<double>();
  const long m = G.cols();
  Eigen::VectorXd wdiag(m);
  for (int i = 0; i < g.size(); ++i)
    wdiag.segment(i * GraspT::dim, GraspT::dim).setConstant(double(g.contact(i).weight));
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(m + 6, m + 6);
  K.topLeftCorner(m, m) = wdiag.asDiagonal();
  K.topRightCorner(m, 6) = G.transpose();
  K.bottomLeftCorner(6, m) = G;
  Eigen::VectorXd rhs(m + 6);
  rhs << wdiag.cwiseProduct(t), -w_ext.template cast<double>();
  return Eigen::FullPivLU<Eigen::MatrixXd>(K).solve(rhs).head(m);
}

// F2 evaluated in double whatever the grasp's scalar, for perturbation checks.
template <class GraspT>
double f2_in_double(const GraspT& g, const Eigen::VectorXd& x) {
  constexpr int d = GraspT::dim;
  double sum = 0.0;
  for (int i = 0; i < g.size(); ++i) {
    const auto& c = g.contact(i);
    const Eigen::VectorXd t = GraspT::ModelType::target(c).template cast<double>();
    sum += double(c.weight) * (x.segment(i * d, d) - t).squaredNorm();
  }
  return 0.5 * sum;
}

template <class GraspT>
void check_optimal(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w_ext, const Solution<GraspT>& sol,
                   std::mt19937& rng) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  REQUIRE(sol.status == Status::Ok);
  const S scale = S(1) + w_ext.norm() + g.target().norm();
  // Equilibrium at round-off.
  CHECK(sol.residual <= tight<S>() * scale);
  CHECK((g.wrench(sol.forces) + w_ext).norm() <= tight<S>() * scale);
  // KKT stationarity: W (x - t) = G^T lambda, contact by contact.
  for (int i = 0; i < g.size(); ++i) {
    const auto& c = g.contact(i);
    const typename GraspT::ContactVector lhs =
        c.weight * (sol.forces.template segment<d>(i * d) - GraspT::ModelType::target(c));
    const typename GraspT::ContactVector rhs = GraspT::ModelType::basis(c).transpose() * sol.multipliers;
    CHECK((lhs - rhs).norm() <= tight<S>() * scale);
  }
  // Agreement with the independent dense reference.
  const Eigen::VectorXd ref = reference_solve(g, w_ext);
  CHECK((sol.forces.template cast<double>() - ref).norm() <= double(tight<S>() * scale) * 10.0);
  // Optimality: random null-space perturbations of G never lower F2.
  const Eigen::MatrixXd G = g.grasp_matrix().template cast<double>();
  const Eigen::MatrixXd P =
      Eigen::MatrixXd::Identity(G.cols(), G.cols()) - G.transpose() * (G * G.transpose()).ldlt().solve(G);
  grip_test::Normal n01(0.0, 1.0);
  const double f0 = f2_in_double(g, sol.forces.template cast<double>());
  CHECK(f0 == doctest::Approx(double(objective_f2(g, sol.forces))).epsilon(1e-4));
  for (int k = 0; k < 20; ++k) {
    Eigen::VectorXd delta(G.cols());
    for (long j = 0; j < delta.size(); ++j) delta(j) = n01(rng);
    delta = P * delta;  // G delta = 0: the perturbed forces still balance the wrench
    const Eigen::VectorXd x = sol.forces.template cast<double>() + 0.1 * delta;
    CHECK(f2_in_double(g, x) >= f0 - double(tight<S>()) * (1.0 + f0));
  }
}

template <class GraspT>
void check_random_grasps(int n, int trials, unsigned seed, double tilt = 0.0) {
  std::mt19937 rng(seed);
  for (int k = 0; k < trials; ++k) {
    const GraspT g = grip_test::random_grasp<GraspT>(rng, n, true, tilt);
    const auto w = grip_test::random_wrench<typename GraspT::ScalarType>(rng);
    const auto a = solve_range_space(g, w);
    const auto b = solve_kkt(g, w);
    check_optimal(g, w, a, rng);
    check_optimal(g, w, b, rng);
    using S = typename GraspT::ScalarType;
    CHECK((a.forces - b.forces).norm() <= tight<S>() * (S(10) + a.forces.norm()));
    CHECK((a.multipliers - b.multipliers).norm() <= tight<S>() * (S(10) + a.multipliers.norm()) * S(10));
  }
}

}  // namespace

TEST_CASE_TEMPLATE("both solvers are optimal and agree: hard fingers, fixed and bounded", S, double, float) {
  check_random_grasps<Grasp<3, HardFinger, S>>(3, 20, 1);
  check_random_grasps<Grasp<7, HardFinger, S>>(7, 20, 2);
  check_random_grasps<Grasp<Dynamic, HardFinger, S, 20>>(20, 10, 3);
  check_random_grasps<Grasp<Dynamic, HardFinger, S, 20>>(4, 10, 4);
}

TEST_CASE_TEMPLATE("both solvers are optimal and agree: soft fingers and frictionless points", S, double, float) {
  check_random_grasps<Grasp<2, SoftFinger, S>>(2, 20, 5);  // two soft fingers can span all six wrenches
  check_random_grasps<Grasp<Dynamic, SoftFinger, S, 10>>(6, 10, 6);
  // Frictionless normals through the centre resist no moment: tilt them (an irregular body).
  check_random_grasps<Grasp<9, FrictionlessPoint, S>>(9, 20, 7, 1.0);
  check_random_grasps<Grasp<Dynamic, FrictionlessPoint, S, 16>>(12, 10, 8, 1.0);
}

TEST_CASE_TEMPLATE("hand-solved: three hard fingers at 120 degrees hold a ball against gravity", S, double, float) {
  // Ball of radius R = 4 cm, mass m = 0.5 kg; contacts on the equator at azimuths 0, 120, 240
  // degrees: r_i = R u_i, inward normals a_i = -u_i, squeeze s = 2 N, unit weights.
  // External wrench: gravity only, w_ext = (0, 0, -m g, 0, 0, 0).
  // Derivation: stationarity gives f_i = s a_i + lambda_F - r_i x lambda_M. Try lambda_M = 0,
  // lambda_F = (0, 0, m g / 3): sum f_i = s sum a_i + m g z = m g z since the u_i sum to zero,
  // which cancels F_ext; moments: r_i x a_i = 0 (radial), and sum r_i x (m g/3) z =
  // (R sum u_i) x (m g/3) z = 0. Both equilibrium equations hold, so by uniqueness
  //     f_i = -s u_i + (m g / 3) z,   lambda = (0, 0, m g / 3, 0, 0, 0).
  const double R = 0.04, m = 0.5, grav = 9.81, s = 2.0;
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(1.5707963267948966, 2.0943951023931957 * i, R, 0.5, s)) ==
            Status::Ok);
  Wrench<S> w_ext = Wrench<S>::Zero();
  w_ext(2) = S(-m * grav);
  for (const auto& sol : {solve_range_space(g, w_ext), solve_kkt(g, w_ext)}) {
    REQUIRE(sol.status == Status::Ok);
    for (int i = 0; i < 3; ++i) {
      const double phi = 2.0943951023931957 * i;
      const Vector3<S> expected(S(-s * std::cos(phi)), S(-s * std::sin(phi)), S(m * grav / 3.0));
      CHECK((sol.forces.template segment<3>(3 * i) - expected).norm() <= tight<S>() * S(10));
    }
    CHECK(std::abs(sol.multipliers(2) - S(m * grav / 3.0)) <= tight<S>() * S(10));
    CHECK(sol.multipliers.template tail<3>().norm() <= tight<S>() * S(10));
  }
}

TEST_CASE_TEMPLATE("the paper's F1: with zero squeeze the forces are the weighted minimum norm", S, double, float) {
  // F1 (eq. 6): x = W^-1 G^T (G W^-1 G^T)^-1 (-w_ext), the weighted pseudo-inverse.
  std::mt19937 rng(21);
  Grasp<5, HardFinger, S> g;
  for (int i = 0; i < 5; ++i) {
    auto c = grip_test::random_contact<S>(rng);
    c.squeeze = S(0);
    REQUIRE(g.set(i, c) == Status::Ok);
  }
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  const auto sol = solve_range_space(g, w);
  REQUIRE(sol.ok());
  const Eigen::MatrixXd G = g.grasp_matrix().template cast<double>();
  Eigen::VectorXd winv(15);
  for (int i = 0; i < 5; ++i) winv.segment<3>(3 * i).setConstant(1.0 / double(g.contact(i).weight));
  const Eigen::MatrixXd Gw = winv.asDiagonal() * G.transpose();
  const Eigen::VectorXd x = Gw * (G * Gw).ldlt().solve(-w.template cast<double>());
  CHECK((sol.forces.template cast<double>() - x).norm() <= double(tight<S>()) * 100.0);
}

TEST_CASE_TEMPLATE("rank-deficient grasps are Singular with finite least-squares forces", S, double, float) {
  std::mt19937 rng(31);
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  auto check_least_squares = [&](const auto& g) {
    for (const auto& sol : {solve_range_space(g, w), solve_kkt(g, w)}) {
      CHECK(sol.status == Status::Singular);
      CHECK(sol.forces.allFinite());
      CHECK(sol.multipliers.allFinite());
      CHECK(std::isfinite(sol.residual));
      // x minimises |D (G x + w_ext)|, D = diag(1, 1, 1, 1/L, 1/L, 1/L): the normal equations
      // G^T D^2 (G x + w_ext) = 0 hold.
      const S L = detail::lever_arm(g);
      Wrench<S> d2;
      d2 << S(1), S(1), S(1), S(1) / (L * L), S(1) / (L * L), S(1) / (L * L);
      const auto G = g.grasp_matrix();
      const Wrench<S> res = d2.cwiseProduct(g.wrench(sol.forces) + w);
      CHECK((G.transpose() * res).norm() <= tight<S>() * S(100) * (S(1) + w.norm()));
      CHECK(sol.residual > S(1e-3));  // a generic wrench is not balanced
    }
  };
  // Two hard fingers: no moment about the line through them.
  Grasp<2, HardFinger, S> two;
  REQUIRE(two.set(0, grip_test::sphere_contact<S>(1.5707963267948966, 0.0, 0.04)) == Status::Ok);
  REQUIRE(two.set(1, grip_test::sphere_contact<S>(1.5707963267948966, 3.141592653589793, 0.04)) == Status::Ok);
  check_least_squares(two);
  // Five hard fingers all on one line (the x axis), normals anywhere.
  Grasp<Dynamic, HardFinger, S, 8> line;
  for (int i = 0; i < 5; ++i) {
    Contact<S> c;
    c.position << S(0.01 * i - 0.02), S(0), S(0);
    c.normal << S(0), S(i % 2 ? 1 : -1), S(0);
    REQUIRE(line.add(c) == Status::Ok);
  }
  check_least_squares(line);
  // Frictionless points whose normals all pass through the centre: no moment at all.
  Grasp<Dynamic, FrictionlessPoint, S, 8> radial;
  for (int i = 0; i < 7; ++i) REQUIRE(radial.add(grip_test::random_contact<S>(rng)) == Status::Ok);
  check_least_squares(radial);
  // An empty bounded grasp.
  Grasp<Dynamic, HardFinger, S, 4> empty;
  const auto e = solve_range_space(empty, w);
  CHECK(e.status == Status::Singular);
  CHECK(e.forces.size() == 0);
  CHECK(std::abs(e.residual - w.norm()) <= tight<S>() * (S(1) + w.norm()));
}

TEST_CASE_TEMPLATE("RankFallback::decline: the same answer where accepted, zero multipliers elsewhere", S, double,
                   float) {
  // The variant of solve_constrained's fast path: the default's answer where the straight-line
  // solve accepts (to round-off: the two instantiations may contract multiply-adds
  // differently); Singular with lambda = 0, x = t and res = -rhs where any rank fallback would
  // be needed (rank-deficient grasps, and an ill-conditioned one whose Schur complement has a
  // determinant under rank_tolerance but which pivoted LDL^T still accepts).
  using detail::RankFallback;
  std::mt19937 rng(43);
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  auto both = [&](const auto& g, bool accepted) {
    using GraspT = std::decay_t<decltype(g)>;
    Solution<GraspT> full, lean;
    Wrench<S> rhs_full, res_full, rhs_lean, res_lean, diag_full, diag_lean;
    REQUIRE(detail::range_space_solve(g, w, full, rhs_full, res_full, &diag_full));
    REQUIRE(detail::range_space_solve<RankFallback::decline>(g, w, lean, rhs_lean, res_lean, &diag_lean));
    CHECK(rhs_lean == rhs_full);
    CHECK(diag_lean == diag_full);
    if (accepted) {
      CHECK(full.status == Status::Ok);
      CHECK(lean.status == Status::Ok);
      const S eps = tight<S>();
      CHECK((lean.forces - full.forces).norm() <= eps * (S(1) + full.forces.norm()));
      CHECK((lean.multipliers - full.multipliers).norm() <= eps * (S(1) + full.multipliers.norm()));
      CHECK((res_lean - res_full).norm() <= eps * (S(1) + rhs_full.norm()));
      return full.status;
    }
    CHECK(lean.status == Status::Singular);
    CHECK(lean.multipliers.isZero(S(0)));
    CHECK(res_lean == Wrench<S>(-rhs_lean));
    for (int i = 0; i < g.size(); ++i)  // targets s_i a_i
      CHECK(lean.forces.template segment<3>(3 * i) == Vector3<S>(g.contact(i).squeeze * g.contact(i).normal));
    return full.status;
  };
  for (int k = 0; k < 20; ++k) both(grip_test::random_grasp<Grasp<6, HardFinger, S>>(rng, 6), true);
  Grasp<2, HardFinger, S> two;
  REQUIRE(two.set(0, grip_test::sphere_contact<S>(1.5707963267948966, 0.0, 0.04)) == Status::Ok);
  REQUIRE(two.set(1, grip_test::sphere_contact<S>(1.5707963267948966, 3.141592653589793, 0.04)) == Status::Ok);
  CHECK(both(two, false) == Status::Singular);
  // Full rank, but the Schur complement's determinant is under rank_tolerance: the
  // adjugate declines, the pivoted LDL^T fallback accepts (fixtures.hpp).
  const auto cluster = grip_test::tetrahedron_cluster<S>(S(1));
  CHECK(both(cluster, false) == Status::Ok);
}

TEST_CASE_TEMPLATE("bad input gives InvalidInput with zeros, never NaN", S, double, float) {
  std::mt19937 rng(41);
  const auto g = grip_test::random_grasp<Grasp<4, HardFinger, S>>(rng, 4);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  for (int k = 0; k < 6; ++k) {
    for (S bad : {nan, inf, -inf, S(3) * ScalarTraits<S>::max_magnitude}) {
      Wrench<S> w = Wrench<S>::Zero();
      w(k) = bad;
      for (const auto& sol : {solve_range_space(g, w), solve_kkt(g, w)}) {
        CHECK(sol.status == Status::InvalidInput);
        CHECK(sol.forces.size() == 12);
        CHECK(sol.forces.isZero(S(0)));
        CHECK(std::isfinite(sol.residual));
      }
    }
  }
  Grasp<4, HardFinger, S> incomplete;  // slots never set
  REQUIRE(incomplete.set(0, g.contact(0)) == Status::Ok);
  CHECK(solve_range_space(incomplete, Wrench<S>::Zero()).status == Status::InvalidInput);
  CHECK(solve_kkt(incomplete, Wrench<S>::Zero()).status == Status::InvalidInput);
}

TEST_CASE("no heap on any solver path, fixed and bounded, Ok and Singular") {
  std::mt19937 rng(51);
  const auto fixed = grip_test::random_grasp<Grasp<10, HardFinger, double>>(rng, 10);
  const auto bounded = grip_test::random_grasp<Grasp<Dynamic, SoftFinger, float, 16>>(rng, 11);
  Grasp<2, HardFinger, double> singular;
  REQUIRE(singular.set(0, grip_test::sphere_contact<double>(1.0, 0.0, 0.04)) == Status::Ok);
  REQUIRE(singular.set(1, grip_test::sphere_contact<double>(2.0, 1.0, 0.04)) == Status::Ok);
  const Wrench<double> w = grip_test::random_wrench<double>(rng);
  grip_test::NoHeapScope scope;
  const auto a = solve_range_space(fixed, w);
  const auto b = solve_kkt(fixed, w);
  const auto c = solve_range_space(bounded, w.cast<float>());
  const auto d = solve_kkt(bounded, w.cast<float>());
  const auto e = solve_range_space(singular, w);
  const auto f = solve_kkt(singular, w);
  const long allocations = scope.allocations();
  CHECK(allocations == 0);
  CHECK(a.ok());
  CHECK(b.ok());
  CHECK(c.ok());
  CHECK(d.ok());
  CHECK(e.status == Status::Singular);
  CHECK(f.status == Status::Singular);
}

TEST_CASE_TEMPLATE("two hard fingers are always Singular, however they are placed", S, double, float) {
  // Rank 5 by construction (no moment about the line through the contacts); a rank test
  // without pivoting let a few of these through as Ok with multipliers of 1e11 and more.
  std::mt19937 rng(61);
  int singular = 0;
  for (int k = 0; k < 3000; ++k) {
    const auto g = grip_test::random_grasp<Grasp<2, HardFinger, S>>(rng, 2, true, 0.5);
    const auto sol = solve_range_space(g, grip_test::random_wrench<S>(rng));
    singular += sol.status == Status::Singular;
    CHECK(sol.multipliers.allFinite());
  }
  CHECK(singular == 3000);
}

TEST_CASE_TEMPLATE("the reported residual keeps its value when it is denormal", S, double, float) {
  // Two opposed hard fingers on the x axis with no squeeze cannot resist a moment tau about
  // that axis (every force passes through it), and nothing else is asked: the least-squares
  // forces are zero and |G x + w| = tau exactly. With tau a few hundred denormal steps its
  // square is 0, so a plain norm reported 0 (found by the solver fuzz target).
  const S dmin = std::numeric_limits<S>::denorm_min();
  Grasp<2, HardFinger, S> g;
  Contact<S> c;
  c.friction = S(0.5);
  c.squeeze = S(0);
  c.position = Vector3<S>(S(0.03), S(0), S(0));
  c.normal = Vector3<S>(S(-1), S(0), S(0));
  REQUIRE(g.set(0, c) == Status::Ok);
  c.position = -c.position;
  c.normal = -c.normal;
  REQUIRE(g.set(1, c) == Status::Ok);
  Wrench<S> w = Wrench<S>::Zero();
  w(3) = S(700) * dmin;
  const S tau = w(3);
  const auto rs = solve_range_space(g, w);
  const auto kkt = solve_kkt(g, w);
  const auto con = solve_constrained(g, w);
  CHECK(rs.status == Status::Singular);
  for (const S reported : {rs.residual, kkt.residual, con.residual}) {
    CAPTURE(reported);
    CHECK(std::fabs(reported - tau) <= S(8) * dmin);
  }
  // and each is the residual of the forces it returned (recomputed in long double, whose
  // norm is Eigen's scaled one: on 32-bit ARM long double is double, and squares underflow)
  for (const auto* x : {&rs.forces, &kkt.forces, &con.forces}) {
    const Eigen::Matrix<long double, 6, 1> r =
        g.grasp_matrix().template cast<long double>() * x->template cast<long double>() +
        w.template cast<long double>();
    CHECK(std::fabs(static_cast<double>(r.stableNorm()) - static_cast<double>(tau)) <= 8.0 * static_cast<double>(dmin));
  }
}

TEST_CASE_TEMPLATE("the 6x6 Jacobi eigen-decomposition matches Eigen's solver", S, double, float) {
  std::mt19937 rng(71);
  grip_test::Normal n01(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    Eigen::Matrix<double, 6, 6> b;
    for (int i = 0; i < 36; ++i) b(i) = n01(rng);
    Eigen::Matrix<double, 6, 6> a = b * b.transpose();
    if (k % 3 == 0) a = b.leftCols(4) * b.leftCols(4).transpose();  // rank 4
    Wrench<S> ev;
    Matrix6<S> v;
    Matrix6<S> work = a.cast<S>();
    detail::symmetric_eigen_6x6(work, ev, v);
    Eigen::Matrix<double, 6, 1> mine = ev.template cast<double>();
    std::sort(mine.data(), mine.data() + 6);
    const Eigen::Matrix<double, 6, 1> ref = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(a).eigenvalues();
    CHECK((mine - ref).norm() <= double(tight<S>()) * 10.0 * a.norm());
    // Orthonormal vectors that rebuild the matrix.
    CHECK((v.transpose() * v - Matrix6<S>::Identity()).norm() <= tight<S>() * S(10));
    const Matrix6<S> rebuilt = v * ev.asDiagonal() * v.transpose();
    CHECK((rebuilt.template cast<double>() - a).norm() <= double(tight<S>()) * 10.0 * a.norm());
  }
}
