#pragma once
// The hostile-input oracle, shared by the property test (hostile_input.test.cpp) and the
// libFuzzer target (tests/fuzz/fuzz_solvers.cpp): an independent statement of which inputs
// are valid, and a check of every public solver (and the monitor, the resolution step and
// solve_constrained) on one grasp against the contract of
// status.hpp / solution.hpp (status matches the input, every output finite, least squares
// never worse than doing nothing). No doctest here, no heap: a failure is a message.
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <grip/grip.hpp>

#include "support/equilibrium_norm.hpp"

namespace grip_hostile {

/// What the generator knows about a grasp it built.
struct Expect {
  bool contacts_valid = true;     ///< every contact offered passed contact_valid() (else grasp incomplete)
  bool must_be_singular = false;  ///< rank < 6 by construction, exactly representable
  bool well_conditioned = false;  ///< moderate magnitudes, spread contacts: Ok and accurate expected
};

/// Independent restatement of Contact's invariants (contact.hpp), in long double.
template <class S>
bool value_ok(S x) {
  return std::isfinite(x) &&
         std::fabs(static_cast<long double>(x)) <= static_cast<long double>(grip::ScalarTraits<S>::max_magnitude);
}
template <class S>
bool contact_valid(const grip::Contact<S>& c) {
  using T = grip::ScalarTraits<S>;
  long double n2 = 0;
  for (int k = 0; k < 3; ++k) {
    if (!value_ok(c.position(k)) || !value_ok(c.normal(k))) return false;
    n2 += static_cast<long double>(c.normal(k)) * static_cast<long double>(c.normal(k));
  }
  for (S v : {c.friction, c.torsional_friction, c.squeeze, c.weight})
    if (!value_ok(v)) return false;
  if (c.friction < S(0) || c.torsional_friction < S(0) || c.squeeze < S(0)) return false;
  if (c.weight < T::min_weight) return false;
  return std::fabs(n2 - 1.0L) <= 2.0L * static_cast<long double>(T::normal_tolerance);
}
/// True when c's |normal|^2 - 1 lies within rounding of the tolerance's edge (eight units of
/// S's round-off of it): computed in S, as validate() does, the verdict there may go either way,
/// so an oracle takes the library's.
template <class S>
bool normal_on_tolerance_edge(const grip::Contact<S>& c) {
  long double n2 = 0;
  for (int k = 0; k < 3; ++k) n2 += static_cast<long double>(c.normal(k)) * static_cast<long double>(c.normal(k));
  const long double edge = 2.0L * static_cast<long double>(grip::ScalarTraits<S>::normal_tolerance);
  return std::fabs(std::fabs(n2 - 1.0L) - edge) <= 8.0L * static_cast<long double>(std::numeric_limits<S>::epsilon());
}
template <class S>
bool wrench_valid(const grip::Wrench<S>& w) {
  for (int k = 0; k < 6; ++k)
    if (!value_ok(w(k))) return false;
  return true;
}

template <class Derived>
bool finite(const Eigen::MatrixBase<Derived>& v) {
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v(i))) return false;
  return true;
}

/// res = |D (G x + w)| with D = diag(1, 1, 1, m, m, m), in double, from the contacts directly
/// (norms scaled, so that denormal terms do not vanish into a sum of squares);
/// adds to `scale` the size of its terms, sum |D G_i| |x_i| + |D w| (round-off scales with it).
template <class GraspT, class Vec>
void residual_of(const GraspT& g, const Vec& x, const grip::Wrench<typename GraspT::ScalarType>& w, double& res,
                 double& scale, double m = 1.0) {
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  grip::Wrench<double> dm;
  dm << 1, 1, 1, m, m, m;
  grip::Wrench<double> sum = dm.cwiseProduct(w.template cast<double>());
  scale += sum.stableNorm();
  for (int i = 0; i < g.size(); ++i) {
    const Eigen::Matrix<double, 6, d> gi = dm.asDiagonal() * M::basis(g.contact(i)).template cast<double>();
    const Eigen::Matrix<double, d, 1> xi = x.template segment<d>(i * d).template cast<double>();
    sum += gi * xi;
    scale += gi.norm() * xi.stableNorm();  // |D G_i| >= 1: its force rows hold a unit vector
  }
  res = sum.stableNorm();
}

