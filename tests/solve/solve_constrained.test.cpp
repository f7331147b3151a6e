// solve_constrained: optimality certificates (KKT from the definitions), the fast path, warm
// starts, hand-derived instances (a cone boundary, mu = 0, infeasible), bad input, no heap.
#include <doctest/doctest.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <grip/solve/solve_constrained.hpp>

#include "solve/constrained_support.hpp"
#include "solve/slip_checks.hpp"
#include "support/allocation_counter.hpp"
#include "support/equilibrium_norm.hpp"
#include "support/fixtures.hpp"
#include "support/random.hpp"
#include "support/test_scale.hpp"
#include "support/tolerance.hpp"

using namespace grip;

template struct grip::ConstrainedSolution<Grasp<3, HardFinger, double>>;
template struct grip::ConstrainedSolution<Grasp<Dynamic, SoftFinger, float, 20>>;
template struct grip::ConstrainedSettings<float>;

namespace {

// Dynamic grasps of every test here hold up to 20 contacts: one capacity per model and scalar,
// so that each compiles the solver once (as solve_constrained_reference and conic_dual do).
template <class Model, class S>
using DynamicGrasp = Grasp<Dynamic, Model, S, 20>;

// Round-off scales of a solution (support/tolerance.hpp), in double. The solver's forces are
// projections x_i = P_i(v_i) of v_i = t_i + k_i G_i^T lambda at its multipliers, so the
// conditions on x_i and s_i below hold exactly but for the rounding of v_i and of the
// projection, some 10 roundings of |v_i| <= |t_i| + k_i (|l_f| + (1 + |r_i|) |l_m|).
template <class GraspT>
double v_bound(const GraspT& g, int i, const Wrench<double>& l) {
  using M = typename GraspT::ModelType;
  const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
  return M::target(c).norm() + double(g.inverse_weight(i)) * (l.template head<3>().norm() +
                                                              (1 + c.position.norm()) * l.template tail<3>().norm());
}

// How an error e in a force or in s_i moves cone_violation and dual_cone_violation (their
// condition): hard |t| - mu n and mu |t| - n by (1 + mu) e; soft (sqrt(mt^2 |t|^2 + mu^2 m^2)
// - mu mt n) / (mu mt) by (1 + 1 / mu + 1 / mt) e and sqrt(mu^2 |t|^2 + mt^2 m^2) - n by
// (1 + mu + mt) e; frictionless by e.
template <class M>
double cone_condition(const Contact<double>& c) {
  if constexpr (M::dim == 1) return 1;
  if constexpr (M::dim == 3) return 1 + c.friction;
  return 1 + 1 / c.friction + 1 / c.torsional_friction;
}
template <class M>
double dual_condition(const Contact<double>& c) {
  if constexpr (M::dim == 1) return 1;
  if constexpr (M::dim == 3) return 1 + c.friction;
  return 1 + c.friction + c.torsional_friction;
}

// The equilibrium the solver accepts (solve_constrained.hpp: Ok when |G x + w_ext|_L <=
// settings.tolerance (|w_ext|_L + |x| + max_i s_i), computed in S, with |(f, m)|_L = |(f, m / L)|,
// L the longest lever arm), plus the rounding of its residual in S, n + 4 roundings of its terms
// |w_ext|_L + sum (1 + |r_i| / L) |x_i|. The settings' tolerance is the solver's contract, chosen
// per type by ScalarTraits (1e-12 in double, 1e-5 in float), not a round-off: the one term here
// that is not k u. The grasps here have L <= 1 m, so that the plain norm |G x + w_ext| is at most
// the L norm and the bound holds for it too.
template <class GraspT>
double equilibrium_tolerance(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w,
                             const typename GraspT::ForceVector& x,
                             const ConstrainedSettings<typename GraspT::ScalarType>& st = {}) {
  using S = typename GraspT::ScalarType;
  constexpr int d = GraspT::dim;
  const double len = grip_test::grasp_lever_length(g);
  REQUIRE(len <= 1.0);
  const double wl = grip_test::norm_l(w.template cast<double>(), len);
  double x2 = 0, terms = wl, squeeze = 0;
  for (int i = 0; i < g.size(); ++i) {
    const double xi = double(x.template segment<d>(i * d).norm());
    x2 += xi * xi;
    terms += (1 + double(g.contact(i).position.norm()) / len) * xi;
    squeeze = std::max(squeeze, double(g.contact(i).squeeze));
  }
  const double stop = std::max(double(st.tolerance), 16 * double(std::numeric_limits<S>::epsilon()));
  return stop * (wl + std::sqrt(x2) + squeeze) + grip_test::roundoff<S>(g.size() + 4, 1, terms);
}

// |F2(x) - F2*| for an accepted solution: a refined answer x = x(lambda) solves the problem whose
// load is G x, so to first order F2(x) - F2* = lambda . (G x + w_ext), at most |lambda|_L* times
// the accepted residual |G x + w_ext|_L; an answer of the interior-point method (not refined) is
// within its duality gap, ScalarTraits::interior_tolerance of F2, more. Plus F2's own rounding in
// S, unknowns + 4 roundings of F2.
template <class GraspT>
double objective_tolerance(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w,
                           const ConstrainedSolution<GraspT>& sol, double f2) {
  using S = typename GraspT::ScalarType;
  const double len = grip_test::grasp_lever_length(g);
  const double lambda = grip_test::dual_norm_l(sol.multipliers.template cast<double>(), len);
  const double gap = sol.refined ? 0.0 : double(ScalarTraits<S>::interior_tolerance) * f2;
  return lambda * equilibrium_tolerance(g, w, sol.forces) + gap + grip_test::roundoff<S>(g.unknowns() + 4, 1, f2);
}

// KKT of min F2 s.t. G x + w = 0, x_i in K_i, checked from the definitions: x_i in K_i,
// s_i = W_i (x_i - t_i) - G_i^T lambda in K_i^* (dual feasibility: -s_i in the normal cone at x_i),
// s_i . x_i = 0 (complementarity), and G x + w = 0. The dual conditions hold to round-off for a
// refined answer (projections at the multipliers); an answer of the interior-point method is
// checked for its cones and equilibrium here, for its objective by the callers.
template <class GraspT>
void check_kkt(const GraspT& g, const Wrench<typename GraspT::ScalarType>& w, const ConstrainedSolution<GraspT>& sol) {
  using M = typename GraspT::ModelType;
  constexpr int d = M::dim;
  using S = typename GraspT::ScalarType;
  const Wrench<double> l = sol.multipliers.template cast<double>();
  Wrench<double> r = w.template cast<double>();
  for (int i = 0; i < g.size(); ++i) {
    const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
    const Eigen::Matrix<double, d, 1> x = sol.forces.template segment<d>(i * d).template cast<double>();
    const Eigen::Matrix<double, d, 1> s = c.weight * (x - M::target(c)) - M::wrench_transpose(c, l);
    const double v = v_bound(g, i, l);
    // x_i in K_i to the projection's last roundings of |v_i| (k = 8) through cone_condition;
    // s_i in K_i^* and s_i . x_i = 0, exact for x_i = P_i(v_i), to k = 8 roundings of w_i |v_i|
    // through dual_condition and of |v_i| (w_i |x_i| + |s_i|). A soft finger's elliptic
    // projection finds its multiplier l by bisection on (1 - l) f_n'(l) = f_n, f_n' =
    // sqrt(t'^2 / mu^2 + m'^2 / mu_t^2): the rounding of that equation, divided by mu_t, moves
    // l and with it the moment m' = m mu_t^2 / (mu_t^2 + l), a further condition 1 / mu_t (100
    // here; observed up to 1.6 / mu_t, 0.2 of these tolerances).
    const double ecc = d == 4 ? 1 / c.torsional_friction : 1.0;
    CHECK(grip_test::cone_violation<M>(c, x) <= grip_test::roundoff<S>(8, cone_condition<M>(c), v));
    if (sol.refined) {
      CHECK(grip_test::dual_cone_violation<M>(c, s) <=
            grip_test::roundoff<S>(8, ecc * dual_condition<M>(c), c.weight * v));
      CHECK(std::abs(s.dot(x)) <= grip_test::roundoff<S>(8, ecc, v * (c.weight * x.norm() + s.norm())));
    }
    r += M::wrench(c, x);
  }
  ConstrainedSettings<S> accepted;  // an answer not refined: to the interior-point tolerance
  if (!sol.refined) accepted.tolerance = std::max(accepted.tolerance, S(ScalarTraits<S>::interior_tolerance));
  CHECK(r.norm() <= equilibrium_tolerance(g, w, sol.forces, accepted));
}

template <class Model, class S>
void kkt_on_random_instances(int count) {
  using GraspT = DynamicGrasp<Model, S>;
  std::mt19937 rng(4242 + Model::dim);
  int checked = 0;
  for (int k = 0; k < count; ++k) {
    GraspT g = grip_test::random_grasp<GraspT>(rng, 16);
    Wrench<S> w = grip_test::random_wrench<S>(rng);
    const auto sol = solve_constrained(g, w);
    CHECK(sol.residual < std::numeric_limits<S>::max());
    if (sol.status != Status::Ok) {
      // Random frictionless contacts on a sphere have radial normals (rank(G) = 3): mostly
      // infeasible, and some undecided within the iteration bound.
      CHECK((sol.status == Status::Infeasible || (Model::dim == 1 && sol.status == Status::IterationLimit)));
      continue;
    }
    ++checked;
    check_kkt(g, w, sol);
  }
  if (Model::dim > 1) CHECK(checked > count / 2);
}

}  // namespace

