#pragma once
// Helpers of the solve_constrained tests: the cvxopt reference data set (parsed from
// constrained_reference.txt, found next to this file), and independent optimality checks
// written from the cone definitions (not through the cone types the solver uses).
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <grip/analysis/detail/analysis_cones.hpp>
#include <grip/grip.hpp>

namespace grip_test {

/// One instance of the reference file (see make_constrained_reference.py).
struct ConstrainedReference {
  char model{'H'};
  int n{0};  ///< the contact count the instance line states
  bool feasible{true};
  double objective{0};
  double gap{0};  ///< cvxopt's duality gap at x*: F2(x*) - F2_min <= gap
  grip::Wrench<double> w_ext{grip::Wrench<double>::Zero()};
  std::vector<grip::Contact<double>> contacts;
  std::vector<double> x;                                      ///< cvxopt's optimal forces (feasible instances)
  grip::Wrench<double> lambda{grip::Wrench<double>::Zero()};  ///< cvxopt's multipliers (feasible)
  bool has_lambda{false};
  /// Infeasible instances: |G x_c + w_ext| and F2(x_c) at cvxopt's least-residual forces x_c
  /// (negative when the line is missing).
  double least_residual{-1};
  double least_residual_f2{-1};
  std::string kind;  ///< random, rescaled-1e-3, rescaled-1e3, collinear, nearly-collinear
};

/// The file's "# counts" line: instances and infeasible ones per model tag.
struct ReferenceCounts {
  int instances[3]{-1, -1, -1};  ///< H, S, F; -1 when the line is missing
  int infeasible[3]{-1, -1, -1};
  static int slot(char tag) { return tag == 'H' ? 0 : tag == 'S' ? 1 : 2; }
};

/// Parses tests/solve/constrained_reference.txt (located from this header's own path).
inline std::vector<ConstrainedReference> load_constrained_reference(ReferenceCounts* counts = nullptr) {
  std::string dir = __FILE__;
  dir = dir.substr(0, dir.find_last_of("/\\") + 1);
  std::ifstream in(dir + "constrained_reference.txt");
  std::vector<ConstrainedReference> out;
  std::string line;
  while (std::getline(in, line)) {
    if (counts != nullptr && line.rfind("# counts ", 0) == 0) {
      std::istringstream h(line.substr(9));
      char tag = 0;
      int total = 0, infeasible = 0;
      while (h >> tag >> total >> infeasible) {
        counts->instances[ReferenceCounts::slot(tag)] = total;
        counts->infeasible[ReferenceCounts::slot(tag)] = infeasible;
      }
    }
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "instance") {
      ConstrainedReference r;
      int k = 0;
      std::string status;
      double resid = 0;
      s >> k >> r.model >> r.n >> status >> r.objective >> resid >> r.gap >> r.kind;
      r.feasible = status == "optimal";
      out.push_back(r);
    } else if (tag == "w") {
      for (int i = 0; i < 6; ++i) s >> out.back().w_ext(i);
    } else if (tag == "c") {
      grip::Contact<double> c;
      s >> c.position.x() >> c.position.y() >> c.position.z() >> c.normal.x() >> c.normal.y() >> c.normal.z() >>
          c.friction >> c.torsional_friction >> c.squeeze >> c.weight;
      double bound = -1;
      if (s >> bound && bound > 0) c.max_normal_force = bound;  // bounded instances: -1 for none
      // The file's normals carry 10 digits; a Grasp stores such a normal scaled to unit length
      // (as here), so the checks read the contacts that the solver sees.
      c.normal /= std::sqrt(c.normal.squaredNorm());
      out.back().contacts.push_back(c);
    } else if (tag == "x") {
      double v = 0;
      while (s >> v) out.back().x.push_back(v);
    } else if (tag == "l") {
      for (int i = 0; i < 6; ++i) s >> out.back().lambda(i);
      out.back().has_lambda = static_cast<bool>(s);
    } else if (tag == "r") {
      s >> out.back().least_residual >> out.back().least_residual_f2;
    }
  }
  return out;
}

/// Contact c in scalar type S (e.g. a float grasp's contact in double for the checks below).
template <class S, class From>
grip::Contact<S> cast_contact(const grip::Contact<From>& c) {
  return grip::detail::cast_contact<S>(c);
}

/// Normal part, tangential norm (and moment) of a contact unknown, for each model.
struct ConeCoordinates {
  double n{0}, t{0}, m{0};
};
template <class Model, class Vec>
ConeCoordinates cone_coordinates(const grip::Contact<double>& c, const Vec& x) {
  ConeCoordinates k;
  if constexpr (Model::dim == 1) {
    k.n = double(x(0));
  } else {
    const grip::Vector3<double> f(double(x(0)), double(x(1)), double(x(2)));
    k.n = f.dot(c.normal);
    k.t = (f - k.n * c.normal).norm();
    if constexpr (Model::dim == 4) k.m = double(x(3));
  }
  return k;
}

/// How far x lies outside contact c's exact cone, in N (0 inside), from the definitions:
/// hard |f_t| <= mu f_n; soft sqrt(|f_t|^2/mu^2 + m^2/mu_t^2) <= f_n, i.e.
/// sqrt(mu_t^2 |f_t|^2 + mu^2 m^2) <= mu mu_t f_n; frictionless f_n >= 0.
template <class Model, class Vec>
double cone_violation(const grip::Contact<double>& c, const Vec& x) {
  const ConeCoordinates k = cone_coordinates<Model>(c, x);
  if constexpr (Model::dim == 1) return std::fmax(0.0, -k.n);
  if constexpr (Model::dim == 3) return std::fmax(std::fmax(0.0, k.t - c.friction * k.n), -k.n);
  const double mu = c.friction, mt = c.torsional_friction;
  const double lhs = std::sqrt(mt * mt * k.t * k.t + mu * mu * k.m * k.m);
  return std::fmax(std::fmax(0.0, (lhs - mu * mt * k.n) / std::fmax(mu * mt, 1e-300)), -k.n);
}

/// How far z lies outside the DUAL cone of contact c (0 inside), from the definitions:
/// hard mu |z_t| <= z_n; soft sqrt(mu^2 |z_t|^2 + mu_t^2 z_m^2) <= z_n; frictionless z >= 0.
template <class Model, class Vec>
double dual_cone_violation(const grip::Contact<double>& c, const Vec& z) {
  const ConeCoordinates k = cone_coordinates<Model>(c, z);
  if constexpr (Model::dim == 1) return std::fmax(0.0, -k.n);
  if constexpr (Model::dim == 3) return std::fmax(0.0, c.friction * k.t - k.n);
  const double mu = c.friction, mt = c.torsional_friction;
  return std::fmax(0.0, std::sqrt(mu * mu * k.t * k.t + mt * mt * k.m * k.m) - k.n);
}

/// v.n - mu |v_t| for a hard finger c: >= 0 when v lies in the dual of its friction cone, and
/// how far inside (or, negative, outside) it lies along the normal.
inline double dual_margin(const grip::Contact<double>& c, const grip::Vector3<double>& v) {
  const double vn = v.dot(c.normal);
  return vn - c.friction * (v - vn * c.normal).norm();
}

}  // namespace grip_test
