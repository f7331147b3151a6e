// The interior-point method's answer on the boundary of the feasible set
// (include/grip/solve/detail/interior_point.hpp): a load that the grasp resists only with forces
// on the boundary of its cones, to within rounding, ends Ok with balanced forces and multipliers
// in range, within the bound on iterations; a run resumed after Newton's refinement failed
// stops where an uninterrupted run does; and a bound far above every force costs no iterations.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

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

namespace {

struct LightContact {
  double position[3], normal[3], friction;
};

// Light loads (15 uN to 8 mN against squeezing forces of 0.3 N) on grasps of bench_constrained's
// make_hard_instance<N>(rng, true) (std::mt19937 rng(5000 + N); draws 10815, 24639 and 30787 at
// n = 3, 5576 at n = 5, and 32541 at n = 3), hexadecimal, exact. The first four hold with forces
// near the squeezing forces; without the wide neighbourhood, one pair's complementarity fell to
// the cone's boundary ahead of the rest and every later step shrank to a sliver: 40 iterations and
// IterationLimit. The fifth lies on the boundary of the feasible set (see the test).
const LightContact light3[4][3] = {
    {{{-0x1.402935b3b0a7ep-7, -0x1.2bcc81739d404p-8, 0x1.3b8961d530fc9p-5},
      {0x1.f44063e8c4065p-3, 0x1.d46f8a44a5b46p-4, -0x1.ed06a8dd1c8aap-1},
      0x1.cb06bffad3573p-1},
     {{-0x1.646ae32dc58c7p-8, 0x1.05127aed7af5fp-7, 0x1.3e0228ffbe425p-5},
      {0x1.1673817bc255bp-3, -0x1.97ece01310205p-3, -0x1.f0e3600f9947ap-1},
      0x1.f0ee8891e9ac7p-1},
     {{0x1.8bc0b4817853ep-6, -0x1.9c3fd01db3e8ap-6, -0x1.40d28a4d5a311p-6},
      {-0x1.352e8d0526018p-1, 0x1.4211da97348dcp-1, 0x1.f548f818dcecap-2},
      0x1.c9415515f1a04p-2}},
    {{{-0x1.e92bea6e2cbb1p-7, 0x1.ca114a317e24ap-10, 0x1.2faac8dbefc54p-5},
      {0x1.7e2a4f2612f22p-2, -0x1.65dd81f6aa8cap-5, -0x1.da7ad9d7a6a43p-1},
      0x1.eb96077ff132cp-2},
     {{-0x1.548a78a27346ap-7, 0x1.6258b95f92d41p-7, 0x1.2fc61e49d48cep-5},
      {0x1.0a0c2e3eea0f3p-2, -0x1.14d550d2aab5bp-2, -0x1.daa58f535c1c1p-1},
      0x1.1ad504dab194dp-1},
     {{-0x1.8b3d6f2c06abep-7, -0x1.04c787c2cac59p-7, -0x1.318ca177b73dfp-5},
      {0x1.34c7feda65364p-2, 0x1.9777c4205cd4bp-3, 0x1.dd6bbc4b0e50cp-1},
      0x1.38f580c92f51dp-2}},
    {{{0x1.a3bc80502f083p-8, -0x1.6e57162a3eb3ap-7, 0x1.3637220619c78p-5},
      {-0x1.47eb443ea4be6p-3, 0x1.1e34095100fc5p-2, -0x1.e4b625298847cp-1},
      0x1.13c04c7141068p-1},
     {{0x1.3168a066d8f91p-5, 0x1.22986501e368cp-7, -0x1.77b2f150d7ff5p-7},
      {-0x1.dd337aa0b3053p-1, -0x1.c60e1dd2f353ap-3, 0x1.2583cc8728bf7p-2},
      0x1.cca8113a428a4p-1},
     {{0x1.b679a1e4ab3e8p-6, -0x1.a50cef6b63981p-11, -0x1.e6e42e058f65ep-6},
      {-0x1.568f067aa5c8dp-1, 0x1.48f21b0be5cedp-6, 0x1.7c6243f458079p-1},
      0x1.a785c66f930c4p-1}},
    {{{0x1.3c7ed670a6434p-6, -0x1.af9799ef77767p-11, 0x1.1edb227dd20cdp-5},
      {-0x1.ee862f1003c91p-2, 0x1.512e704315548p-6, -0x1.c03665e49834p-1},
      0x1.a21df714a43fcp-1},
     {{0x1.7904001256e11p-6, 0x1.784d008772eap-8, -0x1.07de455b0799cp-5},
      {-0x1.268b200e53dfdp-1, -0x1.25fc2869d1c6dp-3, 0x1.9c4b4c5e3be03p-1},
      0x1.14281e1e72fcfp-1},
     {{0x1.e82b5715bbf7p-9, -0x1.5c49a995ca881p-6, 0x1.13e4b97d45bc9p-5},
      {-0x1.7d61dc08fad8fp-4, 0x1.10198c7d063a5p-1, -0x1.af1561d3bcf6ap-1},
      0x1.a8a054add0bf2p-2}},
};
const double light3_load[4][6] = {
    {0x1.db22bd2f07668p-17, 0x1.308e61010a6d4p-16, 0x1.c80935ab76d94p-15, 0x1.2e56f7f593c31p-23, -0x1.c3a39c8888e77p-20,
     0x1.8faa768e7e011p-20},
    {-0x1.53bbb6e2d08f2p-15, 0x1.2230602a5f8b8p-14, -0x1.496e863a9a2cep-19, -0x1.21507f6c81058p-21,
     -0x1.58f81c8dce1cap-26, -0x1.4b5f647ed141bp-23},
    {-0x1.9a9c59e746a08p-17, -0x1.0a4aaf52d1349p-10, -0x1.a168190838d41p-9, -0x1.8b69d720ef9a4p-15,
     0x1.0a461bff32d1ep-15, -0x1.ab2be6dc7114fp-14},
    {-0x1.fddefe07759f5p-8, 0x1.19bb9576b372bp-10, 0x1.b5a4e1a4d2cf8p-7, 0x1.db592c81e1579p-15, 0x1.c02292ee3501p-12,
     0x1.ec64973999bf4p-15},
};
const LightContact light5[5] = {
    {{0x1.5e495b921098ep-9, 0x1.4f430130b88e7p-7, 0x1.3c059cc0fa3c8p-5},
     {-0x1.11a94f8a1cf77p-4, -0x1.05ec58ee102f4p-2, -0x1.edc8c4ed86fe9p-1},
     0x1.d7fdb3832e62cp-1},
    {{0x1.1aac7f9f585a2p-5, -0x1.2282aa0eb0f97p-6, -0x1.3f43bdbb54981p-7},
     {-0x1.b9ad8768fa0cdp-1, 0x1.c5ec29b6f485cp-2, 0x1.f2d9d874b42d9p-3},
     0x1.a6adab7a0754cp-2},
    {{0x1.1b34d95715e3cp-6, -0x1.fcc51004735ap-7, 0x1.0abad4f24e18p-5},
     {-0x1.ba8293981233dp-2, 0x1.8d79f4837a1e5p-2, -0x1.a0c3ecba9a058p-1},
     0x1.35e7480d4acc7p-1},
    {{0x1.3e17eca3e1aafp-7, -0x1.06c5febc45ea3p-5, -0x1.65c5d78b805ccp-6},
     {-0x1.f10561c0109b2p-3, 0x1.9a955e062d3dep-1, 0x1.17829064fc487p-1},
     0x1.589341a169e68p-2},
    {{0x1.b49abf64563e7p-6, 0x1.6878e4bb5ebb6p-7, -0x1.c64cb79a54198p-6},
     {-0x1.5518e5866360cp-1, -0x1.199e72b262026p-2, 0x1.62ebef7091b3fp-1},
     0x1.3f47cb4b7a4f9p-2},
};
const double light5_load[6] = {-0x1.1af719cca8b59p-13, 0x1.0ffca2ac836cp-11,  0x1.48821618c07bbp-12,
                               0x1.ce0aa87e2e8a6p-15,  0x1.056dbe4f273c6p-17, 0x1.b6b5f300ff555p-17};

template <int N>
Grasp<N, HardFinger, double> light_grasp(const LightContact (&cs)[N]) {
  Grasp<N, HardFinger, double> g;
  for (int i = 0; i < N; ++i) {
    Contact<double> c;
    c.position = Vector3<double>(cs[i].position[0], cs[i].position[1], cs[i].position[2]);
    c.normal = Vector3<double>(cs[i].normal[0], cs[i].normal[1], cs[i].normal[2]);
    c.friction = cs[i].friction;
    c.torsional_friction = 0.005;
    c.squeeze = 0.3;
    (void)g.set(i, c);
  }
  return g;
}

// The forces of an Ok answer lie in the cones and balance w to the interior-point method's
// tolerance (docs/solve.md, the statuses: relative to the load, the forces and the squeezing
// forces), checked in double from their definition.
template <int N>
void check_balanced(const Grasp<N, HardFinger, double>& g, const Wrench<double>& w,
                    const typename Grasp<N, HardFinger, double>::ForceVector& forces) {
  const double len = grip_test::grasp_lever_length(g);
  Wrench<double> res = w;
  for (int i = 0; i < N; ++i) {
    const Vector3<double> xi = forces.template segment<3>(3 * i);
    res += HardFinger::wrench(g.contact(i), xi);
    CHECK(grip_test::cone_violation<HardFinger>(g.contact(i), xi) <= 1e-9 * (w.norm() + xi.norm()));
  }
  const double scale = grip_test::norm_l(w, len) + forces.norm() + 0.3;
  CHECK(grip_test::norm_l(res, len) <= 2 * ScalarTraits<double>::interior_tolerance * scale);
}

// A hold that the interior-point method alone (newton_passes = 0) decides within 20 iterations,
// at the optimum that Newton's method alone finds (the defaults decide these four in Newton's
// passes, without an interior-point iteration): a second method's objective.
template <int N>
void check_hold(const Grasp<N, HardFinger, double>& g, const Wrench<double>& w) {
  ConstrainedSettings<double> ip_only;
  ip_only.newton_passes = 0;
  const auto a = solve_constrained(g, w, ip_only);
  const auto b = solve_constrained(g, w);
  REQUIRE(a.status == Status::Ok);
  REQUIRE(b.status == Status::Ok);
  CHECK(a.iterations <= 20);
  CHECK(b.iterations == 0);
  CHECK(a.objective == doctest::Approx(b.objective).epsilon(1e-6));
  check_balanced(g, w, a.forces);
}

}  // namespace

