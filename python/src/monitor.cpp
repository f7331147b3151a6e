// The friction-cone monitor from Python: the mode of every contact (sticking, sliding,
// separating: the paper's eq. 4-5) under given forces, with margins and the force's parts.

#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "grasp.hpp"

namespace grip_python {
namespace {

struct MonitorPy {
  Eigen::VectorXi mode;  ///< (n,) ContactMode values
  Eigen::VectorXd margin, relative_margin, normal_force, moment;
  RowMatrix tangential_force;                       ///< (n, 3)
  Eigen::Matrix<bool, Eigen::Dynamic, 1> at_bound;  ///< (n,)
  bool stable{false};
  int sticking{0}, sliding{0}, separating{0}, at_bound_count{0};
  double min_margin{0};
  grip::Status status{grip::Status::InvalidInput};
};

MonitorPy monitor(const PyGrasp& g, const py::handle& forces, Real relative, Real absolute) {
  const Array f = numbers(forces, "forces");
  const double relative_tolerance = relative.get("relative_tolerance");
  const double absolute_tolerance = absolute.get("absolute_tolerance");
  if (!f || f.ndim() != 2 || f.shape(0) != g.size() || f.shape(1) != g.dim())
    invalid("forces must have shape (" + std::to_string(g.size()) + ", " + std::to_string(g.dim()) + ")");
  for (py::ssize_t k = 0; k < f.size(); ++k)
    if (!std::isfinite(f.data()[k])) invalid("forces[" + std::to_string(k / g.dim()) + "] is not finite");
  if (!std::isfinite(relative_tolerance) || !std::isfinite(absolute_tolerance))
    invalid("the tolerances must be finite");
  grip::MonitorSettings<double> settings;
  settings.relative_tolerance = relative_tolerance;
  settings.absolute_tolerance = absolute_tolerance;
  MonitorPy out;
  g.visit([&](const auto& x) {
    using GT = std::decay_t<decltype(x)>;
    const typename GT::ForceVector fv = Eigen::Map<const Eigen::VectorXd>(f.data(), f.size());
    const auto s = grip::monitor_grasp(x, fv, settings);
    const int n = x.size();
    out.mode.resize(n);
    out.margin.resize(n);
    out.relative_margin.resize(n);
    out.normal_force.resize(n);
    out.moment.resize(n);
    out.tangential_force.resize(n, 3);
    out.at_bound.setZero(n);
    for (int i = 0; i < n && s.status == grip::Status::Ok; ++i) {
      const auto& c = s.contact(i);
      out.mode(i) = static_cast<int>(c.mode);
      out.margin(i) = c.margin;
      out.relative_margin(i) = c.relative_margin;
      out.normal_force(i) = c.normal_force;
      out.moment(i) = c.moment;
      out.tangential_force.row(i) = c.tangential_force.transpose();
      out.at_bound(i) = c.at_bound;
    }
    out.stable = s.stable;
    out.sticking = s.sticking_count;
    out.sliding = s.sliding_count;
    out.separating = s.separating_count;
    out.at_bound_count = s.at_bound_count;
    out.min_margin = s.min_margin;
    out.status = s.status;
  });
  return out;
}

}  // namespace

void bind_monitor(py::module_& m) {
  py::enum_<grip::ContactMode>(m, "ContactMode", "What one contact does under the forces (eq. 4-5).")
      .value("Sticking", grip::ContactMode::Sticking, "f_n > 0 and the force inside its friction cone")
      .value("Sliding", grip::ContactMode::Sliding, "f_n > 0 but outside the cone: the finger slips")
      .value("Separating", grip::ContactMode::Separating, "f_n <= 0: the finger would have to pull");
  py::class_<MonitorPy>(m, "MonitorReport", "The monitor's report on every contact of a grasp.")
      .def_readonly("mode", &MonitorPy::mode, "(n,) ContactMode values (int(grip.ContactMode.Sliding), ...)")
      .def_readonly("margin", &MonitorPy::margin,
                    "(n,) the cone's margin (N): >= 0 inside (hard finger: mu f_n - |f_t|)")
      .def_readonly("relative_margin", &MonitorPy::relative_margin, "(n,) <= 1 (hard finger: 1 - |f_t| / (mu f_n))")
      .def_readonly("normal_force", &MonitorPy::normal_force, "(n,) f_n = f . a (N)")
      .def_readonly("tangential_force", &MonitorPy::tangential_force, "(n, 3) f - f_n a (N)")
      .def_readonly("moment", &MonitorPy::moment, "(n,) the torsional moment about a (N m; soft finger)")
      .def_readonly("at_bound", &MonitorPy::at_bound,
                    "(n,) bool: the contact has a max_normal_force c and f_n reaches it to the tolerance "
                    "(f_n >= c - absolute_tolerance - relative_tolerance c)")
      .def_readonly("stable", &MonitorPy::stable, "every contact sticks")
      .def_readonly("sticking", &MonitorPy::sticking)
      .def_readonly("sliding", &MonitorPy::sliding)
      .def_readonly("separating", &MonitorPy::separating)
      .def_readonly("at_bound_count", &MonitorPy::at_bound_count, "the contacts at their max_normal_force")
      .def_readonly("min_margin", &MonitorPy::min_margin)
      .def_readonly("status", &MonitorPy::status);
  m.def("monitor", &monitor, py::arg("grasp"), py::arg("forces"),
        py::arg("relative_tolerance") = grip::ScalarTraits<double>::default_tolerance,
        py::arg("absolute_tolerance") = 0.0,
        "Classifies every contact under `forces` (n, dim): Separating if f_n <= 0, else Sliding if the cone's margin "
        "is below -(absolute_tolerance + relative_tolerance f_n), else Sticking; with margins and the force's parts.");
}

}  // namespace grip_python