TEST_CASE_TEMPLATE("hard-finger pass: the fused projection and Hessian block match the generic path", S, double,
                   float) {
  // The fused kernel against CoulombCone::project and k G J G^T from projection_jacobian (the
  // generic path the other models use), in every region: interior, polar cone, the boundary
  // part, exactly on the boundary (|v_t| = mu n), the apex v = 0, and mu = 0 (the ray).
  std::mt19937 rng(41);
  grip_test::Normal n01(0.0, 1.0);
  int regions[3] = {0, 0, 0};
  for (int rep = 0; rep < 3000; ++rep) {
    Contact<S> c = grip_test::random_contact<S>(rng);
    const double mus[4] = {0.0, 0.3, 0.5, 1.7};
    c.friction = S(mus[rep % 4]);
    const S k = S(0.2 + std::abs(n01(rng)));
    const Vector3<S> a = c.normal;
    const Vector3<S> e = a.unitOrthogonal();
    const double vn = n01(rng), vt = std::abs(n01(rng));
    Vector3<S> v = S(vn) * a + S(vt) * e;
    if (rep % 7 == 0) v = S(std::abs(vn)) * a + c.friction * S(std::abs(vn)) * e;  // on the boundary
    if (rep % 11 == 0) v.setZero();
    // A denormal tangential part: |v_t| underflows to 0 while v.a may be a tiny positive number
    // whose mu v.a underflows too (the generic path calls that polar).
    if (rep % 13 == 0) v = S(1000) * std::numeric_limits<S>::denorm_min() * e;
    if (rep % 17 == 0) {  // mu = 0 and v exactly on the ray: v_t = 0 on the boundary part
      c.normal = Vector3<S>::UnitZ();
      c.friction = S(0);
      v = S(2) * Vector3<S>::UnitZ();
    }
    GramAccumulator<S> acc;
    const Vector3<S> x = detail::coulomb_project_accumulate(c, k, v, &acc);
    const CoulombCone<S> cone = CoulombCone<S>::from_contact(c);
    const Vector3<S> x_ref = detail::project_onto(cone, v);
    const auto j = projection_jacobian(cone, v, x_ref);
    regions[int(j.region)]++;
    Matrix6<S> h_ref = Matrix6<S>::Zero();
    if (j.region != ProjectionRegion::Polar) {
      const Eigen::Matrix<S, 6, 3> g = HardFinger::basis(c);
      h_ref = k * (g * j.matrix * g.transpose());
    }
    // Round-off (support/tolerance.hpp), as in coulomb_pass.test.cpp: each path projects with
    // about 10 roundings of |v|, k = 32 for the two. The Hessian's terms k G J G^T, at most
    // sqrt(6) k (1 + |r|^2) in Frobenius norm, take about 16 roundings in the two paths, with
    // e = v_t / |v_t| within a few u times 1 + 1 / mu on the boundary part (where |v| <= (1 +
    // 1 / mu) |v_t|; with mu = 0, e meets only zero factors). Observed at most 0.1 of both.
    const double r2 = double(c.position.squaredNorm()),
                 mu_cond = 1 + (c.friction > S(0) ? 1 / double(c.friction) : 0.0);
    CHECK(double((x - x_ref).norm()) <= grip_test::roundoff<S>(32, 1, double(v.norm())));
    CAPTURE(rep);
    CHECK(double((acc.matrix() - h_ref).norm()) <=
          grip_test::roundoff<S>(16, mu_cond, std::sqrt(6.0) * double(k) * (1 + r2)));
  }
  CHECK(regions[int(ProjectionRegion::Interior)] > 100);
  CHECK(regions[int(ProjectionRegion::Polar)] > 100);
  CHECK(regions[int(ProjectionRegion::Boundary)] > 100);
}

TEST_CASE_TEMPLATE("solve_constrained optima satisfy the KKT conditions (all models)", S, double, float) {
  kkt_on_random_instances<HardFinger, S>(40);
  kkt_on_random_instances<SoftFinger, S>(40);
  kkt_on_random_instances<FrictionlessPoint, S>(40);
}

TEST_CASE_TEMPLATE("solve_constrained: a pinch exactly on the cone's boundary (hand derivation)", S, double, float) {
  // Two soft fingers at x = -/+3 cm pushing along +/-x with squeeze s = 4 N, mu = 0.5,
  // w_ext = (0, 0, -W, 0, 0, 0) with W = 2 mu s = 4 N. By symmetry the unconstrained optimum is
  // f_i = s a_i + (0, 0, W/2), m_i = 0 (the moments of the two W/2 cancel): |f_t| = 2 = mu f_n,
  // exactly on the boundary, hence also the constrained optimum, with F2 = 2 * 1/2 (W/2)^2 = 4.
  Grasp<2, SoftFinger, S> g;
  Contact<S> c;
  c.friction = S(0.5);
  c.torsional_friction = S(0.01);
  c.squeeze = S(4);
  c.position << S(-0.03), S(0), S(0);
  c.normal << S(1), S(0), S(0);
  REQUIRE(g.set(0, c) == Status::Ok);
  c.position << S(0.03), S(0), S(0);
  c.normal << S(-1), S(0), S(0);
  REQUIRE(g.set(1, c) == Status::Ok);
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-4);
  const auto sol = solve_constrained(g, w);
  REQUIRE(sol.status == Status::Ok);
  Eigen::Matrix<S, 8, 1> expect;
  expect << S(4), S(0), S(2), S(0), S(-4), S(0), S(2), S(0);
  // The forces' error is at most grasp_condition times the residual the solver accepts (unit
  // weights; the optimum is the unconstrained one, J = I: |x - x*| <= |r| / sigma_min(G), and
  // sigma_max(G) >= 1 from G's identity columns); F2's, objective_tolerance.
  CHECK(double((sol.forces - expect).norm()) <=
        grip_test::grasp_condition(g) * equilibrium_tolerance(g, w, sol.forces));
  CHECK(std::abs(double(sol.objective) - 4.0) <= objective_tolerance(g, w, sol, 4.0));
  check_kkt(g, w, sol);
}

TEST_CASE_TEMPLATE("solve_constrained: mu = 0 and an active apex (hand derivation, rank(G) < 6)", S, double, float) {
  // Hard fingers with mu = 0 at x = -/+3 cm, normals +/-x, squeeze s: forces n_i a_i, n_i >= 0.
  // w_ext = (5, 0, 0, 0, 0, 0): equilibrium n_1 - n_2 = -5. Minimise 1/2 ((n1 - s)^2 + (n2 - s)^2):
  // s = 4: n1 = 1.5, n2 = 6.5, F2 = 6.25 (interior); s = 1: n1 = -1.5 < 0 -> n1 = 0 (apex), n2 = 5,
  // F2 = 1/2 (1 + 16) = 8.5. G has rank 2 here; that is no error while w_ext can be balanced.
  for (const double s : {4.0, 1.0}) {
    DynamicGrasp<HardFinger, S> g;
    Contact<S> c;
    c.friction = S(0);
    c.squeeze = S(s);
    c.position << S(-0.03), S(0), S(0);
    c.normal << S(1), S(0), S(0);
    REQUIRE(g.add(c) == Status::Ok);
    c.position << S(0.03), S(0), S(0);
    c.normal << S(-1), S(0), S(0);
    REQUIRE(g.add(c) == Status::Ok);
    Wrench<S> w = Wrench<S>::Zero();
    w(0) = S(5);
    const auto sol = solve_constrained(g, w);
    REQUIRE(sol.status == Status::Ok);
    const double n1 = s > 2.5 ? s - 2.5 : 0.0, n2 = n1 + 5.0;
    // In (n1, n2) the problem is n1 - n2 = -5 with unit weights (grasp_condition is infinite,
    // rank 2, but this reduced problem's condition is 1): the normal forces' error is at most
    // the residual the solver accepts. The ray's projection (f.a) a with a = +-x: its y and z
    // parts are products with zeros, at most 2 roundings of |f| (support/tolerance.hpp).
    const double eq = equilibrium_tolerance(g, w, sol.forces);
    CHECK(std::abs(double(sol.forces(0)) - n1) <= eq);
    CHECK(std::abs(double(sol.forces(3)) + n2) <= eq);
    CHECK(double(sol.forces.template segment<2>(1).norm()) <= grip_test::roundoff<S>(2, 1, n2));  // no friction
    const double f2 = s > 2.5 ? 6.25 : 8.5;
    CHECK(std::abs(double(sol.objective) - f2) <= objective_tolerance(g, w, sol, f2));
    check_kkt(g, w, sol);
  }
}