/// 1/L, L the weighted RMS lever arm sqrt(sum k_i |r_i|^2 / sum k_i), k_i = 1/w_i, in double
/// from the contacts scaled by their largest coordinate (no underflow at any scale): the
/// solvers' unit balance; 1 when L is zero or 1/L overflows the grasp's scalar (the solvers
/// then balance nothing: D = I).
template <class GraspT>
double inverse_lever(const GraspT& g) {
  using S = typename GraspT::ScalarType;
  double big = 0;
  for (int i = 0; i < g.size(); ++i)
    big = std::max(big, static_cast<double>(g.contact(i).position.cwiseAbs().maxCoeff()));
  if (!(big > 0)) return 1.0;
  double k_sum = 0, kr2_sum = 0;
  for (int i = 0; i < g.size(); ++i) {
    const double k = 1.0 / static_cast<double>(g.contact(i).weight);
    k_sum += k;
    kr2_sum += k * (g.contact(i).position.template cast<double>() / big).squaredNorm();
  }
  const double lever = k_sum > 0 ? big * std::sqrt(kr2_sum / k_sum) : 0.0;
  const bool usable = lever > 0 && 1 / lever <= static_cast<double>(std::numeric_limits<S>::max());
  return usable ? 1 / lever : 1.0;
}

/// The eigenvalues, ascending, of the unit-balanced Gram matrix A = D G W^-1 G^T D divided by
/// the largest (D = diag(1, 1, 1, 1/L, 1/L, 1/L), L the weighted RMS lever arm, as the solvers
/// balance it), formed and decomposed in double from the contacts: how far the grasp is from
/// rank-deficient, whatever scalar it is solved in. All zero when A is zero or not finite.
template <class GraspT>
grip::Wrench<double> relative_gram_spectrum(const GraspT& g) {
  using M = typename GraspT::ModelType;
  const double inv_l = inverse_lever(g);
  grip::Wrench<double> dm;
  dm << 1, 1, 1, inv_l, inv_l, inv_l;
  grip::Matrix6<double> a = grip::Matrix6<double>::Zero();
  for (int i = 0; i < g.size(); ++i) {
    const Eigen::Matrix<double, 6, GraspT::dim> gi = dm.asDiagonal() * M::basis(g.contact(i)).template cast<double>();
    a.noalias() += (1.0 / static_cast<double>(g.contact(i).weight)) * gi * gi.transpose();
  }
  grip::Wrench<double> ev = grip::Wrench<double>::Zero();
  if (!finite(a)) return ev;
  grip::Matrix6<double> vecs;
  grip::detail::symmetric_eigen_6x6_sorted(a, ev, vecs);
  const double top = ev(5);
  if (!(top > 0) || !std::isfinite(top)) return grip::Wrench<double>::Zero();
  return ev / top;
}

/// True when the smallest eigenvalue of A (relative_gram_spectrum) lies below 100 times the
/// rank tolerance of scalar S: the grasp is then near-singular at S's own threshold (or
/// below it), so Singular is a right answer too even for a grasp built clean and spread.
template <class GraspT>
bool near_singular(const GraspT& g) {
  const double tol = static_cast<double>(grip::ScalarTraits<typename GraspT::ScalarType>::rank_tolerance);
  return relative_gram_spectrum(g)(0) < 100 * tol;
}

