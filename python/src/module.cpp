// The Python module grip._grip: grasps from NumPy arrays, the grasp matrix and the paper's
// KKT system, the three solvers and force closure, for double and the three contact models
// with a run-time count of 1 to max_contacts contacts. Every solve releases the GIL.

#include <algorithm>
#include <limits>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <grip/grip.hpp>

#include "grasp.hpp"

namespace py = pybind11;

namespace grip_python {

template <class S>
void fill(SolutionPy& out, const S& s, int dim) {
  out.forces = per_contact_rows(s.forces, dim);
  out.multipliers = s.multipliers;
  out.status = s.status;
  out.residual = s.residual;
  out.iterations = s.iterations;
}

/// The binding of a direct solver solve(grasp, w_ext): the wrench checked, then solved
/// without the GIL.
template <class Solve>
auto direct_solver(Solve solve) {
  return [solve](const PyGrasp& g, const py::handle& w) {
    const auto we = wrench(w, "w_ext");
    py::gil_scoped_release release;
    SolutionPy out;
    g.visit([&](const auto& x) { fill(out, solve(x, we), g.dim()); });
    return out;
  };
}

PyGrasp make_grasp(const py::handle& positions, const py::handle& normals, const py::handle& friction,
                   const py::handle& torsional_friction, const py::handle& squeeze, const py::handle& weights,
                   Model model, const py::handle& max_normal_force) {
  const auto cs = contacts(positions, normals, friction, torsional_friction, squeeze, weights, max_normal_force);
  PyGrasp out;
  auto build = [&](auto g) {
    for (const auto& c : cs)
      if (g.add(c) != grip::Status::Ok) invalid("contact rejected by the grasp");
    out.g = std::move(g);
  };
  switch (model) {
    case Model::HardFinger: build(HardGrasp{}); break;
    case Model::SoftFinger: build(SoftGrasp{}); break;
    case Model::FrictionlessPoint: build(PointGrasp{}); break;
  }
  return out;
}

/// The number `member` of every contact, (n,).
Eigen::VectorXd field(const PyGrasp& g, double grip::Contact<double>::*member) {
  return g.visit([member](const auto& x) {
    Eigen::VectorXd v(x.size());
    for (int i = 0; i < x.size(); ++i) v(i) = x.contact(i).*member;
    return v;
  });
}

RowMatrix vectors(const PyGrasp& g, bool normals) {
  return g.visit([normals](const auto& x) {
    RowMatrix m(x.size(), 3);
    for (int i = 0; i < x.size(); ++i) m.row(i) = (normals ? x.contact(i).normal : x.contact(i).position).transpose();
    return m;
  });
}

/// cls.name: `member` read and written like def_readwrite, but a complex number raises
/// TypeError naming the field (def_readwrite would keep a NumPy complex scalar's real part).
template <class C, class T>
py::class_<C>& settable(py::class_<C>& cls, const char* name, T C::*member, const char* doc) {
  return cls.def_property(
      name, [member](const C& c) { return c.*member; }, [member, name](C& c, Number<T> v) { c.*member = v.get(name); },
      doc);
}

}  // namespace grip_python

using namespace grip_python;