TEST_CASE("solve_constrained: light-load holds that cycled at a cone's boundary converge in the wide neighbourhood") {
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    check_hold(light_grasp(light3[k]), Wrench<double>(light3_load[k]));
  }
  check_hold(light_grasp(light5), Wrench<double>(light5_load));
  // The boundary hold: balanced only by forces of about 2 kN against a load of 0.016 N. A
  // certificate to the tolerance t rules out balancing forces below about |w|_L / t (docs/solve.md),
  // 1.6 kN at the default t = 1e-5: both answers are right to their tolerances. With the defaults
  // the interior-point method finds the certificate; with t = 1e-7 (no forces below 160 kN) it
  // stops on the boundary, Ok.
  const auto g = light_grasp(light3[3]);
  const Wrench<double> w(light3_load[3]);
  const double len = grip_test::grasp_lever_length(g), load = grip_test::norm_l(w, len);
  const ConstrainedSettings<double> st;
  const auto slip = solve_constrained(g, w, st);
  REQUIRE(slip.status == Status::Infeasible);
  CHECK(slip.iterations < st.max_iterations);
  // The certificate from its definition (y.w > 0, every G_i^T y within t (y.w) / |w|_L of K_i^*,
  // y of dual norm 1), as solve_constrained.test.cpp checks it.
  const Wrench<double> y = slip.certificate;
  CHECK(std::abs(grip_test::dual_norm_l(y, len) - 1.0) <= 1e-12);
  CHECK(y.dot(w) > 0.0);
  for (int i = 0; i < 3; ++i) {
    const Contact<double>& c = g.contact(i);
    const double reach = 1 + c.position.norm() / len, mu = c.friction;
    CHECK(grip_test::dual_cone_violation<HardFinger>(c, HardFinger::wrench_transpose(c, y)) <=
          std::sqrt(1 + mu * mu) * st.certificate_tolerance * y.dot(w) / load * reach + 1e-14);
  }
  ConstrainedSettings<double> strict;
  strict.certificate_tolerance = 1e-7;
  const auto hold = solve_constrained(g, w, strict);
  REQUIRE(hold.status == Status::Ok);
  CHECK(hold.iterations < st.max_iterations);
  check_balanced(g, w, hold.forces);
  // The two answers agree: the balancing forces lie beyond what the default certificate rules out.
  CHECK(hold.forces.norm() * st.certificate_tolerance > load);
}

