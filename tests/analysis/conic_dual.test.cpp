// The interior-point solver of the conic analyses (analysis/conic_dual.hpp): its second-order
// cone algebra checked against the definitions, and force_closure / max_resistible_wrench
// against cvxopt's solutions of the primal problems (conic_reference.txt, written by
// make_conic_reference.py next to this file).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <grip/analysis/detail/cone_lanes.hpp>
#include <grip/analysis/force_closure.hpp>
#include <grip/analysis/max_wrench.hpp>

#include "support/random.hpp"
#include "support/second_order_cone.hpp"
#include "support/tolerance.hpp"

using namespace grip;

namespace {

// --- The cone algebra -------------------------------------------------------------------------

// A random point of the interior of Q^M: the tail drawn in a ball, the head above its norm.
template <int M>
grip_test::SocVector<double, M> interior_point(std::mt19937& rng) {
  grip_test::Uniform u(-1.0, 1.0), lift(0.01, 2.0);
  grip_test::SocVector<double, M> v;
  for (int k = 0; k < M; ++k) v(k) = u(rng);
  v(0) = grip_test::soc_tail_norm(v) + lift(rng);
  return v;
}

template <int M>
void check_algebra(std::mt19937& rng) {
  using V = grip_test::SocVector<double, M>;
  grip_test::Uniform u(-1.0, 1.0);
  for (int rep = 0; rep < 200; ++rep) {
    const V s = interior_point<M>(rng), z = interior_point<M>(rng);
    grip_test::SocScaling<double, M> w;
    REQUIRE(w.set(s, z));
    // The defining property of the Nesterov-Todd scaling and its consequences.
    const V lambda = w.apply(z);
    const double scale = s.norm() + z.norm();
    CHECK((lambda - w.apply_inverse(s)).norm() <= grip_test::roundoff<double>(64, 1, scale));
    CHECK(std::abs(lambda.squaredNorm() - s.dot(z)) <= grip_test::roundoff<double>(64, 1, scale * scale));
    CHECK(grip_test::soc_interior(lambda));
    V x;
    for (int k = 0; k < M; ++k) x(k) = u(rng);
    CHECK((w.apply(w.apply_inverse(x)) - x).norm() <= grip_test::roundoff<double>(64, 1, x.norm() * (1 + scale)));
    // The Jordan product's definition, and division as its inverse.
    const V p = grip_test::soc_product(s, z);
    CHECK(std::abs(p(0) - s.dot(z)) <= grip_test::roundoff<double>(8, 1, scale * scale));
    if constexpr (M > 1)
      CHECK((p.template tail<M - 1>() - (s(0) * z.template tail<M - 1>() + z(0) * s.template tail<M - 1>())).norm() <=
            grip_test::roundoff<double>(8, 1, scale * scale));
    CHECK((grip_test::soc_product(s, grip_test::soc_divide(s, x)) - x).norm() <=
          grip_test::roundoff<double>(1e4, 1, x.norm() * (1 + s.norm() / grip_test::soc_det(s))));
    // The largest step against bisection on membership.
    const V d = interior_point<M>(rng) - 2.0 * interior_point<M>(rng);
    const double a = grip_test::soc_max_step(s, d);
    if (std::isinf(a)) {
      CHECK(grip_test::soc_interior(V(s + 1e3 * d)));
    } else {
      CHECK(a > 0);
      CHECK(grip_test::soc_interior(V(s + 0.999 * a * d)));
      CHECK_FALSE(grip_test::soc_interior(V(s + 1.001 * a * d)));
    }
  }
}

}  // namespace

TEST_CASE("second-order cone algebra: Nesterov-Todd scaling, Jordan product, step to the boundary") {
  std::mt19937 rng(41);
  check_algebra<1>(rng);
  check_algebra<2>(rng);
  check_algebra<3>(rng);
  check_algebra<4>(rng);
}

