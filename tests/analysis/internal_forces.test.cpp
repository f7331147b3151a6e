// Internal/external split of contact forces, the basis of null(G), the squeeze split.
#include <doctest/doctest.h>

#include <random>

#include <grip/analysis/internal_forces.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using namespace grip;

namespace {

template <class GraspT>
typename GraspT::ForceVector random_forces(std::mt19937& rng, const GraspT& g) {
  grip_test::Normal n01(0.0, 1.0);
  typename GraspT::ForceVector x(g.unknowns());
  for (int k = 0; k < g.unknowns(); ++k) x(k) = typename GraspT::ScalarType(3.0 * n01(rng));
  return x;
}

// Properties that define the split, checked by independent computations (G from
// grasp_matrix(), not the closed forms decompose_forces uses).
template <class GraspT>
void check_split(const GraspT& g, std::mt19937& rng) {
  using S = typename GraspT::ScalarType;
  const S tol = grip_test::tight<S>();
  const auto x = random_forces(rng, g);
  const auto G = g.grasp_matrix();
  const auto basis = internal_force_basis(g);
  ForceDecomposition<GraspT> dec;
  {
    grip_test::NoHeapScope scope;
    dec = decompose_forces(g, x);
    CHECK(scope.allocations() == 0);
  }
  REQUIRE(dec.status == Status::Ok);
  const S scale = S(1) + x.norm();
  // Recombines exactly: x = x_ext + x_int (x_int is defined as x - x_ext; round-off only).
  CHECK((dec.external + dec.internal - x).norm() <= tol * scale);
  // Internal part squeezes without moving the object: G x_int = 0.
  CHECK((G * dec.internal).norm() <= tol * scale);
  // External part balances the same wrench as x.
  CHECK((G * dec.external - G * x).norm() <= tol * scale);
  // x_ext is W-orthogonal to every internal force (every column of the basis).
  typename GraspT::ForceVector wx = dec.external;
  for (int i = 0; i < g.size(); ++i) wx.segment(i * GraspT::dim, GraspT::dim) *= g.contact(i).weight;
  REQUIRE(basis.status == Status::Ok);
  REQUIRE(basis.basis.cols() == g.unknowns() - 6);
  CHECK((basis.basis.transpose() * wx).norm() <= tol * scale);
  // Basis: orthonormal and in null(G).
  const auto I = (basis.basis.transpose() * basis.basis).eval();
  CHECK((I - decltype(I)::Identity(I.rows(), I.cols())).norm() <= tol);
  CHECK((G * basis.basis).norm() <= tol);
  // x_int is in the span of the basis: projecting it leaves it unchanged.
  CHECK((basis.basis * (basis.basis.transpose() * dec.internal) - dec.internal).norm() <= tol * scale);
}

}  // namespace

TEST_CASE_TEMPLATE("force split recombines, is internal and W-orthogonal (all models)", S, double, float) {
  std::mt19937 rng(11);
  for (int rep = 0; rep < 20; ++rep) {
    check_split(grip_test::random_grasp<Grasp<4, HardFinger, S>>(rng, 4), rng);
    check_split(grip_test::random_grasp<Grasp<Dynamic, SoftFinger, S, 6>>(rng, 3), rng);
    // Frictionless contacts on a sphere all push through the centre (rank 3): tilt the normals.
    Grasp<Dynamic, FrictionlessPoint, S, 12> p;
    grip_test::Normal n01(0.0, 1.0);
    for (int i = 0; i < 9; ++i) {
      Contact<S> c = grip_test::random_contact<S>(rng);
      const Vector3<double> t = grip_test::draw3(rng, n01);
      c.normal = (c.normal.template cast<double>() + 0.6 * t).normalized().template cast<S>();
      REQUIRE(p.add(c) == Status::Ok);
    }
    check_split(p, rng);
  }
}

