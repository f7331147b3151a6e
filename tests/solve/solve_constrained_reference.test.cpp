// solve_constrained against an independent conic solver (cvxopt, data made by
// make_constrained_reference.py): the objective at every instance, equilibrium and cone
// feasibility of our forces checked from the definitions, and the infeasibility certificates.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>
#include <type_traits>
#include <vector>
#include <string>

#include <grip/solve/solve_constrained.hpp>

#include "solve/constrained_support.hpp"

using namespace grip;

namespace {

template <class Model, class S>
void check_against_reference(const std::vector<grip_test::ConstrainedReference>& data, char tag) {
  using GraspT = Grasp<Dynamic, Model, S, 20>;
  const double obj_tol = std::is_same<S, float>::value ? 1e-3 : 1e-7;
  const ConstrainedSettings<S> settings;
  int count = 0, infeasible = 0, worst_iter = 0;
  double worst_obj = 0, worst_res = 0, worst_cone = 0;
  int index = -1;
  for (const auto& ref : data) {
    ++index;
    if (ref.model != tag) continue;
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
  std::printf("[constrained reference %c %s] %d instances (%d infeasible): worst objective rel %.2e, residual %.2e, "
              "cone %.2e, iterations %d\n",
              tag, std::is_same<S, float>::value ? "float" : "double", count, infeasible, worst_obj, worst_res,
              worst_cone, worst_iter);
}

}  // namespace

TEST_CASE_TEMPLATE("solve_constrained agrees with cvxopt on every reference instance", S, double, float) {
  const auto data = grip_test::load_constrained_reference();
  REQUIRE(data.size() >= 250);
  check_against_reference<HardFinger, S>(data, 'H');
  check_against_reference<SoftFinger, S>(data, 'S');
  check_against_reference<FrictionlessPoint, S>(data, 'F');
}