TEST_CASE_TEMPLATE("solve_constrained: infeasible wrenches get a checked certificate", S, double, float) {
  // Three hard fingers on top of an object, pushing down (a = -z); the external wrench also
  // pushes down: G f = -w_ext needs an upward force, but every cone has f.a >= 0, i.e. f_z <= 0.
  // Farkas by hand: y = (0, 0, -1, 0, 0, 0) has G_i^T y = -e_z = a_i (inside K_i^*), y.w_ext > 0.
  Grasp<3, HardFinger, S> g;
  for (int i = 0; i < 3; ++i) {
    Contact<S> c;
    const double phi = 2.0943951023931953 * i;
    c.position << S(0.02 * std::cos(phi)), S(0.02 * std::sin(phi)), S(0.03);
    c.normal << S(0), S(0), S(-1);
    c.friction = S(0.8);
    c.squeeze = S(1);
    REQUIRE(g.set(i, c) == Status::Ok);
  }
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-5);
  w(3) = S(0.01);
  const auto sol = solve_constrained(g, w);
  REQUIRE(sol.status == Status::Infeasible);
  const Wrench<double> y = sol.certificate.template cast<double>();
  // A certificate of dual norm 1, |(y_f, L y_m)| with L the longest lever arm (docs/solve.md):
  // y / |y|_L* in S, a few roundings of 1 (k = 4, support/tolerance.hpp).
  const double len = grip_test::grasp_lever_length(g);
  CHECK(std::abs(grip_test::dual_norm_l(y, len) - 1.0) <= grip_test::roundoff<S>(4, 1, 1));
  CHECK(y.dot(w.template cast<double>()) > 0.0);
  const ConstrainedSettings<S> st;
  for (int i = 0; i < 3; ++i) {
    const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
    // The solver's acceptance (is_infeasibility_certificate): z = G_i^T y within
    // certificate_tolerance (1 + |r_i| / L) of K_i^*, the solver's contract per type (1e-5 in
    // double, 2e-3 in float); mu |z_t| - z_n is sqrt(1 + mu^2) times that distance. Plus the
    // rounding of z and of the test in S, 8 roundings of |y|_L* (1 + |r_i| / L) through 1 + mu.
    const double reach = 1 + c.position.norm() / len, mu = c.friction;
    CHECK(grip_test::dual_cone_violation<HardFinger>(c, HardFinger::wrench_transpose(c, y)) <=
          std::sqrt(1 + mu * mu) * double(st.certificate_tolerance) * reach + grip_test::roundoff<S>(8, 1 + mu, reach));
  }
  // The closest forces: inside the cones; the least residual is |(0,0,-5)| pushed against
  // (forces can only add -z), i.e. at least 5 N: the best is f = 0-ish with residual >= 5.
  CHECK(sol.forces.allFinite());
  // The residual in S: 3 + 4 roundings of its terms |w_ext| + sum (1 + |r_i|) |x_i|, and the
  // forces' f_z <= 0 to the cone tolerance below, a few more (k = 3 + 12).
  double terms = double(w.norm());
  for (int i = 0; i < 3; ++i)
    terms += (1 + double(g.contact(i).position.norm())) * double(sol.forces.template segment<3>(3 * i).norm());
  CHECK(double(sol.residual) >= 5.0 - grip_test::roundoff<S>(3 + 12, 1, terms));
  // In its cone: a projection sn a + beta v_t, both parts proportional to sn, so on the cone to
  // a few roundings of its own size |x_i| (k = 8), through 1 + mu (see cone_condition).
  for (int i = 0; i < 3; ++i)
    CHECK(grip_test::cone_violation<HardFinger>(grip_test::cast_contact<double>(g.contact(i)),
                                                sol.forces.template segment<3>(3 * i)) <=
          grip_test::roundoff<S>(8, 1 + double(g.contact(i).friction),
                                 double(sol.forces.template segment<3>(3 * i).norm())));
  // An empty Dynamic grasp: only w_ext = 0 is balanced.
  DynamicGrasp<HardFinger, S> empty;
  CHECK(solve_constrained(empty, w).status == Status::Infeasible);
  CHECK(solve_constrained(empty, Wrench<S>(Wrench<S>::Zero())).status == Status::Ok);
}

TEST_CASE_TEMPLATE("solve_constrained: fast path returns solve_range_space's optimum", S, double, float) {
  // Large squeeze, small load: the unconstrained optimum is strictly inside every cone.
  std::mt19937 rng(77);
  using GraspT = Grasp<10, HardFinger, S>;
  GraspT g = grip_test::random_grasp<GraspT>(rng, 10);
  for (int i = 0; i < 10; ++i) {
    Contact<S> c = g.contact(i);
    c.squeeze = S(20);
    c.friction = S(1);
    REQUIRE(g.set(i, c) == Status::Ok);
  }
  Wrench<S> w = grip_test::random_wrench<S>(rng) * S(0.1);
  const auto sol = solve_constrained(g, w);
  const auto ref = solve_range_space(g, w);
  REQUIRE(sol.status == Status::Ok);
  CHECK(sol.fast_path);
  CHECK(sol.iterations == 0);
  // The same range-space solve: any difference is its re-rounding, u times grasp_condition times
  // the size of the data, to first order (support/tolerance.hpp, k = 1).
  CHECK(double((sol.forces - ref.forces).norm()) <=
        grip_test::roundoff<S>(1, grip_test::grasp_condition(g), double(ref.forces.norm() + w.norm())));
  check_kkt(g, w, sol);
}

TEST_CASE_TEMPLATE("solve_constrained: rank-deficient and ill-conditioned grasps reach the optimum by Newton", S,
                   double, float) {
  // The fast path declines any grasp whose Gram matrix needs a rank fallback
  // (RankFallback::decline); the iteration then starts from zero multipliers.
  // A pinch (rank 5) by hand: hard fingers at x = -/+3 cm, normals +/-x, squeeze 4 N, mu = 1,
  // w_ext = (0, 0, -2, 0, 0, 0). By symmetry f_i = 4 a_i + (0, 0, 1): the moments
  // r_i x (0, 0, 1) = (0, -/+0.03, 0) cancel, |f_t| = 1 < mu f_n = 4, F2 = 2 * 1/2 * 1 = 1.
  Grasp<2, HardFinger, S> pinch;
  for (int i = 0; i < 2; ++i) {
    Contact<S> c;
    const S side = i == 0 ? S(-1) : S(1);
    c.position << S(0.03) * side, S(0), S(0);
    c.normal << -side, S(0), S(0);
    c.friction = S(1);
    c.squeeze = S(4);
    REQUIRE(pinch.set(i, c) == Status::Ok);
  }
  Wrench<S> w = Wrench<S>::Zero();
  w(2) = S(-2);
  const auto sol = solve_constrained(pinch, w);
  REQUIRE(sol.status == Status::Ok);
  CHECK_FALSE(sol.fast_path);
  Eigen::Matrix<S, 6, 1> expect;
  expect << S(4), S(0), S(1), S(-4), S(0), S(1);
  CHECK(double((sol.forces - expect).norm()) <=
        grip_test::grasp_condition(pinch) * equilibrium_tolerance(pinch, w, sol.forces));
  CHECK(std::abs(double(sol.objective) - 1.0) <= objective_tolerance(pinch, w, sol, 1.0));
  check_kkt(pinch, w, sol);
  // Full rank but ill-conditioned (grip_test::tetrahedron_cluster): the Schur complement's
  // determinant is under rank_tolerance (declined) while pivoted LDL^T accepts it. The
  // unconstrained optimum (solve_range_space's, Ok) is inside the cones and so is the answer.
  const auto cluster = grip_test::tetrahedron_cluster<S>(S(10));
  const S rho = std::abs(cluster.contact(0).position.y());
  // A push of 39 N along +x against the four 10 N squeezes, with moments that the normal
  // forces' differences (about 10 %) balance on the cluster's lever arms of rho (its corners'
  // coordinates about the centre).
  Wrench<S> load = Wrench<S>::Zero();
  load(0) = S(39);
  load(4) = S(0.4) * rho;
  load(5) = S(-0.4) * rho;
  const auto ref = solve_range_space(cluster, load);
  REQUIRE(ref.status == Status::Ok);
  const auto got = solve_constrained(cluster, load);
  REQUIRE(got.status == Status::Ok);
  CHECK_FALSE(got.fast_path);
  CHECK(double((got.forces - ref.forces).norm()) <=
        grip_test::grasp_condition(cluster) * equilibrium_tolerance(cluster, load, got.forces));
  check_kkt(cluster, load, got);
}

