// solve_constrained's hard-finger pass over columns (solve/coulomb_pass.hpp) against the
// contact-by-contact pass (detail::constrained_pass through coulomb_project_accumulate, itself
// checked against CoulombCone::project and projection_jacobian in solve_constrained.test.cpp):
// forces, every sum, and the Hessian, for every size from 1 to 40 (block tails), compile-time
// sizes, multipliers of every scale (all three regions), mu = 0, and overflowing v. CMake
// builds this file again with -march=native and with AVX2 (see tests/CMakeLists.txt), so each
// SIMD pack runs against the same reference.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <grip/solve/coulomb_pass.hpp>
#include <grip/solve/solve_constrained.hpp>

#include "support/allocation_counter.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"

using namespace grip;

namespace {

using grip_test::tol_of;

// The regions of the reference: 0 interior, 1 boundary part, 2 polar (or invalid v).
template <class S>
int region_of(const Contact<S>& c, S k, const Wrench<S>& lambda) {
  const Vector3<S> v = HardFinger::target(c) + k * HardFinger::wrench_transpose(c, lambda);
  if (!detail::cone_input_valid(v)) return 2;
  const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
  const auto j = projection_jacobian(cone, v, detail::project_onto(cone, v));
  return j.region == ProjectionRegion::Interior ? 0 : j.region == ProjectionRegion::Boundary ? 1 : 2;
}

// Compares one pass of the table with the reference at lambda; counts the reference's regions.
template <class GraspT>
void compare_pass(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w_ext,
                  const Wrench<typename GraspT::ScalarType>& lambda, int* regions) {
  using S = typename GraspT::ScalarType;
  const double tol = tol_of<S>(1e-11, 5e-4);
  const detail::CoulombPassTable<GraspT> table(g);
  REQUIRE(table.rows() % detail::CoulombPassTable<GraspT>::block == 0);
  REQUIRE(table.rows() >= g.size());
  REQUIRE(table.rows() < g.size() + detail::CoulombPassTable<GraspT>::block);
  auto cols = table.make_forces();
  GramAccumulator<S> h, h_ref;
  const detail::ConstrainedPass<S> p = table.pass(w_ext, lambda, cols, &h);
  typename GraspT::ForceVector x(g.unknowns()), x_ref(g.unknowns());
  table.store(cols, x);
  const detail::ConstrainedPass<S> q = detail::constrained_pass(g, w_ext, lambda, x_ref, &h_ref);
  // The same pass without the Hessian gives the same forces and sums.
  auto cols2 = table.make_forces();
  const detail::ConstrainedPass<S> p2 = table.pass(w_ext, lambda, cols2, nullptr);
  // The padding rows stay inert: zero forces.
  for (int i = g.size(); i < table.rows(); ++i) CHECK((cols.x(i) == S(0) && cols.y(i) == S(0) && cols.z(i) == S(0)));
  double scale = 1.0;
  for (int i = 0; i < g.size(); ++i) scale += double(x_ref.template segment<3>(3 * i).norm());
  for (int i = 0; i < g.size(); ++i) {
    ++regions[region_of(g.contact(i), g.inverse_weight(i), lambda)];
    CAPTURE(i);
    CHECK(double((x.template segment<3>(3 * i) - x_ref.template segment<3>(3 * i)).norm()) <=
          tol * (1.0 + double(x_ref.template segment<3>(3 * i).norm())));
  }
  CHECK(double((p.residual - q.residual).norm()) <= tol * (double(w_ext.norm()) + scale));
  CHECK(std::abs(double(p.f2 - q.f2)) <= tol * (1.0 + double(std::abs(q.f2))));
  CHECK(std::abs(double(p.scale - q.scale)) <= tol * (1.0 + double(q.scale)));
  CHECK(std::abs(double(p.dual - q.dual)) <= tol * (1.0 + double(std::abs(q.f2)) + double(lambda.norm()) * scale));
  const Matrix6<S> m = h.matrix(), m_ref = h_ref.matrix();
  CHECK(double((m - m_ref).norm()) <= tol * (1.0 + double(m_ref.norm())));
  CHECK(double((m - m.transpose()).norm()) == 0.0);
  // The same pass without the Hessian gives the same forces and sums to round-off. Not bit for
  // bit: the two instantiations may fuse different multiplies and adds into FMAs (g++ contracts
  // by default, -ffp-contract=fast), which moves the last bits.
  const double same = tol_of<S>(1e-14, 2e-6);
  CHECK(double((p2.residual - p.residual).norm()) <= same * (double(w_ext.norm()) + scale));
  CHECK(std::abs(double(p2.f2 - p.f2)) <= same * (1.0 + double(std::abs(p.f2))));
  for (int i = 0; i < g.size(); ++i) {
    CAPTURE(i);
    const Vector3<S> a(cols.x(i), cols.y(i), cols.z(i)), b(cols2.x(i), cols2.y(i), cols2.z(i));
    CHECK(double((a - b).norm()) <= same * (1.0 + double(a.norm())));
  }
}

template <class S>
Wrench<S> random_lambda(std::mt19937& rng, double scale) {
  grip_test::Normal n01(0.0, 1.0);
  Wrench<S> l;
  for (int r = 0; r < 6; ++r) l(r) = S(scale * n01(rng) * (r < 3 ? 1.0 : 20.0));
  return l;
}

}  // namespace