// The solver's lane-wise algebra (cone_lanes.hpp: every contact a SIMD lane) against the
// scalar definitions above, cone by cone, for counts that leave the last pack partly empty.
template <int M>
void check_lanes(std::mt19937& rng, int n) {
  using V = grip_test::SocVector<double, M>;
  using Lanes = detail::ConeLanes<double, M, 20>;
  grip_test::Uniform u(-1.0, 1.0);
  Lanes k(n);
  std::vector<V> s(static_cast<std::size_t>(n)), z(s), ds(s), dz(s);
  Eigen::Matrix<double, 7, 7> h_ref = Eigen::Matrix<double, 7, 7>::Zero();
  std::vector<grip_test::SocScaling<double, M>> w(s.size());
  std::vector<Eigen::Matrix<double, M, 7>> f(s.size());
  double step_ref = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const auto j = static_cast<std::size_t>(i);
    s[j] = interior_point<M>(rng);
    z[j] = interior_point<M>(rng);
    ds[j] = interior_point<M>(rng) - 2.0 * interior_point<M>(rng);
    dz[j] = interior_point<M>(rng) - 2.0 * interior_point<M>(rng);
    for (int r = 0; r < M; ++r)
      for (int c = 0; c < 7; ++c) f[j](r, c) = u(rng);
    for (int r = 0; r < M; ++r) {
      Lanes::at(k.s, r, i) = s[j](r);
      Lanes::at(k.z, r, i) = z[j](r);
      Lanes::at(k.ds, r, i) = ds[j](r);
      Lanes::at(k.dz, r, i) = dz[j](r);
      k.set_map(i, r, f[j].row(r));
    }
    REQUIRE(w[j].set(s[j], z[j]));
    Eigen::Matrix<double, M, 7> wf;
    w[j].apply_inverse_to(f[j], wf);
    h_ref += wf.transpose() * wf;
    step_ref = std::min({step_ref, grip_test::soc_max_step(s[j], ds[j]), grip_test::soc_max_step(z[j], dz[j])});
  }
  Eigen::Matrix<double, 7, 7> h = Eigen::Matrix<double, 7, 7>::Zero();
  REQUIRE(k.scale(h));
  CHECK((h - h_ref).norm() <= grip_test::roundoff<double>(256, 1, h_ref.norm()));
  for (int i = 0; i < n; ++i) {
    const auto j = static_cast<std::size_t>(i);
    V lambda;
    for (int r = 0; r < M; ++r) lambda(r) = Lanes::at(k.lambda, r, i);
    CHECK((lambda - w[j].apply(z[j])).norm() <= grip_test::roundoff<double>(64, 1, s[j].norm() + z[j].norm()));
  }
  const double step = k.max_step();
  if (std::isinf(step_ref))
    CHECK(std::isinf(step));
  else
    CHECK(step == doctest::Approx(step_ref).epsilon(1e-12));
  // The affine gap at a = 0 is sum s_i . z_i, the padded lanes (s = z = e) left out.
  double gap_ref = 0;
  for (std::size_t j = 0; j < s.size(); ++j) gap_ref += s[j].dot(z[j]);
  CHECK(k.affine_gap(0.0) == doctest::Approx(gap_ref).epsilon(1e-13));
  // affine_gap also prepared Mehrotra's corrector from ds, dz: d = c + sm e' (fields d, el)
  // solves lambda o d = sm e - lambda o lambda - (W^-1 ds) o (W dz) for every sm.
  for (const double sm : {0.0, 0.37, 5.0}) {
    for (int i = 0; i < n; ++i) {
      const auto j = static_cast<std::size_t>(i);
      V lambda, d;
      for (int r = 0; r < M; ++r) {
        lambda(r) = Lanes::at(k.lambda, r, i);
        d(r) = Lanes::at(k.d, r, i) + sm * Lanes::at(k.el, r, i);
      }
      const V rhs = sm * V::Unit(0) - grip_test::soc_product(lambda, lambda) -
                    grip_test::soc_product(w[j].apply_inverse(ds[j]), w[j].apply(dz[j]));
      CHECK((grip_test::soc_product(lambda, d) - rhs).norm() <= grip_test::roundoff<double>(1024, 1, rhs.norm() + sm));
    }
  }
  // recover, with rc = g = 0 (as constructed): ds_i = F_i dq, dz_i = -W_i^-2 F_i dq,
  // res -= sum F_i^T dz_i, and the step max_step() finds along them.
  Eigen::Matrix<double, 7, 1> dq, res = Eigen::Matrix<double, 7, 1>::Zero(), res_ref = res;
  for (int c = 0; c < 7; ++c) dq(c) = u(rng);
  double step2_ref = std::numeric_limits<double>::infinity(), scale = 0;
  for (int i = 0; i < n; ++i) {
    const auto j = static_cast<std::size_t>(i);
    ds[j] = f[j] * dq;
    dz[j] = -w[j].apply_inverse(w[j].apply_inverse(ds[j]));
    res_ref -= f[j].transpose() * dz[j];
    step2_ref = std::min({step2_ref, grip_test::soc_max_step(s[j], ds[j]), grip_test::soc_max_step(z[j], dz[j])});
    scale += ds[j].norm() + dz[j].norm();
  }
  const double step2 = k.recover(dq, res);
  CHECK(step2 == k.max_step());
  if (std::isinf(step2_ref))
    CHECK(std::isinf(step2));
  else
    CHECK(step2 == doctest::Approx(step2_ref).epsilon(1e-9));
  CHECK((res - res_ref).norm() <= grip_test::roundoff<double>(1024, 1, 8 * scale));
  // advance: the step a, then residuals, gap and H at the new point, in one pass.
  const double a = std::isinf(step2) ? 1.0 : 0.5 * step2;
  Eigen::Matrix<double, 7, 1> q, rd = Eigen::Matrix<double, 7, 1>::Zero(), rd_ref = rd;
  for (int c = 0; c < 7; ++c) q(c) = u(rng);
  Eigen::Matrix<double, 7, 7> h2 = Eigen::Matrix<double, 7, 7>::Zero(), h2_ref = h2;
  double gap2_ref = 0, pres_ref = 0, pres = 0;
  for (int i = 0; i < n; ++i) {
    const auto j = static_cast<std::size_t>(i);
    s[j] += a * ds[j];
    z[j] += a * dz[j];
    gap2_ref += s[j].dot(z[j]);
    rd_ref -= f[j].transpose() * z[j];
    const V rc = f[j] * q - s[j];
    pres_ref = std::max(pres_ref, rc.cwiseAbs().maxCoeff() / (1 + s[j].cwiseAbs().maxCoeff()));
    REQUIRE(w[j].set(s[j], z[j]));
    Eigen::Matrix<double, M, 7> wf;
    w[j].apply_inverse_to(f[j], wf);
    h2_ref += wf.transpose() * wf;
  }
  bool ok = true;
  const double gap2 = k.advance(a, q, rd, pres, h2, ok);
  CHECK(ok);
  CHECK(gap2 == doctest::Approx(gap2_ref).epsilon(1e-10));
  CHECK(pres == doctest::Approx(pres_ref).epsilon(1e-10));
  CHECK((rd - rd_ref).norm() <= grip_test::roundoff<double>(1024, 1, 1 + rd_ref.norm()));
  CHECK((h2 - h2_ref).norm() <= 1e-10 * h2_ref.norm());
}