TEST_CASE_TEMPLATE("solve_constrained: warm starts of a slowly moving grasp", S, double, float) {
  // 20 hard fingers on a 4 cm sphere, low squeeze (active cones); the object turns slowly and
  // the load swings: each frame solved cold and warm-started from the previous multipliers.
  using GraspT = Grasp<20, HardFinger, S>;
  std::mt19937 rng(5);
  grip_test::Uniform u01(0, 1);
  double th[20], ph[20];
  for (int i = 0; i < 20; ++i) {
    th[i] = std::acos(1 - 2 * u01(rng));
    ph[i] = 6.283185307179586 * u01(rng);
  }
  Wrench<S> warm = Wrench<S>::Zero();
  int cold_total = 0, warm_total = 0;
  for (int frame = 0; frame < 30; ++frame) {
    GraspT g;
    for (int i = 0; i < 20; ++i)
      REQUIRE(g.set(i, grip_test::sphere_contact<S>(th[i] + 0.002 * frame, ph[i], 0.04, 0.5, 0.3)) == Status::Ok);
    Wrench<S> w;
    w << S(0.5 * std::sin(0.01 * frame)), S(0), S(-4.905), S(0), S(0.01 * std::cos(0.02 * frame)), S(0);
    const auto cold = solve_constrained(g, w);
    REQUIRE(cold.status == Status::Ok);
    if (frame > 0) {
      const auto hot = solve_constrained(g, w, ConstrainedSettings<S>{}, warm);
      REQUIRE(hot.status == Status::Ok);
      // Both answers meet the solver's acceptance, each within objective_tolerance of F2* and
      // within grasp_condition times its accepted residual of x* (first order, J = I; an active
      // cone's J <= I could only worsen it: observed at most 0.0002 of this in float).
      CHECK(std::abs(double(hot.objective - cold.objective)) <=
            objective_tolerance(g, w, hot, double(cold.objective)) +
                objective_tolerance(g, w, cold, double(cold.objective)));
      CHECK(double((hot.forces - cold.forces).norm()) <=
            grip_test::grasp_condition(g) *
                (equilibrium_tolerance(g, w, hot.forces) + equilibrium_tolerance(g, w, cold.forces)));
      cold_total += cold.passes;
      warm_total += hot.passes;
    }
    warm = cold.multipliers;
  }
  MESSAGE("passes over 29 frames: cold ", cold_total, ", warm ", warm_total);
  CHECK(warm_total < cold_total);
}

TEST_CASE_TEMPLATE("solve_constrained: a warm start follows a slowly moving grasp in a few Newton passes", S, double,
                   float) {
  // The contract: warm-started from the previous frame's multipliers, a frame whose contacts
  // moved by up to 1 mm and whose load changed by a few percent is answered by Newton's method
  // on the dual alone (no interior-point iteration, KKT exact) in at most warm_pass_bound
  // passes, line-search trials included, while the same frame solved cold needs the
  // interior-point method and more than twice as many passes (so that a warm start that is
  // ignored, or that starts anywhere but near the optimum, breaks the bound).
  // warm_pass_bound is one pass above the most any frame here takes, in float or in double.
  constexpr int warm_pass_bound = 7;
  // Five hard fingers (mu 0.3, squeeze 0.2 N) at seeded points of a 4 cm sphere that turns by
  // 0.025 rad a frame about a fixed axis; the load is a 0.5 kg weight swinging by 10 % with a
  // lateral push of at most 0.7 N and small moments: consecutive loads differ by at most 3.5 %.
  // The low friction and squeeze keep cones active, where the unconstrained optimum's
  // multipliers (the cold start) are too far for Newton's method.
  using GraspT = Grasp<Dynamic, HardFinger, S, 20>;
  std::mt19937 rng(5);
  grip_test::Uniform u01(0, 1);
  Eigen::Vector3d dirs[5];
  for (Eigen::Vector3d& u : dirs) {
    const double th = std::acos(1 - 2 * u01(rng)), ph = 6.283185307179586 * u01(rng);
    u = Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  }
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  Wrench<S> warm = Wrench<S>::Zero();
  for (int frame = 0; frame < 30; ++frame) {
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.025 * frame, axis).toRotationMatrix();
    GraspT g;
    for (const Eigen::Vector3d& u0 : dirs) {
      const Eigen::Vector3d u = turn * u0;
      Contact<S> c;
      c.position = (0.04 * u).cast<S>();
      c.normal = (-u).cast<S>();
      c.friction = S(0.3);
      c.squeeze = S(0.2);
      REQUIRE(g.add(c) == Status::Ok);
    }
    Wrench<S> w;
    w << S(0.5 * std::sin(0.2 * frame)), S(0.5), S(-4.905 * (1 + 0.1 * std::sin(0.3 * frame))),
        S(0.01 * std::cos(0.3 * frame)), S(0.01), S(0);
    const auto cold = solve_constrained(g, w);
    REQUIRE(cold.status == Status::Ok);
    if (frame == 0) {
      warm = cold.multipliers;
      continue;
    }
    const auto hot = solve_constrained(g, w, ConstrainedSettings<S>{}, warm);
    REQUIRE(hot.status == Status::Ok);
    CHECK(hot.refined);
    CHECK(hot.iterations == 0);
    CHECK(hot.passes <= warm_pass_bound);
    CHECK(cold.iterations > 0);
    CHECK(cold.passes > 2 * warm_pass_bound);
    // The same optimum either way (as in the test above).
    CHECK(std::abs(double(hot.objective - cold.objective)) <=
          objective_tolerance(g, w, hot, double(cold.objective)) +
              objective_tolerance(g, w, cold, double(cold.objective)));
    warm = hot.multipliers;  // as a haptic loop chains them
  }
}

TEST_CASE_TEMPLATE("solve_constrained: a contact at its apex can be dropped, the others' optimum unchanged", S, double,
                   float) {
  // What lets the haptic pipeline skip a second solve after dropping separating contacts: if
  // x_j = 0 at the optimum, the remaining forces are feasible for the grasp without contact j
  // (G_j 0 = 0) and optimal there (a better one, with x_j = 0 added, would beat the optimum),
  // and F2 drops by the constant w_j |t_j|^2 / 2. Checked on seeded random grasps of 12
  // contacts with low squeeze (many at their apex), hard and soft fingers, against a cold solve
  // of the reduced grasp: both answers meet the solver's acceptance for the reduced problem.
  const auto check_model = [](auto model_tag) {
    using M = decltype(model_tag);
    using GraspT = DynamicGrasp<M, S>;
    constexpr int d = M::dim;
    std::mt19937 rng(77 + d);
    int compared = 0;
    for (int k = 0; k < 60; ++k) {
      const GraspT g = grip_test::random_grasp<GraspT>(rng, 12);
      const Wrench<S> w = grip_test::random_wrench<S>(rng);
      const auto full = solve_constrained(g, w);
      if (full.status != Status::Ok) continue;
      GraspT reduced;
      typename GraspT::ForceVector kept(g.unknowns());
      double dropped_f2 = 0;
      int nk = 0;
      for (int i = 0; i < g.size(); ++i) {
        const auto xi = full.forces.template segment<d>(i * d);
        if (xi.isZero(0)) {  // exactly the apex: a projection onto it writes zeros
          const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
          dropped_f2 += 0.5 * c.weight * M::target(c).squaredNorm();
          continue;
        }
        REQUIRE(reduced.add(g.contact(i)) == Status::Ok);
        kept.template segment<d>(nk++ * d) = xi;
      }
      if (nk == g.size() || nk < 3) continue;
      kept.conservativeResize(nk * d);
      const auto part = solve_constrained(reduced, w);
      REQUIRE(part.status == Status::Ok);
      ++compared;
      // As for two warm and cold answers of one problem (above): F2 within the objective
      // tolerances, forces within the reduced grasp's condition times the accepted residuals.
      const double f2 = double(part.objective);
      CHECK(std::abs(double(full.objective) - dropped_f2 - f2) <=
            objective_tolerance(reduced, w, part, f2) + objective_tolerance(g, w, full, double(full.objective)) +
                grip_test::roundoff<S>(g.unknowns() + 4, 1, double(full.objective)));
      // An answer of the interior-point method (not refined) is within its gap of F2*: by F2's
      // strong convexity (modulus min w_i = 1 here) within sqrt(2 interior_tolerance F2) of x*.
      const double gap =
          (full.refined ? 0.0 : std::sqrt(2 * double(ScalarTraits<S>::interior_tolerance) * double(full.objective))) +
          (part.refined ? 0.0 : std::sqrt(2 * double(ScalarTraits<S>::interior_tolerance) * f2));
      CHECK(double((part.forces - kept).norm()) <=
            grip_test::grasp_condition(reduced) *
                    (equilibrium_tolerance(reduced, w, part.forces) + equilibrium_tolerance(g, w, full.forces)) +
                gap);
    }
    MESSAGE("model dim ", d, ": ", compared, " grasps with contacts at the apex compared");
    CHECK(compared >= 10);
  };
  check_model(HardFinger{});
  check_model(SoftFinger{});
}

TEST_CASE_TEMPLATE("solve_constrained: bad input gives InvalidInput and zeros", S, double, float) {
  std::mt19937 rng(9);
  using GraspT = DynamicGrasp<HardFinger, S>;
  GraspT g = grip_test::random_grasp<GraspT>(rng, 5);
  Wrench<S> w = grip_test::random_wrench<S>(rng);
  const auto check_invalid = [&](const ConstrainedSolution<GraspT>& s) {
    CHECK(s.status == Status::InvalidInput);
    CHECK(s.forces.size() == g.unknowns());
    CHECK(s.forces.isZero(S(0)));
    CHECK(s.multipliers.isZero(S(0)));
  };
  Wrench<S> bad = w;
  bad(4) = std::numeric_limits<S>::quiet_NaN();
  check_invalid(solve_constrained(g, bad));
  bad(4) = std::numeric_limits<S>::infinity();
  check_invalid(solve_constrained(g, bad));
  check_invalid(solve_constrained(g, w, ConstrainedSettings<S>{}, bad));  // non-finite warm start
  ConstrainedSettings<S> st;
  st.tolerance = S(-1);
  check_invalid(solve_constrained(g, w, st));
  st = ConstrainedSettings<S>{};
  st.max_iterations = 0;
  check_invalid(solve_constrained(g, w, st));
  Grasp<3, HardFinger, S> incomplete;  // slots never set
  CHECK(solve_constrained(incomplete, w).status == Status::InvalidInput);
  // A tiny iteration bound on a problem with active cones: IterationLimit, forces still in cones.
  st = ConstrainedSettings<S>{};
  st.max_iterations = 1;
  GraspT low;
  for (int i = 0; i < 5; ++i)
    REQUIRE(low.add(grip_test::sphere_contact<S>(0.5 + i, 1.3 * i, 0.04, 0.3, 0.1)) == Status::Ok);
  Wrench<S> load = Wrench<S>::Zero();
  load(0) = S(3);
  load(2) = S(-4);
  const auto lim = solve_constrained(low, load, st);
  CHECK((lim.status == Status::IterationLimit || lim.status == Status::Ok || lim.status == Status::Infeasible));
  CHECK(lim.forces.allFinite());
  CHECK(lim.iterations <= 2 * st.max_iterations);
}

