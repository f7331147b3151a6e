// solve_constrained against an independent conic solver (cvxopt, data made by
// make_constrained_reference.py): random grasps, grasps rescaled by 1e-3 and 1e3, collinear
// contacts (G of rank 5), nearly collinear ones, and grasps with bounds on the normal forces
// (inactive, some at their bound, too low to hold). Checked at every instance: the objective,
// the forces against cvxopt's x*, the multipliers against cvxopt's where they are unique,
// equilibrium, cone feasibility and the bounds from the definitions; for infeasible instances the
// certificate and the least residual against cvxopt's. Residuals are measured as the solver
// documents them, |(f, m)|_L = |(f, m / L)| with L = max_i |r_i| (moments per lever arm), and
// multipliers and certificates in the dual norm |(y_f, L y_m)|; recomputed here in double.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <type_traits>
#include <vector>
#include <string>

#include <grip/solve/solve_constrained.hpp>

#include "solve/constrained_support.hpp"
#include "support/equilibrium_norm.hpp"

using namespace grip;

namespace {

/// The multipliers against cvxopt's lambda*, where they are unique. At a contact strictly inside
/// its cone and below its bound (both solutions, by 0.1 % of the force), stationarity reads w_i (x_i - t_i) =
/// G_i^T lambda. Stacking G_i^T of those contacts into B: ours must hold it to the round-off
/// of the projection x_i = t_i + G_i^T lambda / w_i, 64 eps sqrt(rows) (w_max |x| + |B| |lambda|)
/// (eps of the solver's scalar), and when B has full column rank lambda is unique, so
/// B (lambda - lambda*) = W (x - x*)_I - e + e*, e* cvxopt's own stationarity error, and
/// |lambda - lambda*| <= (w_max |x - x*| + |e| + |e*|) / sigma_min(B).
/// Returns whether lambda was unique (and so compared).
template <class Model>
bool check_multipliers(const grip_test::ConstrainedReference& ref, const Eigen::VectorXd& x,
                       const Wrench<double>& lambda, double dx, double eps, double force_scale, bool refined,
                       double& worst) {
  constexpr int d = Model::dim;
  const Eigen::Map<const Eigen::VectorXd> xs(ref.x.data(), static_cast<Eigen::Index>(ref.x.size()));
  std::vector<int> interior;
  for (int i = 0; i < static_cast<int>(ref.contacts.size()); ++i) {
    const auto& c = ref.contacts[size_t(i)];
    const auto inside = [&](const Eigen::VectorXd& v) {
      const Eigen::VectorXd xi = v.segment<d>(i * d);
      const auto k = grip_test::cone_coordinates<Model>(c, xi);
      const double margin = 1e-3 * xi.norm() + 1e-9;
      double slack = k.n;
      if constexpr (d == 3) slack = std::min(slack, c.friction * k.n - k.t);
      if constexpr (d == 4) {
        const double mu = c.friction, mt = c.torsional_friction;
        slack = std::min(slack, (mu * mt * k.n - std::sqrt(mt * mt * k.t * k.t + mu * mu * k.m * k.m)) / (mu * mt));
      }
      if (c.max_normal_force < std::numeric_limits<double>::infinity())
        slack = std::min(slack, c.max_normal_force - k.n);
      return slack > margin;
    };
    if (inside(x) && inside(xs)) interior.push_back(i);
  }
  const auto rows = static_cast<Eigen::Index>(interior.size()) * d;
  if (rows < 6) return false;
  Eigen::MatrixXd b(rows, 6);
  Eigen::VectorXd e(rows), e_ref(rows), dxi(rows);
  double w_max = 0;
  for (std::size_t j = 0; j < interior.size(); ++j) {
    const int i = interior[j];
    const auto& c = ref.contacts[size_t(i)];
    const auto r = static_cast<Eigen::Index>(j) * d;
    for (int k = 0; k < 6; ++k)
      b.block(r, k, d, 1) = Model::wrench_transpose(c, Wrench<double>(Wrench<double>::Unit(k)));
    e.segment<d>(r) = c.weight * (x.segment<d>(i * d) - Model::target(c)) - Model::wrench_transpose(c, lambda);
    e_ref.segment<d>(r) = c.weight * (xs.segment<d>(i * d) - Model::target(c)) - Model::wrench_transpose(c, ref.lambda);
    w_max = std::max(w_max, c.weight);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(b);
  const double s_min = svd.singularValues()(5), s_max = svd.singularValues()(0);
  const double e_tol = 64 * eps * std::sqrt(double(rows)) * (w_max * force_scale + s_max * lambda.norm());
  if (refined) CHECK_MESSAGE(e.norm() <= e_tol, "stationarity at interior contacts ", e.norm(), " bound ", e_tol);
  if (!(s_min > 1e-6 * s_max)) return false;
  const double bound = (w_max * dx + e.norm() + e_ref.norm()) / s_min * (1 + 1e-9) + 1e-12 * (1 + ref.lambda.norm());
  const double dl = (lambda - ref.lambda).norm();
  worst = std::max(worst, dl);
  CHECK_MESSAGE(dl <= bound, "|lambda - lambda*| ", dl, " bound ", bound, " (", ref.kind, ")");
  return true;
}

template <class Model, class S>
void check_against_reference(const std::vector<grip_test::ConstrainedReference>& data, char tag) {
  using GraspT = Grasp<Dynamic, Model, S, 20>;
  const double obj_tol = std::is_same<S, float>::value ? 1e-3 : 1e-7;
  const ConstrainedSettings<S> settings;
  int count = 0, infeasible = 0, worst_iter = 0;
  double worst_obj = 0, worst_res = 0, worst_cone = 0, worst_x = 0, worst_lambda = 0, worst_least = 0;
  int lambda_checked = 0, marginal = 0, bounded_contacts = 0, stalled = 0;
  const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
  int index = -1;
  for (const auto& ref : data) {
    ++index;
    if (ref.model != tag) continue;
    REQUIRE(static_cast<int>(ref.contacts.size()) == ref.n);
    GraspT g;
    for (const auto& c : ref.contacts) REQUIRE(g.add(grip_test::cast_contact<S>(c)) == Status::Ok);
    const Wrench<S> w = ref.w_ext.cast<S>();
    const auto sol = solve_constrained(g, w, settings);
    ++count;
    worst_iter = std::max(worst_iter, sol.iterations);
    CHECK(sol.iterations <= settings.max_iterations);
    // Whatever the status, the forces are finite and inside the cones (up to round-off).
    double force_scale = ref.w_ext.norm();
    for (int i = 0; i < g.size(); ++i)
      force_scale += sol.forces.template segment<Model::dim>(i * Model::dim).template cast<double>().norm();
    const double cone_tol = (std::is_same<S, float>::value ? 1e-5 : 1e-10) * (1.0 + force_scale);
    for (int i = 0; i < g.size(); ++i) {
      const double v = grip_test::cone_violation<Model>(ref.contacts[size_t(i)],
                                                        sol.forces.template segment<Model::dim>(i * Model::dim));
      worst_cone = std::max(worst_cone, v / (1.0 + force_scale));
      CHECK(v <= cone_tol);
      // and below its bound: f_n from the definition (a.f, or the frictionless unknown).
      const auto& c = ref.contacts[size_t(i)];
      if (c.max_normal_force < std::numeric_limits<double>::infinity()) {
        const Eigen::Matrix<double, Model::dim, 1> xi =
            sol.forces.template segment<Model::dim>(i * Model::dim).template cast<double>();
        const double fn = grip_test::cone_coordinates<Model>(c, xi).n;
        CHECK_MESSAGE(fn <= c.max_normal_force + cone_tol, "instance ", index, " f_n ", fn, " bound ",
                      c.max_normal_force);
        ++bounded_contacts;
      }
    }
    // Equilibrium in double from the double inputs.
    Eigen::Matrix<double, Eigen::Dynamic, 1> xd = sol.forces.template cast<double>();
    Grasp<Dynamic, Model, double, 20> gd;
    for (const auto& c : ref.contacts) (void)gd.add(c);
    const double len = grip_test::lever_length(ref.contacts);
    const double res = grip_test::norm_l(gd.wrench(xd) + ref.w_ext, len);
    const double force_scale_l = force_scale - ref.w_ext.norm() + grip_test::norm_l(ref.w_ext, len);
    const auto check_certificate = [&]() {
      // Farkas: y.w_ext > 0 and G_i^T y in K_i^* for every contact, to within the documented
      // certificate_tolerance (y.w_ext) / |w_ext|_L (checked from the definitions, in double;
      // 50 % (float) and 10 % (double) more for the round-off of the solver's own scalar).
      const Wrench<double> y = sol.certificate.template cast<double>();
      CHECK(grip_test::dual_norm_l(y, len) == doctest::Approx(1.0).epsilon(1e-5));
      const double yw = y.dot(ref.w_ext);
      CHECK(yw > 0.0);
      const double cert_tol = (std::is_same<S, float>::value ? 1.5 : 1.1) *
                              static_cast<double>(settings.certificate_tolerance) * yw /
                              grip_test::norm_l(ref.w_ext, len);
      // A bounded contact needs less (docs/solve.md): over its truncated cone, the least of
      // z.x is c_i min(0, phi_i), phi_i the least of z.x at unit normal force, here by the
      // cone's coordinates: hard z_n - mu |z_t|, soft z_n - sqrt(mu^2 |z_t|^2 + mu_t^2 z_m^2),
      // frictionless z. The bounded contacts' deficit must stay below y.w_ext.
      double deficit = 0;
      for (int i = 0; i < gd.size(); ++i) {
        const auto& c = ref.contacts[size_t(i)];
        const auto z = Model::wrench_transpose(c, y);
        if (c.max_normal_force < std::numeric_limits<double>::infinity()) {
          double phi = z(0);
          if constexpr (Model::dim > 1) {
            const Vector3<double> f = z.template head<3>();
            const double zn = f.dot(c.normal), zt = (f - zn * c.normal).norm();
            double q = c.friction * c.friction * zt * zt;
            if constexpr (Model::dim == 4) q += c.torsional_friction * c.torsional_friction * z(3) * z(3);
            phi = zn - std::sqrt(q);
          }
          deficit += c.max_normal_force * std::max(0.0, -phi);
          continue;
        }
        CHECK_MESSAGE(grip_test::dual_cone_violation<Model>(c, z) <= cert_tol + 1e-14, "instance ", index, " (",
                      ref.kind, ")");
      }
      CHECK_MESSAGE(deficit < yw, "instance ", index, " bounded deficit ", deficit, " y.w ", yw);
    };
    // float: a feasible instance that is infeasible to within the float certificate tolerance
    // (2e-3) may be called Infeasible; then its certificate must hold at that tolerance. Few may.
    if (ref.feasible && std::is_same<S, float>::value && sol.status == Status::Infeasible) {
      ++marginal;
      check_certificate();
      continue;
    }
    // float: on a bounded instance the method may stall short of its tolerance (a contact at its
    // bound has a cone multiplier z_0 -> 0 beside a bound multiplier t of order 10; z_0's direction
    // is recovered from the dual residual, whose rounding then exceeds z_0 itself; seen without
    // FMA's single rounding). Its forces are checked above (cones, bounds, finite); one may.
    if (ref.feasible && std::is_same<S, float>::value && sol.status == Status::IterationLimit &&
        ref.kind.rfind("bounded", 0) == 0) {
      ++stalled;
      continue;
    }
    if (ref.feasible) {
      CHECK_MESSAGE(sol.status == Status::Ok, "instance ", index, " (", ref.kind, ") model ", tag, " n ", g.size(),
                    " status ", std::string(to_string(sol.status)));
      // F2 recomputed in double from the definition.
      double f2 = 0;
      for (int i = 0; i < gd.size(); ++i) {
        const auto& c = ref.contacts[size_t(i)];
        f2 += 0.5 * c.weight * (xd.segment<Model::dim>(i * Model::dim) - Model::target(c)).squaredNorm();
      }
      // Our forces balance w' = w_ext - r, r = G x + w_ext their residual, not w_ext itself.
      // The optimal value v(w) is convex in the wrench with subgradient -lambda, so F2 may sit
      // below cvxopt's optimum by up to |lambda*| |r|, and above it by up to |lambda| |r| on top
      // of the solver's own accuracy: the condition of the grasp, through its multipliers,
      // sizes the tolerance (negligible in double; in float it reaches percents for grasps that
      // need forces of 1e4 N).
      REQUIRE(ref.has_lambda);
      const double shift = std::max(grip_test::dual_norm_l(ref.lambda, len),
                                    grip_test::dual_norm_l(sol.multipliers.template cast<double>(), len)) *
                           res;
      const double rel = std::max(std::abs(f2 - ref.objective) - shift, 0.0) / std::max(ref.objective, 1e-12);
      worst_obj = std::max(worst_obj, rel);
      // An answer of the interior-point method alone (not refined): to its tolerance, the gap
      // relative to F2 and the residual relative to the scale (solve_constrained.hpp).
      const double interior = static_cast<double>(ScalarTraits<S>::interior_tolerance);
      CHECK_MESSAGE(rel <= (sol.refined ? obj_tol : 2 * interior), "instance ", index, " objective ", f2, " vs cvxopt ",
                    ref.objective, " shift ", shift);
      // The equilibrium: 1e-10 (double) or 1e-4 (float) of the scale (|w_ext|_L + |x| + max s_i).
      double squeeze = 0;
      for (const auto& c : ref.contacts) squeeze = std::max(squeeze, c.squeeze);
      const double res_tol =
          (sol.refined ? (std::is_same<S, float>::value ? 1e-4 : 1e-10) : 2 * interior) * (force_scale_l + squeeze);
      worst_res = std::max(worst_res, res / force_scale_l);
      CHECK_MESSAGE(res <= res_tol, "instance ", index, " residual ", res, " tol ", res_tol);
      // The forces themselves against cvxopt's x*. F2 is strongly convex with modulus
      // w_min = min w_i, and at the optimum x_min grad F2 = G^T lambda - n with n in the normal
      // cone of the cones, so for any x in the cones F2(x) - F2_min >= lambda.r +
      // w_min/2 |x - x_min|^2: x lies within sqrt(2 (F2(x) - F2_min + |lambda*| |r|) / w_min)
      // of x_min, and F2_min >= F2(x*) - gap. cvxopt's x* lies within sqrt(2 gap / w_min) of it.
      // By the triangle inequality through x_min, with the round-off of the two F2 values
      // (64 eps of double, relative) and of S in forces of size force_scale:
      REQUIRE(ref.x.size() == static_cast<std::size_t>(g.unknowns()));
      double w_min = 1e300;
      for (const auto& c : ref.contacts) w_min = std::min(w_min, c.weight);
      const double f2_roundoff = 64 * std::numeric_limits<double>::epsilon() * (1 + ref.objective);
      const double x_tol =
          std::sqrt(2 *
                    (std::max(f2 - ref.objective + grip_test::dual_norm_l(ref.lambda, len) * res, 0.0) + ref.gap +
                     f2_roundoff) /
                    w_min) +
          std::sqrt(2 * (ref.gap + f2_roundoff) / w_min) + 1e3 * eps * force_scale;
      const Eigen::Map<const Eigen::VectorXd> x_ref(ref.x.data(), static_cast<Eigen::Index>(ref.x.size()));
      const double dx = (xd - x_ref).norm();
      worst_x = std::max(worst_x, dx);
      CHECK_MESSAGE(dx <= x_tol, "instance ", index, " |x - x*| ", dx, " bound ", x_tol);
      REQUIRE(ref.has_lambda);
      if (sol.status == Status::Ok && check_multipliers<Model>(ref, xd, sol.multipliers.template cast<double>(), dx,
                                                               eps, force_scale, sol.refined, worst_lambda))
        ++lambda_checked;
    } else {
      ++infeasible;
      CHECK_MESSAGE(sol.status == Status::Infeasible, "instance ", index, " (", ref.kind, ") model ", tag, " n ",
                    g.size(), " status ", std::string(to_string(sol.status)));
      // The forces come closest to equilibrium: they minimise P(x) = |r|_L^2/2 + delta F2(x) over
      // the cones (delta = least_residual_weight times the largest diagonal entry of G W^-1 G^T in
      // |.|_L's units). cvxopt's least-residual forces x_c lie in the cones, so P(x) <= P(x_c):
      // |r|^2 <= |r_c|^2 + 2 delta F2(x_c), plus the interior-point method's tolerance (1e-6 of
      // the scale in double, 1e-3 in float).
      REQUIRE(ref.least_residual >= 0.0);
      double delta = 0;
      for (int k = 0; k < 6; ++k) {
        double d = 0;
        for (const auto& c : ref.contacts)
          d += Model::wrench_transpose(c, Wrench<double>(Wrench<double>::Unit(k))).squaredNorm() / c.weight;
        delta = std::max(delta, k < 3 ? d : d / (len * len));  // in the norm's units
      }
      delta *= static_cast<double>(settings.least_residual_weight);
      const double slack = (std::is_same<S, float>::value ? 1e-3 : 1e-6) * force_scale_l;
      const double bound =
          std::sqrt(ref.least_residual * ref.least_residual + 2 * delta * ref.least_residual_f2) + slack;
      worst_least = std::max(worst_least, (res - ref.least_residual) / force_scale_l);
      CHECK_MESSAGE(res <= bound, "instance ", index, " (", ref.kind, ") least residual ", res, " vs cvxopt ",
                    ref.least_residual, " bound ", bound);
      // And no lower than cvxopt's minimum (two formulations agreed on it to 1e-7).
      CHECK_MESSAGE(res >= ref.least_residual - 1e-6 * (1 + ref.least_residual), "instance ", index, " residual ", res,
                    " below cvxopt's least residual ", ref.least_residual);
      if (sol.status == Status::Infeasible) check_certificate();
    }
  }
  CHECK(count > 0);
  CHECK(marginal <= 2);
  CHECK(stalled <= 1);
  // The multipliers were compared somewhere (unique ones are common for every model).
  CHECK(lambda_checked > 0);
  CHECK(bounded_contacts > 0);  // the bounded instances were read and checked
  std::printf(
      "[constrained reference %c %s] %d instances (%d infeasible): worst objective rel %.2e, residual %.2e, "
      "cone %.2e, |x - x*| %.2e, |lambda - lambda*| %.2e (%d unique), least residual excess %.2e, "
      "iterations %d\n",
      tag, std::is_same<S, float>::value ? "float" : "double", count, infeasible, worst_obj, worst_res, worst_cone,
      worst_x, worst_lambda, lambda_checked, worst_least, worst_iter);
}

}  // namespace

TEST_CASE("the cvxopt reference file is read whole") {
  // Every instance of every model read, as the file's header counts them: a misread tag or a
  // truncated file fails; every feasible instance carries x* and lambda*, every infeasible
  // one its least residual.
  grip_test::ReferenceCounts counts;
  const auto data = grip_test::load_constrained_reference(&counts);
  int instances[3] = {0, 0, 0}, infeasible[3] = {0, 0, 0}, bounded = 0;
  for (const auto& ref : data) {
    const int slot = grip_test::ReferenceCounts::slot(ref.model);
    ++instances[slot];
    bounded += ref.kind.rfind("bounded", 0) == 0 ? 1 : 0;
    infeasible[slot] += ref.feasible ? 0 : 1;
    CHECK(static_cast<int>(ref.contacts.size()) == ref.n);
    CHECK((ref.feasible ? ref.has_lambda && !ref.x.empty() : ref.least_residual >= 0.0));
  }
  for (int k = 0; k < 3; ++k) {
    CHECK(instances[k] == counts.instances[k]);
    CHECK(infeasible[k] == counts.infeasible[k]);
  }
  CHECK(bounded >= 40);  // the bounded instances: inactive, active and too low
}

TEST_CASE_TEMPLATE("solve_constrained agrees with cvxopt on every reference instance", S, double, float) {
  const auto data = grip_test::load_constrained_reference();
  check_against_reference<HardFinger, S>(data, 'H');
  check_against_reference<SoftFinger, S>(data, 'S');
  check_against_reference<FrictionlessPoint, S>(data, 'F');
}