TEST_CASE_TEMPLATE("coulomb pass: columns against the contact-by-contact pass, sizes 1 to 40", S, double, float) {
  std::mt19937 rng(71);
  int regions[3] = {0, 0, 0};
  const double scales[4] = {0.1, 1.0, 10.0, 100.0};
  for (int n = 1; n <= 40; ++n) {
    auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 40>>(rng, n);
    // A few frictionless-like (mu = 0: the ray) and squeeze-free contacts.
    for (int i = 0; i < n; i += 5) {
      Contact<S> c = g.contact(i);
      c.friction = S(0);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    for (int i = 2; i < n; i += 7) {
      Contact<S> c = g.contact(i);
      c.squeeze = S(0);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    for (double sc : scales) {
      CAPTURE(n);
      CAPTURE(sc);
      compare_pass(g, grip_test::random_wrench<S>(rng), random_lambda<S>(rng, sc), regions);
    }
  }
  MESSAGE("regions (interior, boundary, polar): " << regions[0] << ", " << regions[1] << ", " << regions[2]);
  CHECK(regions[0] > 200);
  CHECK(regions[1] > 200);
  CHECK(regions[2] > 200);
}

TEST_CASE_TEMPLATE("coulomb pass: compile-time sizes 1, 8 and 20", S, double, float) {
  std::mt19937 rng(72);
  int regions[3] = {0, 0, 0};
  for (int rep = 0; rep < 20; ++rep) {
    const double sc = rep % 2 == 0 ? 1.0 : 30.0;
    compare_pass(grip_test::random_grasp<Grasp<1, HardFinger, S>>(rng, 1), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
    compare_pass(grip_test::random_grasp<Grasp<8, HardFinger, S>>(rng, 8), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
    compare_pass(grip_test::random_grasp<Grasp<20, HardFinger, S>>(rng, 20), grip_test::random_wrench<S>(rng),
                 random_lambda<S>(rng, sc), regions);
  }
  CHECK(regions[0] > 20);
  CHECK(regions[1] > 20);
}

TEST_CASE_TEMPLATE("coulomb pass: v beyond max_magnitude projects to zero with no Hessian term", S, double, float) {
  // One multiplier component near the largest finite value: v overflows (or exceeds
  // max_magnitude) for every contact, as in the reference; the sums stay finite.
  std::mt19937 rng(73);
  const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, S, 24>>(rng, 13);
  for (int r = 0; r < 6; ++r) {
    Wrench<S> l = Wrench<S>::Zero();
    l(r) = std::numeric_limits<S>::max() / S(4);
    const detail::CoulombPassTable<decltype(g)> table(g);
    auto cols = table.make_forces();
    GramAccumulator<S> h;
    const auto p = table.pass(Wrench<S>::Zero(), l, cols, &h);
    typename decltype(g)::ForceVector x_ref(g.unknowns());
    GramAccumulator<S> h_ref;
    const auto q = detail::constrained_pass(g, Wrench<S>::Zero(), l, x_ref, &h_ref);
    CAPTURE(r);
    // Contacts whose lever arm has no component across the moment axis may keep a valid v.
    for (int i = 0; i < g.size(); ++i) {
      const Vector3<S> xi(cols.x(i), cols.y(i), cols.z(i));
      CHECK((xi - x_ref.template segment<3>(3 * i)).norm() <= S(tol_of<S>(1e-9, 1e-3)) * (S(1) + x_ref.template segment<3>(3 * i).norm()));
    }
    CHECK(p.residual.allFinite());
    CHECK(std::isfinite(p.f2));
    CHECK(h.matrix().allFinite());
    CHECK((h.matrix() - h_ref.matrix()).norm() <= S(tol_of<S>(1e-9, 1e-3)) * (S(1) + h_ref.matrix().norm()));
    CHECK((p.residual - q.residual).norm() <= S(tol_of<S>(1e-9, 1e-3)) * (S(1) + q.residual.norm()));
  }
}

TEST_CASE("coulomb pass: no heap") {
  std::mt19937 rng(74);
  const auto g = grip_test::random_grasp<Grasp<Dynamic, HardFinger, double, 32>>(rng, 19);
  const Wrench<double> w = grip_test::random_wrench<double>(rng), l = random_lambda<double>(rng, 1.0);
  grip_test::NoHeapScope guard;
  const detail::CoulombPassTable<decltype(g)> table(g);
  auto cols = table.make_forces();
  GramAccumulator<double> h;
  const auto p = table.pass(w, l, cols, &h);
  CHECK(guard.allocations() == 0);
  CHECK(std::isfinite(p.f2));
}