TEST_CASE_TEMPLATE("solve_constrained: every setting is range-checked, defaults by ScalarTraits", S, double, float) {
  std::mt19937 rng(19);
  using GraspT = DynamicGrasp<HardFinger, S>;
  const GraspT g = grip_test::random_grasp<GraspT>(rng, 5);
  const Wrench<S> w = grip_test::random_wrench<S>(rng);
  const ConstrainedSettings<S> d;
  CHECK(d.tolerance == ScalarTraits<S>::constrained_tolerance);
  CHECK(d.certificate_tolerance == ScalarTraits<S>::certificate_tolerance);
  CHECK(d.least_residual_weight == ScalarTraits<S>::least_residual_weight);
  CHECK(d.max_iterations == 40);
  CHECK(d.newton_passes == 8);
  CHECK(solve_constrained(g, w, d).status != Status::InvalidInput);
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  const auto invalid = [&](const char* what, const auto& change) {
    ConstrainedSettings<S> st;
    change(st);
    const auto s = solve_constrained(g, w, st);
    CHECK_MESSAGE(s.status == Status::InvalidInput, what);
    CHECK(s.forces.isZero(S(0)));
  };
  // Reals in (0, 1), NaN and infinity refused; max_iterations >= 1, newton_passes >= 0.
  for (const S b : {S(0), S(-1), S(1), nan, inf}) {
    invalid("tolerance", [b](ConstrainedSettings<S>& st) { st.tolerance = b; });
    invalid("certificate_tolerance", [b](ConstrainedSettings<S>& st) { st.certificate_tolerance = b; });
    invalid("least_residual_weight", [b](ConstrainedSettings<S>& st) { st.least_residual_weight = b; });
  }
  invalid("max_iterations 0", [](ConstrainedSettings<S>& st) { st.max_iterations = 0; });
  invalid("newton_passes -1", [](ConstrainedSettings<S>& st) { st.newton_passes = -1; });
  // The edges in range: accepted. newton_passes = 0 leaves the interior-point method alone, its
  // answer checked from the definitions (cones, equilibrium) and against Newton's optimum.
  ConstrainedSettings<S> edge;
  edge.max_iterations = 1;
  CHECK(solve_constrained(g, w, edge).status != Status::InvalidInput);
  std::mt19937 rng2(23);
  int compared = 0;
  for (int k = 0; k < 40; ++k) {
    const GraspT h = grip_test::random_grasp<GraspT>(rng2, 10);
    const Wrench<S> load = grip_test::random_wrench<S>(rng2);
    ConstrainedSettings<S> alone;
    alone.newton_passes = 0;
    const auto ipm = solve_constrained(h, load, alone);
    const auto full = solve_constrained(h, load);
    CHECK(ipm.status == full.status);
    if (ipm.status != Status::Ok || ipm.fast_path) continue;
    ++compared;
    CHECK_FALSE(ipm.refined);
    check_kkt(h, load, ipm);
    const double f2 = double(full.objective);
    CHECK(std::abs(double(ipm.objective) - f2) <=
          objective_tolerance(h, load, ipm, f2) + objective_tolerance(h, load, full, f2));
  }
  CHECK(compared >= 10);
}

TEST_CASE_TEMPLATE("solve_constrained: IterationLimit by a bound that bites, forces in the cones", S, double, float) {
  // Five hard fingers, mu = 0.3, a load that the squeeze targets alone do not balance inside
  // the cones: the interior-point method alone (newton_passes = 0) needs several iterations.
  using GraspT = DynamicGrasp<HardFinger, S>;
  GraspT g;
  for (int i = 0; i < 5; ++i)
    REQUIRE(g.add(grip_test::sphere_contact<S>(0.5 + i, 1.3 * i, 0.04, 0.3, 0.1)) == Status::Ok);
  Wrench<S> load = Wrench<S>::Zero();
  load(0) = S(3);
  load(2) = S(-4);
  ConstrainedSettings<S> st;
  st.newton_passes = 0;
  const auto full = solve_constrained(g, load, st);
  REQUIRE(full.status == Status::Ok);
  st.max_iterations = 2;
  REQUIRE(full.iterations > st.max_iterations);
  const auto cut = solve_constrained(g, load, st);
  CHECK(cut.status == Status::IterationLimit);
  CHECK(cut.iterations <= st.max_iterations);
  CHECK(cut.passes <= 3 * st.max_iterations + 2);
  REQUIRE(cut.forces.allFinite());
  // Each force in its Coulomb cone, checked by hand: f.a >= 0 and |f - (f.a) a| <= mu f.a, to
  // a few roundings of its own size |f| (k = 8; the friction part through 1 + mu).
  double terms = double(load.norm());
  for (int i = 0; i < g.size(); ++i) {
    const Vector3<double> a = g.contact(i).normal.template cast<double>();
    const Vector3<double> f = cut.forces.template segment<3>(3 * i).template cast<double>();
    const double fn = f.dot(a), mu = double(g.contact(i).friction);
    CHECK(fn >= -grip_test::roundoff<S>(8, 1, f.norm()));
    CHECK((f - fn * a).norm() <= mu * fn + grip_test::roundoff<S>(8, 1 + mu, f.norm()));
    terms += (1 + double(g.contact(i).position.norm())) * f.norm();
  }
  // and the residual it reports is its own: the sum in S, n + 4 roundings of its terms.
  const double res =
      (g.grasp_matrix().template cast<double>() * cut.forces.template cast<double>() + load.template cast<double>())
          .norm();
  CHECK(std::abs(double(cut.residual) - res) <= grip_test::roundoff<S>(g.size() + 4, 1, terms));
}

TEST_CASE("solve_constrained: nearly infeasible grasps finish where the dual is flat at round-off") {
  // Two of bench_constrained's Distribution/3 grasps (three hard fingers on a 4 cm sphere, mu
  // 0.5, squeeze 0.3, about 5 N of load): equilibrium needs forces of hundreds of newtons, the
  // multipliers reach 1e6 to 1e7, and near the optimum q's rise along a Newton step is below
  // q's own rounding. Armijo on q alone then rejected every trial step but rare lucky ones
  // (338 and 257 passes). The optimum must satisfy the KKT conditions and take few passes.
  struct Case {
    double theta[3], phi[3], w[6];
  };
  const Case cases[] = {
      {{0x1.4ecff4a3f6ca2p+0, 0x1.31e4eba80858fp-1, 0x1.8ab7bd4e828f4p+0},
       {0x1.74e68ed090b25p+2, 0x1.1fde80db868cbp+2, 0x1.66ddfaf91a7b4p+0},
       {0x1.01fa4b0679a8fp-8, -0x1.1780a7d0fded2p-1, -0x1.c9a2f11decb8p+2, -0x1.114c6657f9665p-8, -0x1.c7880a6fbf667p-7,
        -0x1.9fe80917fb6ep-8}},
      {{0x1.a2a8546b79b68p-1, 0x1.91c5a504bb9adp+0, 0x1.4274f2ab1a69p+1},
       {0x1.1517930563a82p+2, 0x1.ed7bf4f34892bp-3, 0x1.5b093c755f402p+2},
       {-0x1.ae7f46a676e2ep-1, -0x1.0394b6195e3cep-1, -0x1.55f16191ec23fp+2, -0x1.9e536278b01a9p-8,
        -0x1.25fda87939b32p-10, -0x1.8cdb14f50af2ap-7}},
  };
  for (const Case& k : cases) {
    Grasp<3, HardFinger, double> g;
    for (int i = 0; i < 3; ++i)
      REQUIRE(g.set(i, grip_test::sphere_contact<double>(k.theta[i], k.phi[i], 0.04, 0.5, 0.3)) == Status::Ok);
    const Wrench<double> w = Eigen::Map<const Wrench<double>>(k.w);
    const auto sol = solve_constrained(g, w);
    REQUIRE(sol.status == Status::Ok);
    CHECK(sol.multipliers.norm() > 1e6);  // the regime this case is about
    check_kkt(g, w, sol);
  }
}