namespace {

// Light loads on grasps of make_hard_instance<N>(rng, true) (std::mt19937 rng(5000 + N); draws
// 847 and 23474 at n = 3, 46242 at n = 5), hexadecimal, exact: holds on the boundary of the
// feasible set (1e-6 N against squeezing forces of 0.3 N), where the interior-point method's tau
// collapses and Newton's refinement from its multipliers cannot converge.
const LightContact resumed3[2][3] = {
    {{{0x1.49ace346d387ap-10, 0x1.557b92d066da3p-7, -0x1.3c322b14ca601p-5},
      {-0x1.018f118f5541fp-5, -0x1.0ac88ab2d05a7p-2, 0x1.ee0e63507c362p-1},
      0x1.0e8f256e8c59fp-1},
     {{-0x1.4086b895ccb5ap-5, 0x1.d53492d8039c7p-8, -0x1.14ce08adff9ffp-8},
      {0x1.f4d2806a0fdbcp-1, -0x1.6e9112b8c2d23p-3, 0x1.b081ed8fdf69fp-4},
      0x1.c0b6826ae9a62p-1},
     {{0x1.a097838c1fa9p-7, 0x1.312c0c2f48f73p-5, -0x1.d24c2ea011f3p-8},
      {-0x1.45765ec578bcp-2, -0x1.dcd4d309e2024p-1, 0x1.6c4b846d0e05dp-3},
      0x1.dca378944596ap-1}},
    {{{-0x1.03484eae0ec9ap-5, 0x1.50c47d39ec36cp-6, 0x1.b2652c8640152p-7},
      {0x1.9520faeff71bp-1, -0x1.071981d5408acp-1, -0x1.535f0ac8e2108p-2},
      0x1.7e60a77ae9c3ep-2},
     {{0x1.16f4f5fe9ae6ep-9, 0x1.16dda562b4381p-5, 0x1.565e5fbfd85dbp-6},
      {-0x1.b3dec05dd208bp-5, -0x1.b3ba526a3997ap-1, -0x1.0b79bacde1093p-1},
      0x1.d2c5daf75154p-1},
     {{-0x1.9437b73cfd8b2p-6, 0x1.730e73f46ed3fp-6, -0x1.665c2d205aa21p-6},
      {0x1.3bcb8727a614bp-1, -0x1.21e34a96f6959p-1, 0x1.17f8034146ceap-1},
      0x1.a87f7028014aep-1}},
};
const double resumed3_loads[2][6] = {{0x1.6919aaef0bfc9p-23, 0x1.1b084181709cdp-20, -0x1.235336124cf74p-20,
                                      -0x1.37c81bc81bc6dp-26, 0x1.6d89f14164e7bp-24, -0x1.1326f6cc4692fp-25},
                                     {0x1.7dcabf7a3e0dep-20, 0x1.0ce2edd21830cp-18, 0x1.6727842183e5cp-23,
                                      0x1.e9c319034d6p-25, -0x1.40e0a65d8ca71p-26, -0x1.df7d95381ff48p-24}};
const LightContact resumed5[5] = {
    {{0x1.07e3036f6c0d5p-5, -0x1.6a3679bfe7a3bp-8, -0x1.79d344fe78845p-6},
     {-0x1.9c52b55e18d4dp-1, 0x1.1afa8f1decf7ep-3, 0x1.272d0de6ce276p-1},
     0x1.b037e56915818p-2},
    {{0x1.b21efe717d684p-8, 0x1.1b6ac6979e2aap-6, -0x1.226d7456bdc3dp-5},
     {-0x1.532836c8a9f97p-3, -0x1.bad6d64ce722ap-2, 0x1.c5cb05c78881fp-1},
     0x1.d9f0a6ba431fep-1},
    {{-0x1.a570b294e0081p-10, -0x1.3ee0a909024d5p-5, 0x1.2920d15cc6edcp-7},
     {0x1.49400b844f065p-5, 0x1.f23f081e1398dp-1, -0x1.d0434720f6d37p-3},
     0x1.d623ec714501p-2},
    {{0x1.8439964e98a85p-6, -0x1.ddf42acc4d875p-6, -0x1.c0b9572fc5d24p-7},
     {-0x1.2f4cfd6d67438p-1, 0x1.7566c16f9c91bp-1, 0x1.5e90cc1d528c4p-2},
     0x1.5235a1e08bbdap-1},
    {{-0x1.b55928f6e4aadp-6, -0x1.c36edbf29586cp-9, -0x1.e4cee45cac309p-6},
     {0x1.55ada800e2a57p-1, 0x1.60ae9bd584d14p-4, 0x1.7ac1a2686685fp-1},
     0x1.e8d538d5271cp-2},
};
const double resumed5_load[6] = {0x1.c03bccc4a5bbap-24, 0x1.fbee867b24c2ap-21,  -0x1.010278b2b8659p-21,
                                 0x1.a58eee48ec5f3p-25, -0x1.d4fd4a9fc1b44p-28, 0x1.82d8847788492p-25};

// With the defaults the interior-point method hands over to Newton at interior_handover, Newton's
// refinement fails, and the method resumes to its own tolerance; with newton_passes = 0 it runs
// through. The resumed run goes on from the same iterate with the same history (tau's largest
// value, for the boundary test), so both stop at the same iteration with the same verdict.
// Returns whether the instance took that path (on the boundary, rounding decides: another
// instruction set may end it refined or Infeasible).
template <int N>
bool check_resumed(const Grasp<N, HardFinger, double>& g, const Wrench<double>& w) {
  ConstrainedSettings<double> through;
  through.newton_passes = 0;
  const auto a = solve_constrained(g, w);
  const auto b = solve_constrained(g, w, through);
  if (a.refined || b.status != Status::Ok) return false;
  CHECK(a.status == Status::Ok);
  CHECK(a.iterations == b.iterations);
  check_balanced(g, w, a.forces);
  return true;
}

}  // namespace

