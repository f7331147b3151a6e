// The interior-point method's answer on the boundary of the feasible set
// (include/grip/solve/detail/interior_point.hpp): a load that the grasp resists only with forces
// on the boundary of its cones, to within rounding, ends Ok with balanced forces and multipliers
// in range, within the bound on iterations.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/grip.hpp>

#include "solve/constrained_support.hpp"
#include "support/equilibrium_norm.hpp"

using namespace grip;

namespace {

struct RecordedContact {
  double position[3], normal[3], friction, squeeze, weight, max_normal_force;
};

// A frame of examples/06_haptic_loop's session (the cylinder resting on the table, five
// fingertips on its top, four of them on a line): a vertical load with a moment of about
// 1e-17 N m (rounding) about that line, which the grasp resists only with forces on the boundary
// of its cones, or not at all. Recorded from the pipeline (hexadecimal, exact).
const RecordedContact recorded[5] = {
    {{-0x1.d879adp-31, 0x1.46dc5d6388659p-6, 0x1.1eb851eb851e9p-5},
     {0x1.a5da5a93b215cp-26, -0x0p+0, -0x1.ffffffffffffep-1},
     0x1.999999999999ap-1,
     0x1.7bdc3867511bbp+1,
     0x1.590da04391f24p-2,
     0x1.8p+3},
    {{-0x1.769p-40, 0x0p+0, 0x1.1eb851eb851edp-5},
     {0x1.4e6eb8679889cp-35, -0x0p+0, -0x1p+0},
     0x1.999999999999ap-1,
     0x1.a031d76611a56p+1,
     0x1.3aedf5d40531bp-2,
     0x1.8p+3},
    {{-0x1.232f7b4p-29, -0x1.374bc6a7ef9dcp-6, 0x1.1eb851eb851e3p-5},
     {0x1.03fcadf46add5p-24, -0x0p+0, -0x1.ffffffffffffp-1},
     0x1.999999999999ap-1,
     0x1.22acf7f604245p+1,
     0x1.c2ebfd127be2fp-2,
     0x1.8p+3},
    {{-0x1.3ec33fd9687cp-8, -0x1.374bc6a7ef9dcp-5, 0x1.1bf01780642f1p-5},
     {0x1.1c9c0b4b41dbap-3, -0x0p+0, -0x1.fb0829f78e53fp-1},
     0x1.999999999999ap-1,
     0x1.2df17753db952p+0,
     0x1.b218481f255ebp-1,
     0x1.8p+3},
    {{0x1.8c82p-37, -0x1.374bc6a7ef9dcp-5, 0x1.1eb851eb851edp-5},
     {-0x1.62065eeaf0cfdp-32, -0x0p+0, -0x1p+0},
     0x1.999999999999ap-1,
     0x1.0453cb0ed94a4p-3,
     0x1p+1,
     0x1.8p+3},
};

}  // namespace

TEST_CASE_TEMPLATE("solve_constrained: a load on the boundary of the feasible set ends Ok, or Infeasible", S, double,
                   float) {
  Grasp<Dynamic, HardFinger, S, 19> g;
  for (const RecordedContact& r : recorded) {
    Contact<S> c;
    c.position = Vector3<double>(r.position[0], r.position[1], r.position[2]).cast<S>();
    c.normal = Vector3<double>(r.normal[0], r.normal[1], r.normal[2]).cast<S>();
    c.friction = S(r.friction);
    c.squeeze = S(r.squeeze);
    c.weight = S(r.weight);
    c.max_normal_force = S(r.max_normal_force);
    REQUIRE(g.add(c) == Status::Ok);
  }
  // The recorded moment, none, and the recorded moment of the other sign.
  for (const double moment : {-0x1.43d95c030558dp-56, 0.0, 0x1.43d95c030558dp-56}) {
    CAPTURE(moment);
    Wrench<double> wd;
    wd << 0, 0, 0x1.5ff2ca4419e6p-3, 0, moment, 0;
    const Wrench<S> w = wd.cast<S>();
    const ConstrainedSettings<S> st;
    const auto sol = solve_constrained(g, w, st);
    CHECK(sol.iterations < st.max_iterations);
    CHECK(detail::all_in_range(sol.multipliers));
    if (sol.status == Status::Infeasible) {  // float: the rounding may decide either way
      CHECK(std::is_same<S, float>::value);
      continue;
    }
    REQUIRE(sol.status == Status::Ok);
    // Balanced to the interior-point method's tolerance, in the cones, in double.
    const double len = grip_test::grasp_lever_length(g);
    Wrench<double> res = wd;
    double xs = 0, smax = 0;
    for (int i = 0; i < g.size(); ++i) {
      const Contact<double> c = grip_test::cast_contact<double>(g.contact(i));
      const Vector3<double> xi = sol.forces.template segment<3>(3 * i).template cast<double>();
      res += HardFinger::wrench(c, xi);
      xs += xi.squaredNorm();
      smax = std::max(smax, c.squeeze);
      CHECK(grip_test::cone_violation<HardFinger>(c, xi) <= 1e-6 * wd.norm());
    }
    const double loose = double(ScalarTraits<S>::interior_tolerance);
    CHECK(grip_test::norm_l(res, len) <= 4 * loose * (grip_test::norm_l(wd, len) + std::sqrt(xs) + smax));
  }
}