TEST_CASE("the lane-wise cone algebra agrees with the scalar one, partial packs included") {
  std::mt19937 rng(43);
  for (const int n : {1, 3, 5, 8, 13, 20}) {
    check_lanes<1>(rng, n);
    check_lanes<3>(rng, n);
    check_lanes<4>(rng, n);
  }
}

// --- Against cvxopt ---------------------------------------------------------------------------

namespace {

struct ConicReference {
  char model{'H'};
  int n{0};
  bool margin_feasible{true};
  double margin_lo{0}, margin_hi{0};  // cvxopt's bracket of the optimal margin
  double budget{0};
  double scale_lo{0}, scale_hi{0};    // ... of the largest resistible scale along d
  Wrench<double> d{Wrench<double>::Zero()};
  std::vector<Contact<double>> contacts;
};

std::vector<ConicReference> load_conic_reference(int counts[3]) {
  std::string dir = __FILE__;
  dir = dir.substr(0, dir.find_last_of("/\\") + 1);
  std::ifstream in(dir + "conic_reference.txt");
  std::vector<ConicReference> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("# counts ", 0) == 0) {
      std::istringstream h(line.substr(9));
      char tag = 0;
      int count = 0;
      while (h >> tag >> count) counts[tag == 'H' ? 0 : tag == 'S' ? 1 : 2] = count;
    }
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "instance") {
      ConicReference r;
      int k = 0;
      std::string lo, hi;
      s >> k >> r.model >> r.n >> lo >> hi >> r.budget >> r.scale_lo >> r.scale_hi;
      r.margin_feasible = lo != "none";
      if (r.margin_feasible) {
        r.margin_lo = std::stod(lo);
        r.margin_hi = std::stod(hi);
      }
      out.push_back(r);
    } else if (tag == "d" && !out.empty()) {
      for (int k = 0; k < 6; ++k) s >> out.back().d(k);
    } else if (tag == "c" && !out.empty()) {
      Contact<double> c;
      s >> c.position(0) >> c.position(1) >> c.position(2) >> c.normal(0) >> c.normal(1) >> c.normal(2) >> c.friction >>
          c.torsional_friction;
      c.squeeze = 1.0;
      out.back().contacts.push_back(c);
    }
  }
  return out;
}