TEST_CASE("solve_constrained: a run resumed after Newton's refinement stops where an uninterrupted one does") {
  int resumed = 0;
  for (int k = 0; k < 2; ++k) {
    CAPTURE(k);
    resumed += check_resumed(light_grasp(resumed3[k]), Wrench<double>(resumed3_loads[k])) ? 1 : 0;
  }
  resumed += check_resumed(light_grasp(resumed5), Wrench<double>(resumed5_load)) ? 1 : 0;
  MESSAGE(resumed, " of 3 instances resumed after a failed refinement");
  CHECK(resumed >= 1);
}

TEST_CASE_TEMPLATE("solve_constrained: a bound far above every force costs the interior-point method no iterations", S,
                   double, float) {
  // Five hard fingers on a 4 cm sphere, loads of 0.5 to 200 N (many slip), decided by the
  // interior-point method alone (newton_passes = 0), without bounds and with 1 MN on every
  // finger: no force comes near the bound, so both problems have the same answer. The bound's
  // pair adds one to the centring's degree, so the iterates differ a little (in float, at
  // -march=x86-64, one grasp by five iterations); a bound's slack started away from its row
  // (u_0 + s = c tau at the start) would first shrink tau toward 1 / c and cost the run many
  // iterations (up to 18 more here, 15 % more in total in double, 50 % in float).
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> n01(0, 1);
  ConstrainedSettings<S> st;
  st.newton_passes = 0;
  int solves = 0, free_total = 0, bounded_total = 0;
  for (int k = 0; k < 300; ++k) {
    Grasp<5, HardFinger, S> g;
    for (int i = 0; i < 5; ++i) {
      const double th = std::acos(1 - 2 * u01(rng)), ph = 6.283185307179586 * u01(rng);
      const Vector3<double> n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      Contact<S> c;
      c.position = (0.04 * n).cast<S>();
      c.normal = (-n).cast<S>();
      c.friction = S(0.3 + 0.7 * u01(rng));
      c.squeeze = S(0.3);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    Wrench<double> wd;
    for (int j = 0; j < 6; ++j) wd(j) = (j < 3 ? 1.0 : 0.03) * n01(rng);
    const double size = 0.5 * std::pow(400.0, u01(rng));
    wd.head<3>() *= size / wd.head<3>().norm();
    wd.tail<3>() *= size;
    const Wrench<S> w = wd.cast<S>();
    const auto a = solve_constrained(g, w, st);
    if (a.fast_path) continue;
    CAPTURE(k);
    Grasp<5, HardFinger, S> h = g;
    for (int i = 0; i < 5; ++i) {
      Contact<S> c = h.contact(i);
      c.max_normal_force = S(1e6);
      REQUIRE(h.set(i, c) == Status::Ok);
    }
    const auto b = solve_constrained(h, w, st);
    CHECK(b.status == a.status);
    CHECK(b.iterations <= a.iterations + 8);
    ++solves;
    free_total += a.iterations;
    bounded_total += b.iterations;
  }
  MESSAGE(solves, " solves: ", free_total, " iterations without bounds, ", bounded_total, " with");
  CHECK(solves >= 250);
  CHECK(bounded_total <= free_total + free_total / 20);
}