TEST_CASE("solve_constrained: a normal off unit within its tolerance keeps the forces in the cone") {
  // The fuzzer's finding float_soft_finger_normal_off_unit: one float soft finger whose normal
  // has |a| = 0.99992 (validate accepts |a|^2 within 2e-4 of 1), mu = 177, and a load it
  // cannot hold. Its least-residual forces are the projection of a v of hundreds of newtons
  // near the polar cone, and a cone whose axis is short by 8e-5 misplaces that projection by
  // |v| times 1.6e-4: the forces missed the cone by 8e-4 N (0.14 N of margin) at |x| = 0.7 N.
  Contact<float> c;
  c.position << 0x1.5bcp-137f, 0x1.fffffep-60f, 0x1.0f5c28p-8f;
  c.normal << -0x1.fff5c2p-1f, 0.0f, 0.0f;
  c.friction = 0x1.62101ap+7f;
  c.torsional_friction = 0x1.47ae14p-7f;
  c.squeeze = 0x1.78002ap-126f;
  DynamicGrasp<SoftFinger, float> g;
  REQUIRE(g.add(c) == Status::Ok);
  Wrench<float> w;
  w << 0x1.4c485ap-55f, 0x1.70a3d6p-9f, 0x1.ccccccp-9f, 0x1.028f5cp-7f, 0x1.333332p-8f, 0.0f;
  for (int k = 0; k < 2; ++k) {
    const auto sol = k == 0
                         ? solve_constrained(g, w)
                         : solve_constrained(g, w, ConstrainedSettings<float>{}, Wrench<float>(Wrench<float>::Zero()));
    CHECK(sol.status == Status::Infeasible);
    // In the cone about the normal the user meant (c's, scaled to unit length in double), to a
    // projection's few roundings of its own size (k = 8, through 1 + mu).
    Contact<double> unit = grip_test::cast_contact<double>(c);
    unit.normal.normalize();
    const Eigen::Vector4d x = sol.forces.template segment<4>(0).template cast<double>();
    CHECK(grip_test::cone_violation<SoftFinger>(unit, x) <= grip_test::roundoff<float>(8, 1 + unit.friction, x.norm()));
  }
}

TEST_CASE("solve_constrained: warm starts near the optimum of nearly infeasible grasps") {
  // Three more Distribution/3 grasps, multipliers of 1e6 to 1e7, warm-started within 1e-4
  // (relative) of the optimum in random directions, as a haptic loop's next frame or another
  // method's estimate gives. Newton's steps land on kinks of q (a contact's projection changing
  // region); the next line search must not take the kink it stands on, to its rounding, for a
  // kink ahead (it would stop there with IterationLimit: half of these starts did).
  struct Case {
    double theta[3], phi[3], w[6];
  };
  const Case cases[] = {
      {{0x1.35b340937cddcp+0, 0x1.47a14bdaf9699p+1, 0x1.f32b8303baf66p+0},
       {0x1.a8f88bd218781p+0, 0x1.69c845fca4b0ap+1, 0x1.e893bb120ef73p+1},
       {0x1.18665eb73fa47p+0, -0x1.24ce4ecdba48ap-2, -0x1.699202bfb92aap+2, -0x1.785cad51c3d3ap-7,
        -0x1.4b2abc43f205cp-18, -0x1.8b26211c19f24p-7}},
      {{0x1.c91aed473fe55p+0, 0x1.777298b03533ap+1, 0x1.9b272e634a89p+0},
       {0x1.93c6c31ea54fp+0, 0x1.074ae57ca2ffap+0, 0x1.670b2ba6200bap+2},
       {-0x1.62bce38332d72p-2, -0x1.0158dc5274768p+0, -0x1.a0369f5a948a3p+2, -0x1.d28c4f29ce83ep-7,
        -0x1.6466f2940e2dbp-8, 0x1.2ad73b70d9895p-8}},
      {{0x1.d702fe877f2ccp+0, 0x1.38411fd48f239p+0, 0x1.0349b2fe776b1p+1},
       {0x1.2181da7df7334p+1, 0x1.357a45051178dp-4, 0x1.e184bf97cd96ap+0},
       {0x1.3b4e182683ecap+0, -0x1.452ce612472d4p-1, -0x1.51dac906fe794p+2, 0x1.8e05b71aacdeap-7, 0x1.df381a6e6dad1p-7,
        -0x1.91ef7a978f392p-8}},
  };
  std::mt19937 rng(11);
  std::normal_distribution<double> n01(0, 1);
  for (const Case& k : cases) {
    Grasp<3, HardFinger, double> g;
    for (int i = 0; i < 3; ++i)
      REQUIRE(g.set(i, grip_test::sphere_contact<double>(k.theta[i], k.phi[i], 0.04, 0.5, 0.3)) == Status::Ok);
    const Wrench<double> w = Eigen::Map<const Wrench<double>>(k.w);
    const auto cold = solve_constrained(g, w);
    REQUIRE(cold.status == Status::Ok);
    CHECK(cold.multipliers.norm() > 1e5);
    for (int rep = 0; rep < 10; ++rep) {
      Wrench<double> p;
      for (int j = 0; j < 6; ++j) p(j) = n01(rng);
      const Wrench<double> warm = cold.multipliers + 1e-4 * cold.multipliers.norm() / p.norm() * p;
      const auto sol = solve_constrained(g, w, ConstrainedSettings<double>{}, warm);
      CAPTURE(rep);
      REQUIRE(sol.status == Status::Ok);
      check_kkt(g, w, sol);
    }
  }
}

// Three hard fingers on a 4 cm sphere, mu 0.3 to 1, loads of 0.5 to 200 N in random
// directions with moments (bench_constrained's Loads/3: about half slip).
template <class S>
void slip_instance(std::mt19937& rng, Grasp<3, HardFinger, S>& g, Wrench<S>& w) {
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> n01(0, 1);
  for (int i = 0; i < 3; ++i)
    REQUIRE(g.set(i, grip_test::sphere_contact<S>(std::acos(1 - 2 * u01(rng)), 6.283185307179586 * u01(rng), 0.04,
                                                  0.3 + 0.7 * u01(rng), 0.3)) == Status::Ok);
  Wrench<double> wd;
  for (int j = 0; j < 6; ++j) wd(j) = (j < 3 ? 1.0 : 0.03) * n01(rng);
  const double size = 0.5 * std::pow(400.0, u01(rng));
  wd.head<3>() *= size / wd.head<3>().norm();
  wd.tail<3>() *= size;
  w = wd.cast<S>();
}

TEST_CASE_TEMPLATE("solve_constrained: grasps that slip or hold are decided within the bound, checked by definition", S,
                   double, float) {
  // Every solve ends Ok or Infeasible (none at IterationLimit with the default bound), within
  // max_iterations interior-point iterations. Ok: the KKT conditions. Infeasible: the certificate
  // from its definition, and the least-residual forces no worse, by P = |r|_L^2 / 2 + delta F2,
  // than two other points of the cones: zero, and the unconstrained optimum projected onto them.
  std::mt19937 rng(2424);
  const ConstrainedSettings<S> st;
  int slips = 0, holds = 0, worst = 0, beyond = 0;
  const int count = grip_test::scaled(400, 100);  // GRIP_TEST_SCALE
  for (int k = 0; k < count; ++k) {
    Grasp<3, HardFinger, S> g;
    Wrench<S> w;
    slip_instance(rng, g, w);
    const auto sol = solve_constrained(g, w);
    CHECK(sol.iterations <= st.max_iterations);
    if (std::is_same<S, float>::value && sol.status == Status::IterationLimit) {
      // Float's one allowance: a grasp that holds only with multipliers beyond 1 / eps of float
      // (forces of 1e8 N and more for these loads), where float resolves neither the optimum nor
      // a certificate. Checked in double; rare.
      Grasp<3, HardFinger, double> gd;
      for (int i = 0; i < 3; ++i) REQUIRE(gd.set(i, grip_test::cast_contact<double>(g.contact(i))) == Status::Ok);
      const auto sd = solve_constrained(gd, Wrench<double>(w.template cast<double>()));
      CHECK(sd.status == Status::Ok);
      CHECK(sd.multipliers.norm() > 1.0 / double(std::numeric_limits<float>::epsilon()));
      ++beyond;
      continue;
    }
    REQUIRE((sol.status == Status::Ok || sol.status == Status::Infeasible));
    worst = std::max(worst, sol.iterations);
    if (sol.status == Status::Ok) {
      ++holds;
      check_kkt(g, w, sol);
      continue;
    }
    ++slips;
    const Wrench<double> wd = w.template cast<double>();
    grip_test::check_certificate(g, w, sol.certificate);
    const double delta = grip_test::least_residual_delta(g);
    const Eigen::VectorXd x = sol.forces.template cast<double>();
    const auto ref = solve_range_space(g, w);
    Eigen::VectorXd projected = Eigen::VectorXd::Zero(9);
    for (int i = 0; i < 3 && ref.status == Status::Ok; ++i) {
      const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
      projected.segment<3>(3 * i) =
          CoulombCone<double>::from_contact(c).project(ref.forces.template segment<3>(3 * i).template cast<double>());
    }
    // To the interior-point method's tolerance on the least-residual problem: a gap of
    // interior_tolerance of the objective, plus the rounding of P in S.
    const double p = grip_test::least_residual_objective(g, wd, x, delta);
    const double slack = 2 * double(ScalarTraits<S>::interior_tolerance) * p +
                         grip_test::roundoff<S>(16, 1, wd.squaredNorm() + x.squaredNorm());
    CHECK(p <= grip_test::least_residual_objective(g, wd, Eigen::VectorXd::Zero(9), delta) + slack);
    CHECK(p <= grip_test::least_residual_objective(g, wd, projected, delta) + slack);
  }
  MESSAGE(holds, " hold, ", slips, " slip; most interior-point iterations ", worst);
  CHECK(beyond <= 2);
  CHECK(slips >= count / 4);
  CHECK(holds >= count / 4);
}

