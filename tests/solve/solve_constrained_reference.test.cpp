// solve_constrained against an independent conic solver (cvxopt, data made by
// make_constrained_reference.py): the objective at every instance, equilibrium and cone
// feasibility of our forces checked from the definitions, and the infeasibility certificates.
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

using namespace grip;

namespace {

template <class Model, class S>
void check_against_reference(const std::vector<grip_test::ConstrainedReference>& data, char tag,
                             const grip_test::ReferenceCounts& counts) {
  using GraspT = Grasp<Dynamic, Model, S, 20>;
  const double obj_tol = std::is_same<S, float>::value ? 1e-3 : 1e-7;
  const ConstrainedSettings<S> settings;
  int count = 0, infeasible = 0, worst_iter = 0;
  double worst_obj = 0, worst_res = 0, worst_cone = 0, worst_x = 0;
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
    // Whatever the status, the forces are finite and inside the cones (up to round-off).
    double force_scale = ref.w_ext.norm();
    for (int i = 0; i < g.size(); ++i) force_scale += sol.forces.template segment<Model::dim>(i * Model::dim).template cast<double>().norm();
    const double cone_tol = (std::is_same<S, float>::value ? 1e-5 : 1e-10) * (1.0 + force_scale);
    for (int i = 0; i < g.size(); ++i) {
      const double v = grip_test::cone_violation<Model>(ref.contacts[size_t(i)],
                                                        sol.forces.template segment<Model::dim>(i * Model::dim));
      worst_cone = std::max(worst_cone, v / (1.0 + force_scale));
      CHECK(v <= cone_tol);
    }
    // Equilibrium in double from the double inputs.
    Eigen::Matrix<double, Eigen::Dynamic, 1> xd = sol.forces.template cast<double>();
    Grasp<Dynamic, Model, double, 20> gd;
    for (const auto& c : ref.contacts) (void)gd.add(c);
    const double res = (gd.wrench(xd) + ref.w_ext).norm();
    if (ref.feasible) {
      CHECK_MESSAGE(sol.status == Status::Ok, "instance ", index, " model ", tag, " n ", g.size(), " status ", std::string(to_string(sol.status)));
      // F2 recomputed in double from the definition.
      double f2 = 0;
      for (int i = 0; i < gd.size(); ++i) {
        const auto& c = ref.contacts[size_t(i)];
        f2 += 0.5 * c.weight * (xd.segment<Model::dim>(i * Model::dim) - Model::target(c)).squaredNorm();
      }
      const double rel = std::abs(f2 - ref.objective) / std::max(ref.objective, 1e-12);
      worst_obj = std::max(worst_obj, rel);
      CHECK_MESSAGE(rel <= obj_tol, "objective ", f2, " vs cvxopt ", ref.objective);
      const double res_tol = (std::is_same<S, float>::value ? 1e-4 : 1e-10) * force_scale;
      worst_res = std::max(worst_res, res / force_scale);
      CHECK(res <= res_tol);
      // The forces themselves against cvxopt's x*. F2 is strongly convex with modulus
      // w_min = min w_i, so F2(x) - F2_min <= delta puts x within sqrt(2 delta / w_min) of the
      // optimum x_min. cvxopt's x* has delta <= gap; ours has delta <= (F2(x) - F2(x*)) + gap.
      // By the triangle inequality through x_min, with the round-off of the two F2 values
      // (64 eps of double, relative) and of S in forces of size force_scale:
      REQUIRE(ref.x.size() == static_cast<std::size_t>(g.unknowns()));
      double w_min = 1e300;
      for (const auto& c : ref.contacts) w_min = std::min(w_min, c.weight);
      const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
      const double f2_roundoff = 64 * std::numeric_limits<double>::epsilon() * (1 + ref.objective);
      const double x_tol = std::sqrt(2 * (std::max(f2 - ref.objective, 0.0) + ref.gap + f2_roundoff) / w_min) +
                           std::sqrt(2 * (ref.gap + f2_roundoff) / w_min) + 1e3 * eps * force_scale;
      const Eigen::Map<const Eigen::VectorXd> x_ref(ref.x.data(), static_cast<Eigen::Index>(ref.x.size()));
      const double dx = (xd - x_ref).norm();
      worst_x = std::max(worst_x, dx);
      CHECK_MESSAGE(dx <= x_tol, "instance ", index, " |x - x*| ", dx, " bound ", x_tol);
    } else {
      ++infeasible;
      CHECK_MESSAGE(sol.status == Status::Infeasible, "instance ", index, " model ", tag, " n ", g.size(), " status ", std::string(to_string(sol.status)));
      if (sol.status == Status::Infeasible) {
        // Farkas: y.w_ext > 0 and G_i^T y in K_i^* for every contact (checked from the definitions).
        const Wrench<double> y = sol.certificate.template cast<double>();
        CHECK(y.norm() == doctest::Approx(1.0).epsilon(1e-5));
        CHECK(y.dot(ref.w_ext) > 0.0);
        for (int i = 0; i < gd.size(); ++i) {
          const auto& c = ref.contacts[size_t(i)];
          const auto z = Model::wrench_transpose(c, y);
          // ConstrainedSettings::certificate_tolerance: 1e-5 (double), 2e-3 (float), times 1 + |r_i|.
          CHECK(grip_test::dual_cone_violation<Model>(c, z) <= (std::is_same<S, float>::value ? 3e-3 : 2e-5));
        }
      }
    }
  }
  // Every instance of the model was read and run: a misread tag or a truncated file fails.
  const int slot = grip_test::ReferenceCounts::slot(tag);
  CHECK(count == counts.instances[slot]);
  CHECK(infeasible == counts.infeasible[slot]);
  CHECK(count > 0);
  std::printf("[constrained reference %c %s] %d instances (%d infeasible): worst objective rel %.2e, residual %.2e, "
              "cone %.2e, |x - x*| %.2e, iterations %d\n",
              tag, std::is_same<S, float>::value ? "float" : "double", count, infeasible, worst_obj, worst_res,
              worst_cone, worst_x, worst_iter);
}

}  // namespace

TEST_CASE_TEMPLATE("solve_constrained agrees with cvxopt on every reference instance", S, double, float) {
  grip_test::ReferenceCounts counts;
  const auto data = grip_test::load_constrained_reference(&counts);
  REQUIRE(data.size() == static_cast<std::size_t>(counts.instances[0] + counts.instances[1] + counts.instances[2]));
  check_against_reference<HardFinger, S>(data, 'H', counts);
  check_against_reference<SoftFinger, S>(data, 'S', counts);
  check_against_reference<FrictionlessPoint, S>(data, 'F', counts);
}