PYBIND11_MODULE(_grip, m) {
  m.doc() = "grip: grasp mechanics (the grasp matrix, optimal contact forces, friction cones, force closure).";
  m.attr("max_contacts") = max_contacts;
  m.attr("__version__") = GRIP_VERSION_STRING;  // include/grip/core/version.hpp, the one place it is written

  py::enum_<grip::Status>(m, "Status", "The outcome of every grip computation.")
      .value("Ok", grip::Status::Ok, "success: the answer, to round-off or the tolerance")
      .value("InvalidInput", grip::Status::InvalidInput, "an input or setting out of its domain")
      .value("Singular", grip::Status::Singular, "G has rank < 6: some wrench cannot be balanced at all")
      .value("Infeasible", grip::Status::Infeasible, "no forces inside the friction cones balance the wrench")
      .value("IterationLimit", grip::Status::IterationLimit, "an iterative solver stopped at its bound")
      .value("OutOfRange", grip::Status::OutOfRange, "an input beyond its range or limit, clamped");

  py::enum_<Model>(m, "Model", "The contact model: what one contact transmits.")
      .value("HardFinger", Model::HardFinger, "a force f_i (3 unknowns) in a Coulomb cone")
      .value("SoftFinger", Model::SoftFinger, "a force and a moment about the normal (4 unknowns)")
      .value("FrictionlessPoint", Model::FrictionlessPoint, "a push along the normal (1 unknown)");

  py::class_<PyGrasp>(m, "Grasp",
                      "Contacts on one object. positions (n, 3) in m from the object's centre of mass; "
                      "normals (n, 3), unit, pointing INTO the object; friction mu_i >= 0 (dimensionless); "
                      "torsional_friction mu_t >= 0 (m, soft finger: |m| <= mu_t f_n); squeeze s_i >= 0 (N, "
                      "the force the solvers pull each contact's normal component towards); weights w_i > 0 "
                      "of the objective 1/2 sum w_i |x_i - t_i|^2; max_normal_force c_i > 0 (N, inf for none: "
                      "the largest normal force the contact can apply, a finger's strength or a device's limit, "
                      "kept by solve_constrained only). Numbers may be scalars (the same for every contact) or "
                      "arrays of shape (n,). 1 to max_contacts contacts. Invalid input raises ValueError naming "
                      "the field and the index.")
      .def(py::init(&make_grasp), py::arg("positions"), py::arg("normals"), py::arg("friction"), py::kw_only(),
           py::arg("torsional_friction") = 0.0, py::arg("squeeze") = 0.0, py::arg("weights") = 1.0,
           py::arg("model") = Model::HardFinger, py::arg("max_normal_force") = std::numeric_limits<double>::infinity())
      .def_property_readonly("size", &PyGrasp::size, "number of contacts n")
      .def_property_readonly("dim", &PyGrasp::dim, "unknowns per contact (3, 4 or 1)")
      .def_property_readonly("model", [](const PyGrasp& g) { return static_cast<Model>(g.g.index()); })
      .def_property_readonly(
          "positions", [](const PyGrasp& g) { return vectors(g, false); }, "(n, 3), m")
      .def_property_readonly(
          "normals", [](const PyGrasp& g) { return vectors(g, true); }, "(n, 3), unit, into the object")
      .def_property_readonly("friction", [](const PyGrasp& g) { return field(g, &grip::Contact<double>::friction); })
      .def_property_readonly("torsional_friction",
                             [](const PyGrasp& g) { return field(g, &grip::Contact<double>::torsional_friction); })
      .def_property_readonly("squeeze", [](const PyGrasp& g) { return field(g, &grip::Contact<double>::squeeze); })
      .def_property_readonly("weights", [](const PyGrasp& g) { return field(g, &grip::Contact<double>::weight); })
      .def_property_readonly(
          "max_normal_force", [](const PyGrasp& g) { return field(g, &grip::Contact<double>::max_normal_force); },
          "(n,) the bound on each contact's normal force f_n (N); inf where there is none")
      .def(
          "grasp_matrix",
          [](const PyGrasp& g) { return g.visit([](const auto& x) { return Eigen::MatrixXd(x.grasp_matrix()); }); },
          "G (6, n * dim): G x is the wrench (force in N; moment in N m about the centre of mass) that the contact "
          "unknowns x apply on the object")
      .def(
          "target",
          [](const PyGrasp& g) {
            return g.visit([&](const auto& x) { return per_contact_rows(x.target(), g.dim()); });
          },
          "t (n, dim): the forces the objective pulls each contact towards (hard finger: s_i a_i, N)")
      .def(
          "kkt_matrix",
          [](const PyGrasp& g) { return g.visit([](const auto& x) { return Eigen::MatrixXd(x.kkt_matrix()); }); },
          "the paper's H of eq. 9, (6 + n * dim) square: [[W, -G^T], [G, 0]] in grip's ordering (docs/conventions.md)")
      .def(
          "kkt_rhs",
          [](const PyGrasp& g, const py::handle& w) {
            const auto we = wrench(w, "w_ext");
            return g.visit([&](const auto& x) { return Eigen::VectorXd(x.kkt_rhs(we)); });
          },
          py::arg("w_ext"), "the paper's b of eq. 9 for the external wrench w_ext (6,)")
      .def("__repr__", [](const PyGrasp& g) {
        static const char* names[] = {"HardFinger", "SoftFinger", "FrictionlessPoint"};
        return "<grip.Grasp of " + std::to_string(g.size()) + " contacts, " + names[g.g.index()] + ">";
      });

  py::class_<SolutionPy>(m, "Solution", "Contact forces that balance w_ext (G x + w_ext = 0).")
      .def_readonly("forces", &SolutionPy::forces,
                    "(n, dim): the unknowns per contact (hard finger: f_i in N, ON the object; the hand feels -f_i)")
      .def_readonly("multipliers", &SolutionPy::multipliers, "(6,): lambda of the equilibrium rows")
      .def_readonly("status", &SolutionPy::status)
      .def_readonly("residual", &SolutionPy::residual, "|G x + w_ext| (N and N m)")
      .def_readonly("iterations", &SolutionPy::iterations)
      .def("__repr__", [](const SolutionPy& s) {
        return "<grip.Solution " + std::string(grip::to_string(s.status)) + ", residual " + number(s.residual) + ">";
      });
  py::class_<ConstrainedPy, SolutionPy>(m, "ConstrainedSolution",
                                        "The optimum inside the friction cones, or a certificate that none exists.")
      .def_readonly("certificate", &ConstrainedPy::certificate,
                    "(6,) when Infeasible: y with y . w_ext > 0 and G_i^T y in every dual cone (with bounds: "
                    "G_i^T y + tau_i a_i, tau_i >= 0, sum tau_i c_i < y . w_ext); zero otherwise")
      .def_readonly("objective", &ConstrainedPy::objective, "1/2 sum w_i |x_i - t_i|^2 at forces")
      .def_readonly("dual_objective", &ConstrainedPy::dual_objective,
                    "Ok: the dual function at multipliers (the optimum lies between it and objective); else 0")
      .def_readonly("fast_path", &ConstrainedPy::fast_path,
                    "the unconstrained optimum was inside every cone (and below every bound) and was returned")
      .def_readonly("refined", &ConstrainedPy::refined,
                    "Ok: forces are the exact projections of multipliers and meet settings.tolerance (the fast "
                    "path, or Newton's refinement converged); False when they meet only the interior-point "
                    "tolerance (residual and duality gap): Newton's best iterate or the interior-point answer")
      .def_readonly("passes", &ConstrainedPy::passes,
                    "O(n) passes over the contacts after the fast path: three per interior-point iteration, one "
                    "more per interior-point run, one per Newton trial");
  py::class_<ForceClosurePy>(m, "ForceClosure", "Force closure of a grasp with its exact cones.")
      .def_readonly("closure", &ForceClosurePy::closure)
      .def_readonly("margin", &ForceClosurePy::margin,
                    "largest t such that an internal force of total normal force 1 keeps x_i - t e_i in every cone "
                    "(-1e15 when no internal force has normal forces summing to 1; an upper bound at IterationLimit)")
      .def_readonly("unresisted", &ForceClosurePy::unresisted,
                    "(6,) a unit wrench that cannot be resisted (zero in closure and at IterationLimit)")
      .def_readonly("internal_force", &ForceClosurePy::internal_force,
                    "(n, dim) an internal force achieving the margin")
      .def_readonly("residual", &ForceClosurePy::residual, "|G internal_force|")
      .def_readonly("rank", &ForceClosurePy::rank)
      .def_readonly("iterations", &ForceClosurePy::iterations)
      .def_readonly("status", &ForceClosurePy::status)
      .def("__repr__", [](const ForceClosurePy& f) {
        return std::string("<grip.ForceClosure ") + (f.closure ? "closure" : "no closure") + ", margin " +
               number(f.margin) + ">";
      });

  using CS = grip::ConstrainedSettings<double>;
  py::class_<CS> constrained_settings(m, "ConstrainedSettings",
                                      "Tolerances and bounds of solve_constrained (docs/solve.md). Reals finite, > 0 "
                                      "and < 1; max_iterations >= 1, newton_passes >= 0; otherwise the solve answers "
                                      "InvalidInput.");
  constrained_settings.def(py::init<>());
  settable(constrained_settings, "tolerance", &CS::tolerance,
           "Ok when |G x + w_ext|_L <= tolerance (|w_ext|_L + |x|) and |lambda.(G x + w_ext)| <= tolerance F2");
  settable(constrained_settings, "certificate_tolerance", &CS::certificate_tolerance,
           "Infeasible when y.w_ext > 0 and every G_i^T y is within certificate_tolerance (y.w_ext) / "
           "|w_ext|_L of K_i^* (its dual cone)");
  settable(constrained_settings, "least_residual_weight", &CS::least_residual_weight,
           "delta / (largest diagonal entry of G W^-1 G^T in |.|_L's units): Infeasible forces minimise "
           "|r|_L^2/2 + delta F2");
  settable(constrained_settings, "max_iterations", &CS::max_iterations,
           "interior-point iterations of a solve, both problems together (three O(n) passes each): the "
           "deadline (default 40)");
  settable(constrained_settings, "newton_passes", &CS::newton_passes,
           "Newton passes of the warm start and of the refinement, each (one O(n) pass and a 6x6 solve "
           "each; default 8)");
  using AS = grip::ConicAnalysisSettings<double>;
  py::class_<AS> analysis_settings(m, "ConicAnalysisSettings",
                                   "Tolerance and bound of force_closure (docs/analysis.md). tolerance finite and > 0, "
                                   "max_iterations >= 1; otherwise the analysis answers InvalidInput.");
  analysis_settings.def(py::init<>());
  settable(analysis_settings, "tolerance", &AS::tolerance,
           "the interior-point method's residuals and gap (relative) below it; Ok when the margin is "
           "bracketed within tolerance (1 + |margin|); closure when margin > 10 tolerance (default 1e-6)");
  settable(analysis_settings, "max_iterations", &AS::max_iterations,
           "interior-point iterations (three O(n) passes each): the worst-case time (default 50)");

  m.def("solve_range_space",
        direct_solver([](const auto& x, const grip::Wrench<double>& w) { return grip::solve_range_space(x, w); }),
        py::arg("grasp"), py::arg("w_ext"),
        "The forces nearest the targets (min 1/2 sum w_i |x_i - t_i|^2) with G x + w_ext = 0, no cones: "
        "the paper's optimum, by the range-space method. Singular when G has rank < 6.");
  m.def("solve_kkt", direct_solver([](const auto& x, const grip::Wrench<double>& w) { return grip::solve_kkt(x, w); }),
        py::arg("grasp"), py::arg("w_ext"), "As solve_range_space, by the paper's KKT system of eq. 9 (H c = b).");
  m.def(
      "solve_constrained",
      [](const PyGrasp& g, const py::handle& w, const CS* settings, const py::handle& warm,
         const py::handle& certificate) {
        const auto we = wrench(w, "w_ext");
        const CS s = settings ? *settings : CS{};
        grip::ConstrainedWarmStart<double> start;
        start.has_multipliers = !warm.is_none();
        if (start.has_multipliers) start.multipliers = wrench(warm, "warm_start");
        start.has_certificate = !certificate.is_none();
        if (start.has_certificate) start.certificate = wrench(certificate, "warm_certificate");
        py::gil_scoped_release release;
        ConstrainedPy out;
        g.visit([&](const auto& x) {
          const auto r = grip::solve_constrained(x, we, s, start);
          fill(out, r, g.dim());
          out.certificate = r.certificate;
          out.objective = r.objective;
          out.dual_objective = r.dual_objective;
          out.fast_path = r.fast_path;
          out.refined = r.refined;
          out.passes = r.passes;
        });
        return out;
      },
      py::arg("grasp"), py::arg("w_ext"), py::arg("settings") = nullptr, py::arg("warm_start") = py::none(),
      py::arg("warm_certificate") = py::none(),
      "The forces nearest the targets inside the exact friction cones (and below each contact's "
      "max_normal_force) with G x + w_ext = 0; Infeasible with a certificate when the grasp cannot hold. "
      "warm_start: the previous solution's multipliers (6,). warm_certificate: the previous solution's "
      "certificate (6,), if it slipped: where it still holds, the answer is Infeasible with it.");
  m.def(
      "force_closure",
      [](const PyGrasp& g, const AS* settings) {
        const AS s = settings ? *settings : AS{};
        py::gil_scoped_release release;
        ForceClosurePy out;
        g.visit([&](const auto& x) {
          const auto r = grip::force_closure(x, s);
          out.closure = r.closure;
          out.margin = r.margin;
          out.unresisted = r.unresisted;
          out.internal_force = per_contact_rows(r.internal_force, g.dim());
          out.residual = r.residual;
          out.rank = r.rank;
          out.iterations = r.iterations;
          out.status = r.status;
        });
        return out;
      },
      py::arg("grasp"), py::arg("settings") = nullptr,
      "Whether forces inside the cones can balance every wrench, with the margin and, when not, a wrench "
      "direction that cannot be resisted.");

  bind_analysis(m);
  bind_monitor(m);
  bind_hand(m);
  bind_pipeline(m);
  bind_mesh(m);
}