/// Checks one solver's answer; nullptr when it keeps the contract, else what broke.
template <class GraspT>
const char* check_solution(const GraspT& g, const grip::Wrench<typename GraspT::ScalarType>& w, const Expect& e,
                           const grip::Solution<GraspT>& sol) {
  using S = typename GraspT::ScalarType;
  using grip::Status;
  if (!finite(sol.forces) || !finite(sol.multipliers) || !std::isfinite(sol.residual)) return "non-finite output";
  if (sol.forces.size() != g.unknowns()) return "forces of the wrong size";
  const bool invalid = !e.contacts_valid || !wrench_valid(w);
  if (invalid != (sol.status == Status::InvalidInput)) return "InvalidInput does not match the input";
  if (invalid) {
    if (!sol.forces.isZero(0) || !sol.multipliers.isZero(0) || sol.residual != std::numeric_limits<S>::max())
      return "InvalidInput without the documented zeros";
    return nullptr;
  }
  if (sol.status != Status::Ok && sol.status != Status::Singular) return "status neither Ok nor Singular";
  if (e.must_be_singular && sol.status != Status::Singular) {
#ifdef GRIP_HOSTILE_TRACE
    GRIP_HOSTILE_TRACE(g, w, sol, 0.0, 0.0, 0.0, 0.0);
#endif
    return "rank-deficient grasp not Singular";
  }
  if (e.well_conditioned && sol.status != Status::Ok && !near_singular(g)) return "well-conditioned grasp not Ok";
  double res = 0, scale = 0;
  residual_of(g, sol.forces, w, res, scale);
  const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
  // Round-off: relative to the terms' size (solve_range_space forms the residual as
  // M lambda - r, so |M| |lambda| counts too), and absolute at the denormal spacing.
  const double tiny = 64 * static_cast<double>(std::numeric_limits<S>::denorm_min());
  double res_terms = 0, res_t0 = 0;
  residual_of(g, g.target(), w, res_t0, res_terms);
  const double m_lambda =
      grip::weighted_gram(g).template cast<double>().norm() * sol.multipliers.template cast<double>().stableNorm();
  if (!(std::fabs(res - static_cast<double>(sol.residual)) <= 64 * eps * (scale + res_terms + m_lambda) + tiny))
    return "reported residual differs from |G x + w|";
  // Least squares (solve_range_space's contract): |D (G x + w)| is smallest over all x, with
  // D = diag(1, 1, 1, 1/L, 1/L, 1/L), L the weighted RMS lever arm; so it is never larger than
  // at x = 0 nor at x = t.
  const double inv_l = inverse_lever(g);
  double sres = 0, sres_t = 0, sres_0 = 0, sscale = 0;
  residual_of(g, sol.forces, w, sres, sscale, inv_l);
  residual_of(g, g.target(), w, sres_t, sscale, inv_l);
  residual_of(g, decltype(sol.forces)::Zero(g.unknowns()), w, sres_0, sscale, inv_l);
#ifdef GRIP_HOSTILE_TRACE
  GRIP_HOSTILE_TRACE(g, w, sol, sres, sres_t, sres_0, sscale);
#endif
  // At every valid scale: weights spread to min_weight, lever arms from 1e-8 to max_magnitude,
  // squeezes that cancel to 1e-12 relative. The absolute floor (the denormal spacing) holds
  // per row in its own unit, and D multiplies the moment rows by 1/L: a denormal squeeze on a
  // lever of 0.6 mm leaves moments exact only to the spacing, 1/L = 1600 times that in D's units.
  const double tiny_d = tiny * (1 + inv_l);
  if (!(sres <= sres_t * (1 + 1e-3) + 256 * eps * sscale + tiny_d))
    return "least squares: |D(Gx+w)| worse than at x = t";
  if (!(sres <= sres_0 * (1 + 1e-3) + 256 * eps * sscale + tiny_d))
    return "least squares: |D(Gx+w)| worse than at x = 0";
  if (e.well_conditioned && !near_singular(g)) {  // near-singular: the least-squares checks above
    if (!(res <= 1e3 * eps * scale)) return "Ok but equilibrium not met";
    // Stationarity (eq. 9, lower rows): w_i (x_i - t_i) = G_i^T lambda.
    using M = typename GraspT::ModelType;
    constexpr int d = GraspT::dim;
    for (int i = 0; i < g.size(); ++i) {
      const auto& c = g.contact(i);
      const Eigen::Matrix<double, d, 1> lhs =
          static_cast<double>(c.weight) *
          (sol.forces.template segment<d>(i * d) - M::target(c)).template cast<double>();
      const Eigen::Matrix<double, d, 1> rhs =
          M::basis(c).template cast<double>().transpose() * sol.multipliers.template cast<double>();
      if (!((lhs - rhs).norm() <=
            1e4 * eps * (1 + lhs.norm() + rhs.norm() + static_cast<double>(c.weight * c.squeeze))))
        return "Ok but not stationary";
    }
  }
  return nullptr;
}

