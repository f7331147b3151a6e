#pragma once
// Shared test fixtures: seeded random contacts and grasps, tolerances per scalar type.
#include <cmath>
#include <random>

#include <grip/grip.hpp>

#include "support/constants.hpp"
#include "support/random.hpp"
#include "support/tolerance.hpp"

namespace grip_test {

/// Tolerance for "equal at round-off" comparisons of O(1) quantities, one formula for both
/// types (support/tolerance.hpp's u, the unit round-off): 33554 u, about 2e-3 in float and
/// 3.7e-12 in double. Not a count of rounding errors: it is the former float allowance (2e-3)
/// in units of u, kept for the callers (solvers, analysis, external_wrench), which scale it by
/// factors of their own and solve problems of some condition; each should derive its checks
/// instead (issue 25). In double it is 270 times tighter than the former 1e-9, which every
/// caller still meets.
template <class S>
constexpr S tight() {
  return S(33554 * grip_test::unit_roundoff<S>());
}

/// A contact on a sphere of `radius` centred at the origin, at polar angle `theta` and
/// azimuth `phi`, pushing inwards.
template <class S>
grip::Contact<S> sphere_contact(double theta, double phi, double radius, double mu = 0.5, double squeeze = 1.0) {
  grip::Contact<S> c;
  const grip::Vector3<double> u(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  c.position = (radius * u).cast<S>();
  c.normal = (-u).cast<S>();
  c.friction = S(mu);
  c.torsional_friction = S(0.01);
  c.squeeze = S(squeeze);
  return c;
}

/// A random contact on a sphere of radius 2-6 cm, random squeeze and weight. With `tilt` > 0
/// the normal leans off the radial direction by up to atan(tilt) (a non-spherical surface),
/// so that normals no longer all pass through the centre.
template <class S>
grip::Contact<S> random_contact(std::mt19937& rng, bool random_weight = true, double tilt = 0.0) {
  grip_test::Uniform u01(0.0, 1.0);
  const double theta = std::acos(1.0 - 2.0 * u01(rng)), phi = 6.283185307179586 * u01(rng);
  const double radius = 0.02 + 0.04 * u01(rng), mu = 0.2 + u01(rng), squeeze = 3.0 * u01(rng);
  grip::Contact<S> c = sphere_contact<S>(theta, phi, radius, mu, squeeze);
  c.weight = random_weight ? S(0.5 + 1.5 * u01(rng)) : S(1);
  if (tilt > 0.0) {
    const grip::Vector3<double> v = grip_test::draw3(rng, u01) - grip::Vector3<double>::Constant(0.5);
    c.normal = (c.normal.template cast<double>() + tilt * v).normalized().template cast<S>();
  }
  return c;
}

/// Fills every slot of a fixed grasp, or adds `n` contacts to a Dynamic one.
template <class GraspT>
GraspT random_grasp(std::mt19937& rng, int n, bool random_weight = true, double tilt = 0.0) {
  using S = typename GraspT::ScalarType;
  GraspT g;
  if constexpr (GraspT::fixed_size == grip::Dynamic) {
    for (int i = 0; i < n; ++i) (void)g.add(random_contact<S>(rng, random_weight, tilt));
  } else {
    for (int i = 0; i < g.size(); ++i) (void)g.set(i, random_contact<S>(rng, random_weight, tilt));
  }
  return g;
}

/// A random external wrench of a few newtons and tenths of N m.
template <class S>
grip::Wrench<S> random_wrench(std::mt19937& rng) {
  grip_test::Normal n01(0.0, 1.0);
  grip::Wrench<S> w;
  for (int i = 0; i < 3; ++i) w(i) = S(5.0 * n01(rng));
  for (int i = 3; i < 6; ++i) w(i) = S(0.1 * n01(rng));
  return w;
}

/// Four hard fingers at the corners of a regular tetrahedron of circumradius
/// 5 cm sqrt(30 tol) around (5 cm, 0, 0), tol = ScalarTraits<S>::rank_tolerance, all with
/// normal -x, mu = 1 and `squeeze`: a full-rank grasp whose second moment about the centroid,
/// on the rank test's scale, has three eigenvalues of about 10 tol, so that its determinant
/// (about 1e3 tol^3) is under tol and a straight-line solve by the adjugate declines it, while
/// every pivot of diagonally pivoted LDL^T (about 10 tol) passes.
template <class S>
grip::Grasp<4, grip::HardFinger, S> tetrahedron_cluster(S squeeze) {
  const S rho = S(0.05) * std::sqrt(S(30) * grip::ScalarTraits<S>::rank_tolerance) / std::sqrt(S(3));
  const S corner[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  grip::Grasp<4, grip::HardFinger, S> g;
  for (int i = 0; i < 4; ++i) {
    grip::Contact<S> c;
    c.position << S(0.05) + rho * corner[i][0], rho * corner[i][1], rho * corner[i][2];
    c.normal << S(-1), S(0), S(0);
    c.friction = S(1);
    c.squeeze = squeeze;
    g.set(i, c);
  }
  return g;
}

}  // namespace grip_test