TEST_CASE_TEMPLATE("basis of internal forces for two hard fingers: rank 5, 1-D... by hand", S, double, float) {
  // Two hard fingers at (+-1, 0, 0): G has rank 5 (no moment about x), so null(G) has
  // dimension 6 - 5 = 1: the squeeze along the line, x = (-1,0,0, 1,0,0)/sqrt(2) up to sign.
  Grasp<2, HardFinger, S> g;
  Contact<S> c;
  c.position << S(1), S(0), S(0);
  c.normal << S(-1), S(0), S(0);
  REQUIRE(g.set(0, c) == Status::Ok);
  c.position << S(-1), S(0), S(0);
  c.normal << S(1), S(0), S(0);
  REQUIRE(g.set(1, c) == Status::Ok);
  const auto b = internal_force_basis(g);
  CHECK(b.status == Status::Singular);
  CHECK(b.rank == 5);
  REQUIRE(b.basis.cols() == 1);
  const S s = b.basis(0, 0) < S(0) ? S(1) : S(-1);
  Eigen::Matrix<S, 6, 1> expect;
  expect << S(-1), S(0), S(0), S(1), S(0), S(0);
  expect /= std::sqrt(S(2));
  CHECK((s * b.basis.col(0) - expect).norm() <= grip_test::tight<S>());
}

TEST_CASE_TEMPLATE("squeeze split: symmetric squeeze is all kept, a one-sided one half lost", S, double, float) {
  // Three hard fingers at 120 degrees on a circle, equal squeeze s along the inward normals:
  // sum s a_i = 0 and r_i x a_i = 0, so t is internal: kept = t, lost = 0, fraction 1.
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(1.5707963267948966, 2.0943951023931953 * i, 0.05, 0.5, 2.0)) ==
            Status::Ok);
  const auto sp = squeeze_split(g);
  REQUIRE(sp.status == Status::Ok);
  CHECK(sp.lost.norm() <= grip_test::tight<S>());
  CHECK(sp.kept_fraction == doctest::Approx(1.0).epsilon(1e-3));
  // Two antipodal hard fingers with squeezes 3 and 1: t = (3 a, 1 a') with a' = -a. Internal
  // part is the equal squeeze 2 on both (sum of forces zero), the external part (1 a, -1 a')
  // = net force 2a; fraction = |(2,2)| / |(3,1)| = sqrt(8/10).
  Grasp<2, HardFinger, S> h;
  REQUIRE(h.set(0, grip_test::sphere_contact<S>(1.5707963267948966, 0.0, 0.05, 0.5, 3.0)) == Status::Ok);
  REQUIRE(h.set(1, grip_test::sphere_contact<S>(1.5707963267948966, 3.141592653589793, 0.05, 0.5, 1.0)) == Status::Ok);
  const auto sh = squeeze_split(h);
  CHECK(sh.status == Status::Singular);  // two hard fingers: rank 5, the split is still exact
  CHECK(sh.kept.template head<3>().norm() == doctest::Approx(2.0).epsilon(1e-4));
  CHECK(sh.kept.template tail<3>().norm() == doctest::Approx(2.0).epsilon(1e-4));
  CHECK(sh.kept_fraction == doctest::Approx(std::sqrt(0.8)).epsilon(1e-4));
  // The F2 optimum's internal part is the kept squeeze, whatever the load.
  std::mt19937 rng(5);
  Grasp<3, HardFinger, S> r = grip_test::random_grasp<Grasp<3, HardFinger, S>>(rng, 3);
  const auto sol = solve_range_space(r, grip_test::random_wrench<S>(rng));
  REQUIRE(sol.ok());
  const auto dr = decompose_forces(r, sol.forces);
  CHECK((dr.internal - squeeze_split(r).kept).norm() <= S(10) * grip_test::tight<S>() * (S(1) + sol.forces.norm()));
}

TEST_CASE_TEMPLATE("bad input to the split", S, double, float) {
  Grasp<3, HardFinger, S> g;  // incomplete: no slot set
  typename Grasp<3, HardFinger, S>::ForceVector x = Grasp<3, HardFinger, S>::ForceVector::Ones();
  CHECK(decompose_forces(g, x).status == Status::InvalidInput);
  CHECK(internal_force_basis(g).status == Status::InvalidInput);
  CHECK(squeeze_split(g).status == Status::InvalidInput);
  std::mt19937 rng(3);
  g = grip_test::random_grasp<Grasp<3, HardFinger, S>>(rng, 3);
  x(4) = std::numeric_limits<S>::quiet_NaN();
  const auto d = decompose_forces(g, x);
  CHECK(d.status == Status::InvalidInput);
  CHECK(d.internal.allFinite());
  CHECK(d.external.allFinite());
}

template struct grip::ForceDecomposition<Grasp<3, HardFinger, double>>;
template struct grip::InternalForceBasis<Grasp<Dynamic, SoftFinger, float, 5>>;
template struct grip::SqueezeSplit<Grasp<Dynamic, FrictionlessPoint, double, 8>>;
