// The least-squares promise of solve_range_space (and solve_kkt, which falls back to it) at
// extreme but valid scales: |D (G x + w)| is the smallest over all x, D = diag(1, 1, 1, 1/L,
// 1/L, 1/L). Checked against a second method: the singular value decomposition of D G (Eigen's
// JacobiSVD, in long double where it exists), whose least residual is |(I - U U^T) D w|, U
// the left singular vectors of the range. The grasps are the kinds that once broke it: weights
// that spread to min_weight, soft fingers a few nanometres across, one contact 1e12 m out.
#include <doctest/doctest.h>

#include <Eigen/SVD>
#include <random>

#include "hostile/oracle.hpp"
#include "support/fixtures.hpp"

using namespace grip;

namespace least_squares_test {

using L = long double;

/// The least residual min_x |D (G x + w)| by the SVD of D G in long double, and the scale
/// of the terms it is computed from.
template <class GraspT>
L least_residual(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w) {
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  const L inv_l = static_cast<L>(grip_hostile::inverse_lever(g));
  Eigen::Matrix<L, 6, 1> dm;
  dm << 1, 1, 1, inv_l, inv_l, inv_l;
  Eigen::Matrix<L, 6, Eigen::Dynamic> dg(6, g.unknowns());
  for (int i = 0; i < g.size(); ++i) {
    Eigen::Matrix<L, 6, d> b = dm.asDiagonal() * M::basis(g.contact(i)).template cast<L>();
    for (int j = 0; j < d; ++j) b.col(j) /= b.col(j).norm();  // column scales change neither range nor rank
    dg.template middleCols<d>(i * d) = b;
  }
  Eigen::JacobiSVD<Eigen::Matrix<L, 6, Eigen::Dynamic>> svd(dg, Eigen::ComputeFullU);
  const Eigen::Matrix<L, 6, 1> dw = dm.cwiseProduct(w.template cast<L>());
  Eigen::Matrix<L, 6, 1> left = dw;
  for (int k = 0; k < svd.singularValues().size(); ++k)
    if (svd.singularValues()(k) > 1e-9L * svd.singularValues()(0))
      left -= svd.matrixU().col(k) * svd.matrixU().col(k).dot(dw);
  return left.norm();
}

/// Checks the solver's least residual against the SVD's, with the round-off bound of the
/// scalar: 1e3 eps times the size of the terms (sum |D G_i| |x_i| + |D w|).
template <class GraspT>
void check_least_squares(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w, int& checked) {
  using S = typename GraspT::ScalarType;
  const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
  for (int which = 0; which < 2; ++which) {
    const Solution<GraspT> sol = which == 0 ? solve_range_space(g, w) : solve_kkt(g, w);
    REQUIRE(sol.forces.allFinite());
    double res = 0, scale = 0;
    grip_hostile::residual_of(g, sol.forces, w, res, scale, grip_hostile::inverse_lever(g));
    const double best = static_cast<double>(least_residual(g, w));
    INFO("solver ", which, " status ", int(sol.status), " residual ", res, " least ", best, " scale ", scale);
    CHECK(res <= best * (1 + 1e-6) + 1e3 * eps * scale);
    ++checked;
  }
}

}  // namespace least_squares_test

using least_squares_test::check_least_squares;

TEST_CASE_TEMPLATE("least squares holds when weights spread to min_weight", S, double, float) {
  std::mt19937 rng(41);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Two or three hard fingers (rank 5 or 6): the light ones (min_weight) asked for a
    // million newtons of squeeze, the heavy ones for a few.
    const int n = 2 + trial % 2;
    Grasp<Dynamic, HardFinger, S, 4> g;
    for (int i = 0; i < n; ++i) {
      Contact<S> c = grip_test::random_contact<S>(rng);
      if (i == 0) c.weight = ScalarTraits<S>::min_weight;
      if (i == 0) c.squeeze = S(1e6f);
      REQUIRE(g.add(c) == Status::Ok);
    }
    check_least_squares(g, grip_test::random_wrench<S>(rng), checked);
  }
  CHECK(checked == 400);
}

TEST_CASE_TEMPLATE("least squares holds for soft fingers nanometres apart", S, double, float) {
  std::mt19937 rng(42);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Torsion columns (N m) of 1 beside lever arms of 1e-8 m: 1e16 apart at the unit balance.
    Grasp<4, SoftFinger, S> g;
    for (int i = 0; i < 4; ++i) {
      Contact<S> c = grip_test::random_contact<S>(rng);
      c.position *= S(1e-6f);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    check_least_squares(g, grip_test::random_wrench<S>(rng), checked);
  }
  CHECK(checked == 400);
}

TEST_CASE("least squares holds with one contact far beyond the lever arm") {
  std::mt19937 rng(43);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Five frictionless points (rank <= 5), one of them 1e12 m out; the weighted lever arm
    // is set by the others, so that contact's moment columns are 1e10 times theirs.
    Grasp<Dynamic, FrictionlessPoint, double, 8> g;
    for (int i = 0; i < 5; ++i) {
      Contact<double> c = grip_test::random_contact<double>(rng);
      if (i == 1) c.position.x() = 1e12;
      if (i == 1) c.weight = 1e3;
      REQUIRE(g.add(c) == Status::Ok);
    }
    check_least_squares(g, grip_test::random_wrench<double>(rng), checked);
  }
  CHECK(checked == 400);
}

TEST_CASE_TEMPLATE("least squares holds for grasps 1e-29 m across", S, double, float) {
  std::mt19937 rng(44);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Hard fingers of a random grasp shrunk to lever arms of about 1e-29 m: in float the
    // squares of the coordinates underflow (the fuzzer's finding float_lever_of_1e-29), yet
    // the moment rows, scaled by 1 / L, are as large as the force rows.
    const int n = 2 + trial % 3;
    Grasp<Dynamic, HardFinger, S, 4> g;
    for (int i = 0; i < n; ++i) {
      Contact<S> c = grip_test::random_contact<S>(rng);
      c.position *= S(2.5e-28f);
      REQUIRE(g.add(c) == Status::Ok);
    }
    Wrench<S> w = grip_test::random_wrench<S>(rng);
    w.template tail<3>() *= S(2.5e-28f);  // moments on the grasp's own scale
    check_least_squares(g, w, checked);
  }
  CHECK(checked == 400);
}
