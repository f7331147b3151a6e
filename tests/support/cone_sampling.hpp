#pragma once
// Seeded random samples for the friction-cone tests: unit normals, tangents, forces given by
// their normal and tangential parts, and a tolerance that scales with the force.
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include <grip/core/types.hpp>
#include "support/random.hpp"
#include "support/tolerance.hpp"

namespace grip_test {

/// A uniformly random unit 3-vector (double, cast later).
inline grip::Vector3<double> random_unit(std::mt19937& rng) {
  grip_test::Normal n01(0.0, 1.0);
  grip::Vector3<double> v;
  do {
    v << n01(rng), n01(rng), n01(rng);
  } while (v.norm() < 1e-3);
  return v / v.norm();
}

/// A unit vector orthogonal to the unit vector a, uniformly random in that plane.
inline grip::Vector3<double> random_tangent(std::mt19937& rng, const grip::Vector3<double>& a) {
  grip::Vector3<double> v;
  do {
    v = random_unit(rng);
    v -= v.dot(a) * a;
  } while (v.norm() < 1e-3);
  return v / v.norm();
}

/// A unit normal of scalar type S, renormalised in S so |a| = 1 at S's round-off.
template <class S>
grip::Vector3<S> random_normal(std::mt19937& rng) {
  grip::Vector3<S> a = random_unit(rng).cast<S>();
  return a / a.norm();
}

/// A force f = fn a + ft u (u a random tangent), in double; fn in [fn_lo, fn_hi],
/// |f_t| in [0, ft_hi].
inline grip::Vector3<double> random_force(std::mt19937& rng, const grip::Vector3<double>& a, double fn_lo, double fn_hi,
                                          double ft_hi) {
  grip_test::Uniform u01(0.0, 1.0);
  const double fn = fn_lo + (fn_hi - fn_lo) * u01(rng);
  const double ft = ft_hi * u01(rng);
  return fn * a + ft * random_tangent(rng, a);
}

/// Relative round-off allowance for quantities of size |x|, one formula for both types
/// (support/tolerance.hpp's u, the unit round-off): 1678 u, about 1e-4 in float and 1.9e-13 in
/// double. Not a count of rounding errors: it is the former float allowance (1e-4) in units of
/// u, kept for the callers (the cone and monitor tests), which scale it by factors of their own
/// (10 to 100, times 1 + |f|); each should derive its checks instead (issue 25). In double it
/// is 540 times tighter than the former 1e-10, which every caller still meets.
template <class S>
S rel_tol() {
  return S(1678 * grip_test::unit_roundoff<S>());
}

}  // namespace grip_test