TEST_CASE("solve_constrained: light loads get the verdict of the same load at 1 N, balanced to the load") {
  // The grasps of slip_instance under loads of 0.3 uN to 30 mN, far below the squeezing forces
  // (0.3 N), solved with the defaults and by the interior-point method alone (newton_passes 0).
  // Whether forces in the cones balance a load does not depend on its size, so each verdict must
  // be that of the same load scaled to 1 N. Ok: the forces in the cones and balancing the load to
  // interior_tolerance of the load and the squeezing forces, not of the forces themselves (an
  // infeasible grasp's iterate grows without bound). Infeasible: the certificate by definition.
  std::mt19937 rng(2426);
  std::uniform_real_distribution<double> u01(0, 1);
  ConstrainedSettings<double> alone;
  alone.newton_passes = 0;
  int differ = 0, slips = 0;
  const int count = grip_test::scaled(300, 100);
  for (int k = 0; k < count; ++k) {
    Grasp<3, HardFinger, double> g;
    Wrench<double> w;
    slip_instance(rng, g, w);
    w *= 0.3 * std::pow(10.0, -6.0 + 5.0 * u01(rng)) / w.head<3>().norm();
    const Wrench<double> unit = w / w.norm();
    for (const ConstrainedSettings<double>& st : {ConstrainedSettings<double>{}, alone}) {
      CAPTURE(k);
      CAPTURE(st.newton_passes);
      const auto sol = solve_constrained(g, w, st);
      REQUIRE((sol.status == Status::Ok || sol.status == Status::Infeasible));
      differ += sol.status != solve_constrained(g, unit, st).status;
      if (sol.status == Status::Infeasible) {
        ++slips;
        grip_test::check_certificate(g, w, sol.certificate);
        continue;
      }
      Wrench<double> r = w;
      for (int i = 0; i < 3; ++i) {
        const Contact<double> c = g.contact(i);
        const Vector3<double> x = sol.forces.segment<3>(3 * i);
        CHECK(grip_test::cone_violation<HardFinger>(c, x) <= 1e-12 * (x.norm() + c.squeeze));
        r += HardFinger::wrench(c, x);
      }
      CHECK(r.norm() <= 2 * ScalarTraits<double>::interior_tolerance * (w.norm() + 0.3));
    }
  }
  MESSAGE(slips, " of ", 2 * count, " solves slip; ", differ, " verdicts differ from the load at 1 N");
  CHECK(slips >= count / 2);
  CHECK(differ <= 2);
}

TEST_CASE("solve_constrained: float and double agree on the same grasps") {
  // The same algorithm in both, which differ only in tolerances (ScalarTraits): the grasps of the
  // test above, each solved in double and, rounded to float, in float. The verdicts agree but for
  // grasps within the float certificate tolerance of the boundary (few); the float objective is
  // within its tolerances of the double one (a relative 1e-3, the interior-point tolerance in
  // float, and the shift |lambda| |r| of the float residual).
  std::mt19937 rng(2425);
  int differ = 0, compared = 0;
  const int count = grip_test::scaled(400, 100);
  for (int k = 0; k < count; ++k) {
    Grasp<3, HardFinger, double> g;
    Wrench<double> w;
    slip_instance(rng, g, w);
    Grasp<3, HardFinger, float> gf;
    for (int i = 0; i < 3; ++i) REQUIRE(gf.set(i, grip_test::cast_contact<float>(g.contact(i))) == Status::Ok);
    const Wrench<float> wf = w.cast<float>();
    // The double problem is the float one's data, widened: both solve the same instance.
    Grasp<3, HardFinger, double> gd;
    for (int i = 0; i < 3; ++i) REQUIRE(gd.set(i, grip_test::cast_contact<double>(gf.contact(i))) == Status::Ok);
    const auto a = solve_constrained(gd, Wrench<double>(wf.cast<double>()));
    const auto b = solve_constrained(gf, wf);
    if (a.status != b.status) {
      ++differ;
      continue;
    }
    if (a.status != Status::Ok) continue;
    ++compared;
    const double shift = (a.multipliers.norm() + b.multipliers.cast<double>().norm()) * double(b.residual);
    CHECK(std::abs(double(b.objective) - a.objective) <= 1e-3 * a.objective + shift + 1e-6);
  }
  MESSAGE(compared, " compared, ", differ, " verdicts differ");
  CHECK(compared >= count / 4);
  CHECK(differ <= count / 50);
}

TEST_CASE_TEMPLATE("solve_constrained: bounds on the normal forces (hand derivations)", S, double, float) {
  // A pinch: hard fingers at x = -/+3 cm, normals +/-x, mu = 1, squeeze 4 N, w_ext = (0, 0, -W).
  // Unbounded, f_i = 4 a_i + (0, 0, W/2) (the moments cancel). With f_n <= c < 4 on both, the
  // normal parts go to c (F2 rises by (4 - c)^2 per finger) while W/2 <= mu c: f_i = c a_i +
  // (0, 0, W/2), F2 = (4 - c)^2 + W^2 / 4. With W/2 > mu c no forces hold it: y = (0, 0, -1, 0,
  // 0, 0) (unit) has y.w_ext = W, G_i^T y = -e_z with phi_i = 0 - mu * 1 = -1 at unit normal
  // force, a deficit of 2 c < W: a certificate of the bounded definition.
  const auto pinch = [](double c) {
    Grasp<2, HardFinger, S> g;
    for (int i = 0; i < 2; ++i) {
      Contact<S> k;
      const S side = i == 0 ? S(-1) : S(1);
      k.position << S(0.03) * side, S(0), S(0);
      k.normal << -side, S(0), S(0);
      k.friction = S(1);
      k.squeeze = S(4);
      k.max_normal_force = S(c);
      REQUIRE(g.set(i, k) == Status::Ok);
    }
    return g;
  };
  for (const double c : {10.0, 3.0, 1.5}) {
    const auto g = pinch(c);
    Wrench<S> w = Wrench<S>::Zero();
    w(2) = S(-2);
    const auto sol = solve_constrained(g, w);
    REQUIRE(sol.status == Status::Ok);
    const double fn = std::min(c, 4.0);
    Eigen::Matrix<S, 6, 1> expect;
    expect << S(fn), S(0), S(1), S(-fn), S(0), S(1);
    const double f2 = (4 - fn) * (4 - fn) + 1.0;
    // The active bound leaves the tangential part free: the same first-order argument as the
    // unbounded pinch, through grasp_condition.
    CHECK(double((sol.forces - expect).norm()) <=
          10 * grip_test::grasp_condition(g) * equilibrium_tolerance(g, w, sol.forces) +
              grip_test::roundoff<S>(8, 1, 4.0));
    CHECK(std::abs(double(sol.objective) - f2) <=
          objective_tolerance(g, w, sol, f2) + grip_test::roundoff<S>(8, 1, f2));
    CHECK(double(sol.forces(0)) <= c + grip_test::roundoff<S>(4, 1, c));
  }
  {
    const auto g = pinch(1.5);
    Wrench<S> w = Wrench<S>::Zero();
    w(2) = S(-4);  // W/2 = 2 > mu c = 1.5
    const auto sol = solve_constrained(g, w);
    REQUIRE(sol.status == Status::Infeasible);
    const Wrench<double> y = sol.certificate.template cast<double>();
    const double yw = y.dot(w.template cast<double>());
    CHECK(yw > 0.0);
    double deficit = 0;
    for (int i = 0; i < 2; ++i) {
      const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
      const Vector3<double> z = HardFinger::wrench_transpose(c, y);
      const double zn = z.dot(c.normal);
      deficit += c.max_normal_force * std::max(0.0, -(zn - c.friction * (z - zn * c.normal).norm()));
    }
    CHECK(deficit < yw);
    // The least-residual forces: both fingers at their bound with |f_t| = mu c: the residual
    // 4 - 2 mu c = 1 N along z, the least possible (each finger gives at most mu c upward).
    CHECK(double(sol.residual) >= 1.0 - grip_test::roundoff<S>(16, 1, 8.0));
    CHECK(double(sol.residual) <= 1.0 + 1e-3);
    for (int i = 0; i < 2; ++i) CHECK(std::abs(double(sol.forces(3 * i))) <= 1.5 + grip_test::roundoff<S>(8, 1, 2.0));
  }
  // Frictionless points at x = -/+3 cm, normals +/-x, squeeze 4, w_ext = (5, 0, ...): unbounded
  // n1 = 1.5, n2 = 6.5 (n1 - n2 = -5); with n <= 6: n2 = 6, n1 = 1, F2 = (9 + 4) / 2; with
  // n <= 4: no forces balance w_ext (n2 <= 4 < n1 + 5 needs n1 < -1).
  for (const double c : {6.0, 4.0}) {
    DynamicGrasp<FrictionlessPoint, S> g;
    for (int i = 0; i < 2; ++i) {
      Contact<S> k;
      const S side = i == 0 ? S(-1) : S(1);
      k.position << S(0.03) * side, S(0), S(0);
      k.normal << -side, S(0), S(0);
      k.squeeze = S(4);
      k.max_normal_force = S(c);
      REQUIRE(g.add(k) == Status::Ok);
    }
    Wrench<S> w = Wrench<S>::Zero();
    w(0) = S(5);
    const auto sol = solve_constrained(g, w);
    if (c == 4.0) {
      CHECK(sol.status == Status::Infeasible);
      CHECK(double(sol.residual) >= 1.0 - grip_test::roundoff<S>(16, 1, 8.0));
      continue;
    }
    REQUIRE(sol.status == Status::Ok);
    const double eq = equilibrium_tolerance(g, w, sol.forces);
    CHECK(std::abs(double(sol.forces(0)) - 1.0) <= 2 * eq + grip_test::roundoff<S>(8, 1, 6.0));
    CHECK(std::abs(double(sol.forces(1)) - 6.0) <= 2 * eq + grip_test::roundoff<S>(8, 1, 6.0));
    CHECK(std::abs(double(sol.objective) - 6.5) <=
          objective_tolerance(g, w, sol, 6.5) + grip_test::roundoff<S>(8, 1, 6.5));
  }
}