/// The monitor (evaluate and classify, exact cone), resolve() and sticking_grasp() on forces x
/// of g: statuses that match the input, finite numbers, consistent counts.
template <class GraspT, class Vec>
const char* check_monitor(const GraspT& g, const Vec& x, const grip::Wrench<typename GraspT::ScalarType>& w) {
  const bool valid_x = x.size() == g.unknowns() && [&] {
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (!value_ok(x(i))) return false;
    return true;
  }();
  const bool valid = g.complete() && valid_x;
  const grip::StabilityMonitor<GraspT> monitor;
  const grip::GraspState<GraspT> st = monitor.evaluate(g, x);
  const grip::GraspModes<GraspT> modes = monitor.classify(g, x);
  if (st.ok() != valid || modes.ok() != valid) return "monitor status does not match the input";
  if (!std::isfinite(st.min_margin)) return "monitor min_margin not finite";
  const int n = valid ? g.size() : 0;
  if (st.size() != n || modes.size() != n) return "monitor size";
  if (st.sticking_count + st.sliding_count + st.separating_count != n ||
      modes.sticking_count + modes.sliding_count + modes.separating_count != n)
    return "monitor counts do not add up";
  for (int i = 0; i < n; ++i) {
    const auto& c = st.contact(i);
    if (!std::isfinite(c.margin) || !std::isfinite(c.relative_margin) || !std::isfinite(c.normal_force) ||
        !finite(c.tangential_force) || !std::isfinite(c.moment))
      return "monitor contact state not finite";
    if (c.mode != st.mode(i)) return "monitor modes inconsistent";
  }
  const grip::Resolution<GraspT> r = grip::resolve(g, x, st, w);
  if (r.ok() != (valid && wrench_valid(w))) return "resolve status does not match the input";
  if (!finite(r.transmitted) || !finite(r.unbalanced) || !finite(r.released_wrench)) return "resolve output not finite";
  const auto sub = grip::sticking_grasp(g, st);
  if (sub.status == grip::Status::Ok && sub.grasp.size() != st.sticking_count) return "sticking_grasp size";
  return nullptr;
}

/// solve_constrained, cold and warm-started from the range-space multipliers: status matches
/// the input, every number finite, forces in their cones (they are projections).
template <class GraspT>
const char* check_constrained(const GraspT& g, const grip::Wrench<typename GraspT::ScalarType>& w,
                              const grip::Wrench<typename GraspT::ScalarType>& warm) {
  using S = typename GraspT::ScalarType;
  using Cone = grip::ExactConeT<typename GraspT::ModelType, S>;
  constexpr int d = GraspT::dim;
  const grip::ConstrainedSettings<S> settings;
  for (int k = 0; k < 2; ++k) {
    const grip::ConstrainedSolution<GraspT> sol =
        k == 0 ? grip::solve_constrained(g, w, settings) : grip::solve_constrained(g, w, settings, warm);
    const bool valid = g.complete() && wrench_valid(w) && (k == 0 || wrench_valid(warm));
    if ((sol.status == grip::Status::InvalidInput) == valid) return "solve_constrained status does not match the input";
    if (!finite(sol.forces) || !finite(sol.multipliers) || !finite(sol.certificate) || !std::isfinite(sol.residual) ||
        !std::isfinite(sol.objective) || !std::isfinite(sol.dual_objective))
      return "solve_constrained output not finite";
    if (sol.status == grip::Status::InvalidInput) continue;
    if (sol.forces.size() != g.unknowns()) return "solve_constrained forces size";
    for (int i = 0; i < g.size(); ++i) {
      // The cones are homogeneous: a force beyond max_magnitude (a load near it on short lever
      // arms needs one), where margin() reports its floor, is checked scaled down by a power of 2.
      Eigen::Matrix<S, d, 1> xi = sol.forces.template segment<d>(i * d);
      while (xi.cwiseAbs().maxCoeff() > grip::ScalarTraits<S>::max_magnitude / S(16)) xi *= S(0.5);
      // Round-off, plus the normal's own tolerance: the cone's axis is unit only to
      // normal_tolerance, so a force on it (mu = 0) shows |f_t| ~ normal_tolerance |f|. Margins
      // are in N of tangential load, mu f_n - ...: the round-off of f_n counts mu times.
      const S tol = (S(16) * std::numeric_limits<S>::epsilon() + S(4) * grip::ScalarTraits<S>::normal_tolerance) *
                    (S(1) + xi.norm());
      if (!(Cone::from_contact(g.contact(i)).margin(xi) >= -tol * (S(1) + g.contact(i).friction)))
        return "solve_constrained force outside its cone";
    }
    // Of dual norm 1 in the equilibrium norm (docs/solve.md).
    if (sol.status == grip::Status::Infeasible &&
        !(std::abs(grip_test::dual_norm_l(sol.certificate.template cast<double>(), grip_test::grasp_lever_length(g)) -
                   1.0) <= 1e-3))
      return "solve_constrained certificate not of dual norm 1";
  }
  return nullptr;
}