template <class S>
const char* S_name() {
  return ScalarTraits<S>::is_single_precision ? "float" : "double";
}

// Distance of v outside [lo, hi].
double outside(double v, double lo, double hi) { return std::max({0.0, lo - v, v - hi}); }

template <class Model, class S>
void check_model(const std::vector<ConicReference>& data, char tag, int expected) {
  using GraspT = Grasp<Dynamic, Model, S, 20>;
  const ConicAnalysisSettings<S> settings;
  const double tol = double(settings.tolerance);
  // In double the data are the reference's own: the answers are within the solver's stopping
  // tolerance of cvxopt's bracket. In float the data are rounded to float first (relative
  // 2^-24), which moves the optimum by up to that times the problem's condition; the solver,
  // run in ScalarTraits<float>::Wide, is then within its tolerance of the rounded problem's
  // optimum. 2^-24 times a condition of 1e3 stays below the float tolerance of 1e-4, so the
  // bound below is twice the stopping tolerance.
  const double bound = ScalarTraits<S>::is_single_precision ? 2 * tol : tol;
  int count = 0, worst_iter = 0, rank_deficient = 0;
  double worst_margin = 0, worst_scale = 0;
  for (const auto& ref : data) {
    if (ref.model != tag) continue;
    ++count;
    GraspT g;
    for (const auto& c : ref.contacts) REQUIRE(g.add(detail::cast_contact<S>(c)) == Status::Ok);
    REQUIRE(g.size() == ref.n);
    const ForceClosure<GraspT> f = force_closure(g, settings);
    REQUIRE(f.status == Status::Ok);
    REQUIRE(ref.margin_feasible);
    worst_iter = std::max(worst_iter, f.iterations);
    if (f.rank < 6) {
      // The rank test at ScalarTraits<S>::rank_tolerance (1e-5 in float: eigenvalues of the
      // scaled Gram matrix below it are not told from the data's rounding) may call a
      // nearly rank-deficient grasp rank-deficient: margin 0, not in closure. Allowed in
      // float only, and only where cvxopt finds no clear closure either.
      ++rank_deficient;
      CHECK(ScalarTraits<S>::is_single_precision);
      CHECK(ref.margin_hi < 20 * tol);
      CHECK_FALSE(f.closure);
      CHECK(double(f.margin) == 0.0);
      continue;
    }
    const double m = double(f.margin);
    const double em = outside(m, ref.margin_lo, ref.margin_hi) / (1 + std::abs(ref.margin_lo));
    worst_margin = std::max(worst_margin, em);
    CHECK(em <= bound);
    // The decision agrees wherever the optimum is clear of the threshold 10 tol.
    if (ref.margin_lo > 20 * tol) CHECK(f.closure);
    if (ref.margin_hi < 5 * tol) CHECK_FALSE(f.closure);
    const Wrench<S> d = ref.d.cast<S>();
    const ResistibleWrench<GraspT> w = max_resistible_wrench(g, d, S(ref.budget), settings);
    REQUIRE(w.status == Status::Ok);
    worst_iter = std::max(worst_iter, w.iterations);
    const double es = outside(double(w.scale), std::max(0.0, ref.scale_lo), std::max(0.0, ref.scale_hi)) /
                      (1 + ref.budget);
    worst_scale = std::max(worst_scale, es);
    CHECK(es <= bound);
  }
  CHECK(count == expected);
  CHECK(count > 0);
  MESSAGE(std::string(1, tag), ": ", count, " instances, worst margin error ", worst_margin, ", worst scale error ", worst_scale,
          " (bound ", bound, "), most iterations ", worst_iter, ", rank-deficient in ", std::string(S_name<S>()), ": ",
          rank_deficient);
}

}  // namespace

