#pragma once
// The types the bindings share: a grasp of any of the three models, results as NumPy-ready
// Eigen matrices.

#include <sstream>
#include <string>
#include <utility>
#include <variant>

#include <pybind11/pybind11.h>

#include <grip/grip.hpp>

#include "convert.hpp"

namespace grip_python {

namespace py = pybind11;

using HardGrasp = grip::Grasp<grip::Dynamic, grip::HardFinger, double, max_contacts>;
using SoftGrasp = grip::Grasp<grip::Dynamic, grip::SoftFinger, double, max_contacts>;
using PointGrasp = grip::Grasp<grip::Dynamic, grip::FrictionlessPoint, double, max_contacts>;

enum class Model { HardFinger, SoftFinger, FrictionlessPoint };

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A grasp of one of the three models; immutable once made (so solves may run without the GIL).
struct PyGrasp {
  std::variant<HardGrasp, SoftGrasp, PointGrasp> g;
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), g);
  }
  int size() const {
    return visit([](const auto& x) { return x.size(); });
  }
  int dim() const {
    return visit([](const auto& x) { return std::decay_t<decltype(x)>::dim; });
  }
};

/// A number as Python's repr would show it (shortest of %g's forms).
inline std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// x (n * dim) as an (n, dim) array.
template <class Vector>
RowMatrix per_contact_rows(const Vector& x, int dim) {
  return Eigen::Map<const RowMatrix>(x.data(), x.size() / dim, dim);
}

struct SolutionPy {
  RowMatrix forces;  ///< (n, dim)
  grip::Wrench<double> multipliers{grip::Wrench<double>::Zero()};
  grip::Status status{grip::Status::InvalidInput};
  double residual{0};
  int iterations{0};
};

struct ConstrainedPy : SolutionPy {
  grip::Wrench<double> certificate{grip::Wrench<double>::Zero()};
  double objective{0}, dual_objective{0};
  bool fast_path{false};
  bool refined{false};
  int passes{0};
};

struct ForceClosurePy {
  bool closure{false};
  double margin{0};
  grip::Wrench<double> unresisted{grip::Wrench<double>::Zero()};
  RowMatrix internal_force;
  double residual{0};
  int rank{0}, iterations{0};
  grip::Status status{grip::Status::InvalidInput};
};

}  // namespace grip_python

namespace grip_python {
void bind_analysis(py::module_& m);  // analysis.cpp
void bind_monitor(py::module_& m);   // monitor.cpp
void bind_hand(py::module_& m);      // hand.cpp
void bind_pipeline(py::module_& m);  // pipeline.cpp
void bind_mesh(py::module_& m);      // mesh.cpp
}  // namespace grip_python