/// Runs every public solver entry point on (g, w) and checks each; nullptr when all keep
/// the contract. Allocates nothing (callers check that around it). `with_constrained` false
/// skips solve_constrained (iterative, by far the slowest on hostile input).
template <class GraspT>
const char* check_solvers(const GraspT& g, const grip::Wrench<typename GraspT::ScalarType>& w, const Expect& e,
                          bool with_constrained = true) {
  using S = typename GraspT::ScalarType;
  const grip::Solution<GraspT> rs = grip::solve_range_space(g, w);
  if (const char* m = check_solution(g, w, e, rs)) return m;
  const grip::Solution<GraspT> kkt = grip::solve_kkt(g, w);
  if (const char* m = check_solution(g, w, e, kkt)) return m;
  if (rs.status == grip::Status::Ok && kkt.status == grip::Status::Ok && e.well_conditioned) {
    // Two methods, one optimum.
    const double dx = (rs.forces - kkt.forces).template cast<double>().norm();
    const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
    // Two backward-stable methods agree to about cond(A) eps, A = D G W^-1 G^T D the unit-free
    // Gram matrix (three contacts can be nearly collinear even in a clean grasp).
    const grip::Matrix6<double> gram = grip::weighted_gram(g).template cast<double>();
    const double len = static_cast<double>(grip::detail::lever_arm(g));
    grip::Wrench<double> dd;
    dd << 1, 1, 1, 1 / len, 1 / len, 1 / len;
    grip::Wrench<double> ev;
    grip::Matrix6<double> vecs;
    grip::Matrix6<double> scaled = dd.asDiagonal() * gram * dd.asDiagonal();
    grip::detail::symmetric_eigen_6x6(scaled, ev, vecs);
    const double cond = ev.minCoeff() > 0 ? ev.maxCoeff() / ev.minCoeff() : 1e300;
    if (!(dx <= std::max(1e4, 10 * cond) * eps * (1 + rs.forces.template cast<double>().norm())))
      return "range-space and KKT disagree";
  }
  if (e.contacts_valid && g.complete()) {
    const grip::Matrix6<S> m = grip::weighted_gram(g);
    if (!finite(m)) return "weighted_gram not finite";
    grip::Wrench<S> y;
    const grip::Status st = grip::solve_symmetric_6x6(m, w, y);
    if (!finite(y)) return "solve_symmetric_6x6 output not finite";
    if (st != grip::Status::Ok && st != grip::Status::Singular) return "solve_symmetric_6x6 status";
    if (e.must_be_singular && st != grip::Status::Singular) return "singular Gram matrix not Singular";
  }
  if (const char* m = check_monitor(g, rs.forces, w)) return m;
  if (with_constrained)
    if (const char* m = check_constrained(g, w, rs.multipliers)) return m;
  return nullptr;
}

}  // namespace grip_hostile