TEST_CASE_TEMPLATE("force_closure and max_resistible_wrench agree with cvxopt on every reference grasp", S, double,
                   float) {
  int counts[3] = {-1, -1, -1};
  const auto data = load_conic_reference(counts);
  REQUIRE(!data.empty());
  check_model<HardFinger, S>(data, 'H', counts[0]);
  check_model<SoftFinger, S>(data, 'S', counts[1]);
  check_model<FrictionlessPoint, S>(data, 'F', counts[2]);
}

TEST_CASE("the step to the boundary along the axis: a double root that rounding can hide") {
  // u on the axis, d against it: det(u + a d) = (2 - a)^2 has a double root at a = 2 (the
  // apex), with discriminant 0 that rounding may make negative.
  for (const double s : {1.0, 1e-7, 3.3, 1e5}) {
    grip_test::SocVector<double, 3> u(2 * s, 0, 0), d(-s, 0, 0);
    // disc = B^2 - A C is 0 in exact arithmetic; with B^2 - A C contracted into a fused
    // multiply-add (clang -O2 on FMA targets) it is the rounding error of A C, whose square root
    // moves the root by up to sqrt(u) relative: the bound is sqrt of the rounding bound.
    const double tol = std::sqrt(grip_test::roundoff<double>(8, 1, 1.0));
    CHECK(grip_test::soc_max_step(u, d) == doctest::Approx(2.0).epsilon(tol));
    grip_test::SocVector<double, 4> u4(0.7 * s, 0, 0, 0), d4(-0.1 * s, 0, 0, 0);
    CHECK(grip_test::soc_max_step(u4, d4) == doctest::Approx(7.0).epsilon(tol));
    // The solver's lane-wise step, every lane along the same ray.
    detail::ConeLanes<double, 3, 20> k(11);
    for (int i = 0; i < 11; ++i)
      for (int r = 0; r < 3; ++r) {
        decltype(k)::at(k.s, r, i) = decltype(k)::at(k.z, r, i) = u(r);
        decltype(k)::at(k.ds, r, i) = decltype(k)::at(k.dz, r, i) = d(r);
      }
    CHECK(k.max_step() == doctest::Approx(2.0).epsilon(tol));
  }
}