TEST_CASE_TEMPLATE("solve_constrained: an inactive bound changes nothing, and soft fingers with bounds", S, double,
                   float) {
  // Random grasps solved without bounds and with bounds above their optimum's normal forces: the
  // same optimum (the bounded solve's refinement projects onto truncated cones whose caps no force
  // reaches). Then bounds at 0.8 of the largest normal forces: every force below its bound.
  const auto check_model = [](auto model_tag) {
    using M = decltype(model_tag);
    using GraspT = DynamicGrasp<M, S>;
    constexpr int d = M::dim;
    std::mt19937 rng(313 + d);
    int compared = 0, capped = 0, stalled = 0;
    for (int k = 0; k < 40; ++k) {
      GraspT g = grip_test::random_grasp<GraspT>(rng, 8);
      const Wrench<S> w = grip_test::random_wrench<S>(rng);
      const auto free = solve_constrained(g, w);
      if (free.status != Status::Ok) continue;
      double fmax = 0;
      std::vector<double> fn(static_cast<std::size_t>(g.size()));
      for (int i = 0; i < g.size(); ++i) {
        const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
        const Eigen::Matrix<double, d, 1> xi = free.forces.template segment<d>(i * d).template cast<double>();
        fn[std::size_t(i)] = grip_test::cone_coordinates<M>(c, xi).n;
        fmax = std::max(fmax, fn[std::size_t(i)]);
      }
      GraspT high = g, low = g;
      for (int i = 0; i < g.size(); ++i) {
        Contact<S> c = g.contact(i);
        c.max_normal_force = S(2 * fmax + 1);
        REQUIRE(high.set(i, c) == Status::Ok);
        if (fn[std::size_t(i)] > 0.5 * fmax && fmax > 0.1) c.max_normal_force = S(0.8 * fn[std::size_t(i)]);
        REQUIRE(low.set(i, c) == Status::Ok);
      }
      const auto same = solve_constrained(high, w);
      REQUIRE(same.status == Status::Ok);
      ++compared;
      const double f2 = double(free.objective);
      CHECK(std::abs(double(same.objective) - f2) <=
            objective_tolerance(g, w, free, f2) + objective_tolerance(high, w, same, f2));
      const auto cut = solve_constrained(low, w);
      // Float's allowance: soft fingers with bounds have the interior-point method alone, whose
      // float iterates can stall short of its tolerance (none to two grasps in forty here, by
      // the compiler's contractions: two on armhf, whose VFP has no fused multiply-add; see
      // docs/solve.md, known limits).
      if (cut.status == Status::IterationLimit && std::is_same<S, float>::value && d == 4) {
        ++stalled;
        continue;
      }
      CHECK(cut.status != Status::IterationLimit);
      if (cut.status != Status::Ok) continue;
      ++capped;
      CHECK(double(cut.objective) >= f2 - objective_tolerance(g, w, free, f2));  // a smaller feasible set
      for (int i = 0; i < g.size(); ++i) {
        const Contact<double> c = grip_test::cast_contact<double>(low.contact(i));
        const Eigen::Matrix<double, d, 1> xi = cut.forces.template segment<d>(i * d).template cast<double>();
        CHECK(grip_test::cone_coordinates<M>(c, xi).n <= c.max_normal_force * (1 + 1e-6) + 1e-9);
        CHECK(grip_test::cone_violation<M>(c, xi) <= grip_test::roundoff<S>(16, cone_condition<M>(c), 1 + xi.norm()));
      }
    }
    MESSAGE("model dim ", d, ": ", compared, " compared, ", capped, " held under lower bounds");
    CHECK(stalled <= 2);
    CHECK(compared >= 10);
    CHECK(capped >= 3);
  };
  // (Random frictionless grasps rarely hold: the hand derivation above covers that model.)
  check_model(HardFinger{});
  check_model(SoftFinger{});
}

TEST_CASE("solve_constrained allocates nothing (fixed, Dynamic, every model, infeasible too)") {
  std::mt19937 rng(31);
  Grasp<20, HardFinger, double> h = grip_test::random_grasp<Grasp<20, HardFinger, double>>(rng, 20);
  DynamicGrasp<SoftFinger, float> s = grip_test::random_grasp<DynamicGrasp<SoftFinger, float>>(rng, 12);
  DynamicGrasp<FrictionlessPoint, double> f = grip_test::random_grasp<DynamicGrasp<FrictionlessPoint, double>>(rng, 12);
  const Wrench<double> w = grip_test::random_wrench<double>(rng);
  Wrench<double> big = w * 1e3;
  Grasp<20, HardFinger, double> bounded = h;
  for (int i = 0; i < 20; ++i) {
    Contact<double> c = h.contact(i);
    c.max_normal_force = 0.5;
    REQUIRE(bounded.set(i, c) == Status::Ok);
  }
  grip_test::NoHeapScope scope;
  const auto a = solve_constrained(h, w);
  const auto b = solve_constrained(s, Wrench<float>(w.cast<float>()));
  const auto c = solve_constrained(f, big);
  const auto d = solve_constrained(h, w, ConstrainedSettings<double>{}, a.multipliers);
  const auto e = solve_constrained(bounded, w);
  CHECK(scope.allocations() == 0);
  CHECK(e.status != Status::InvalidInput);
  CHECK(a.status != Status::InvalidInput);
  CHECK(b.status != Status::InvalidInput);
  CHECK(c.status != Status::InvalidInput);
  CHECK(d.status == a.status);
}

TEST_CASE_TEMPLATE("solve_newton_6x6: block adjugates where well-conditioned, else the floored Cholesky", S, double,
                   float) {
  // Random SPD matrices O diag(ev) O^T with unit-scaled diagonals, condition numbers from 1 to
  // 1e12. Where the block solve declines (ill-conditioned; float always) the answer is exactly
  // the floored Cholesky's; where it answers, its residual is within its documented backward
  // error (1e8 eps) and it agrees with the Cholesky to the condition number.
  std::mt19937 rng(91);
  grip_test::Normal n01(0.0, 1.0);
  int by_blocks = 0, fallbacks = 0;
  for (int rep = 0; rep < 2000; ++rep) {
    Eigen::Matrix<double, 6, 6> q;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) q(i, j) = n01(rng);
    const Eigen::HouseholderQR<Eigen::Matrix<double, 6, 6>> qr(q);
    const Eigen::Matrix<double, 6, 6> o = qr.householderQ();
    Eigen::Matrix<double, 6, 1> ev;
    const double decades = double(rep % 13);
    for (int i = 0; i < 6; ++i) ev(i) = std::pow(10.0, -decades * double(i) / 5.0);
    Eigen::Matrix<double, 6, 6> a = o * ev.asDiagonal() * o.transpose();
    const Eigen::Matrix<double, 6, 1> dd = a.diagonal().cwiseSqrt().cwiseInverse();
    a = dd.asDiagonal() * a * dd.asDiagonal();
    Eigen::Matrix<double, 6, 1> b;
    for (int i = 0; i < 6; ++i) b(i) = n01(rng);
    const Matrix6<S> as = a.cast<S>();
    const Wrench<S> bs = b.cast<S>();
    const S floor = std::numeric_limits<S>::epsilon();
    const Wrench<S> y = detail::solve_newton_6x6(as, bs, floor);
    const Wrench<S> yc = detail::solve_floored_6x6(as, bs, floor);
    REQUIRE(y.allFinite());
    if (y == yc) {
      ++fallbacks;
      continue;
    }
    ++by_blocks;
    CAPTURE(rep);
    const Eigen::Matrix<double, 6, 1> yd = y.template cast<double>(), ycd = yc.template cast<double>();
    const double eps = double(std::numeric_limits<S>::epsilon());
    CHECK((a * yd - b).norm() <= 1e8 * eps * (1.0 + a.norm() * yd.norm()));
    CHECK((yd - ycd).norm() <= 1e8 * eps * (1.0 / ev(5)) * (1.0 + ycd.norm()));
  }
  if (std::is_same<S, double>::value) {
    CHECK(by_blocks > 500);
    CHECK(fallbacks > 100);
  } else {
    CHECK(by_blocks == 0);
  }
}