TEST_CASE_TEMPLATE("hard fingers with mu = 0 are frictionless points: the same margin, decision and scale", S, double,
                   float) {
  // With mu = 0 the Coulomb cone is the ray along the normal, the frictionless point's cone:
  // both models pose the same problems (the hard finger's cone map then has zero rows).
  std::mt19937 rng(7);
  grip_test::Uniform u(0.0, 1.0);
  const double tol = double(ConicAnalysisSettings<S>{}.tolerance);
  int closure = 0;
  for (int rep = 0; rep < 40; ++rep) {
    Grasp<Dynamic, HardFinger, S, 20> h;
    Grasp<Dynamic, FrictionlessPoint, S, 20> p;
    const int n = 7 + rep % 8;
    for (int i = 0; i < n; ++i) {
      const double th = std::acos(1 - 2 * u(rng)), ph = 6.283185307179586 * u(rng);
      const Vector3<double> r(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const Vector3<double> t(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      const Vector3<double> a = (-r + 0.4 * t).normalized();
      Contact<S> c;
      c.position = (0.05 * r).cast<S>();
      c.normal = a.cast<S>();
      c.squeeze = S(1);
      REQUIRE(h.add(c) == Status::Ok);
      REQUIRE(p.add(c) == Status::Ok);
    }
    const auto fh = force_closure(h);
    const auto fp = force_closure(p);
    REQUIRE(fh.status == Status::Ok);
    REQUIRE(fp.status == Status::Ok);
    CHECK(fh.rank == fp.rank);
    CHECK(std::abs(double(fh.margin) - double(fp.margin)) <= 2 * tol * (1 + std::abs(double(fp.margin))));
    CHECK(fh.closure == fp.closure);
    closure += fp.closure ? 1 : 0;
    Wrench<S> d;
    for (int k = 0; k < 6; ++k) d(k) = S(u(rng) - 0.5);
    const auto wh = max_resistible_wrench(h, d, S(5));
    const auto wp = max_resistible_wrench(p, d, S(5));
    REQUIRE(wh.status == Status::Ok);
    REQUIRE(wp.status == Status::Ok);
    CHECK(std::abs(double(wh.scale) - double(wp.scale)) <= 2 * tol * (1 + 5.0));
  }
  CHECK(closure > 0);
}

TEST_CASE_TEMPLATE("no internal force at all: the search stops at margin_floor with a certificate", S, double, float) {
  // Six frictionless points of generic position: G is 6 x 6 of rank 6, so G x = 0 only for
  // x = 0 and no internal force has normal forces summing to 1: the margin problem is
  // infeasible, its dual unbounded. Force closure must say no, with margin below the floor
  // and an unresisted wrench u whose G_i^T u = a_i . u >= 0 for every contact.
  std::mt19937 rng(11);
  grip_test::Uniform u(0.0, 1.0);
  int stopped = 0;
  for (int rep = 0; rep < 20; ++rep) {
    Grasp<6, FrictionlessPoint, S> g;
    for (int i = 0; i < 6; ++i) {
      const double th = std::acos(1 - 2 * u(rng)), ph = 6.283185307179586 * u(rng);
      const Vector3<double> r(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const Vector3<double> t(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      Contact<S> c;
      c.position = (0.05 * r).cast<S>();
      c.normal = (-r + 0.4 * t).normalized().cast<S>();
      c.squeeze = S(1);
      REQUIRE(g.set(i, c) == Status::Ok);
    }
    const ConicAnalysisSettings<S> settings;
    const auto f = force_closure(g, settings);
    REQUIRE(f.status == Status::Ok);
    CHECK_FALSE(f.closure);
    if (f.rank < 6) continue;
    ++stopped;
    CHECK(f.margin < settings.margin_floor);
    CHECK(f.iterations < settings.max_newton_steps);
    CHECK(double(f.unresisted.norm()) == doctest::Approx(1.0).epsilon(1e-3));
    for (int i = 0; i < 6; ++i)
      CHECK(double(g.contact(i).normal.dot(f.unresisted.template head<3>()) +
                   g.contact(i).position.cross(g.contact(i).normal).dot(f.unresisted.template tail<3>())) >=
            -grip_test::roundoff<S>(64, 1, 1));
  }
  CHECK(stopped > 0);
  ConicAnalysisSettings<S> bad;
  for (const S v : {S(0), S(1), std::numeric_limits<S>::quiet_NaN(), -std::numeric_limits<S>::infinity()}) {
    bad.margin_floor = v;
    CHECK_FALSE(valid_settings(bad));
  }
}
