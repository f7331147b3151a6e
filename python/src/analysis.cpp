// Grasp analysis from Python: quality, the split of contact forces, the largest resistible
// wrench, Ferrari-Canny epsilon, and the batch functions that evaluate or solve thousands of
// candidate grasps given as arrays, on all cores, with no Python loop.

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "grasp.hpp"

namespace grip_python {
namespace {

template <class T>
struct Tag {
  using type = T;
};

/// f(Tag<GraspType>) for the grasp type of `model`.
template <class F>
void dispatch(Model model, F&& f) {
  switch (model) {
    case Model::HardFinger: f(Tag<HardGrasp>{}); break;
    case Model::SoftFinger: f(Tag<SoftGrasp>{}); break;
    case Model::FrictionlessPoint: f(Tag<PointGrasp>{}); break;
  }
}

/// f(std::integral_constant<int, K>) for the sides K of the linearised cones.
template <class F>
void with_sides(int sides, F&& f) {
  switch (sides) {
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 8: f(std::integral_constant<int, 8>{}); break;
    case 16: f(std::integral_constant<int, 16>{}); break;
    default: invalid("sides must be 4, 8 or 16, not " + std::to_string(sides));
  }
}

/// This thread's epsilon workspace (10.6 MB, from the heap, once per thread).
grip::EpsilonWorkspace<double>& workspace() {
  thread_local std::unique_ptr<grip::EpsilonWorkspace<double>> ws(new grip::EpsilonWorkspace<double>());
  return *ws;
}

grip::EpsilonNorm epsilon_norm(const std::string& norm) {
  if (norm == "L1") return grip::EpsilonNorm::L1;
  if (norm == "Linf") return grip::EpsilonNorm::LInfinity;
  invalid("norm must be 'L1' or 'Linf', not '" + norm + "'");
}

double positive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v)) invalid(std::string(name) + " must be finite and > 0, not " + std::to_string(v));
  return v;
}

struct EpsilonPy {
  double epsilon{0}, upper{0};
  grip::Wrench<double> direction{grip::Wrench<double>::Zero()};
  bool closure{false};
  int vertices{0}, facets{0};
  grip::Status status{grip::Status::InvalidInput};
};

/// Candidate grasps as arrays of one shape: positions and normals (k, n, 3), the numbers (k, n).
struct Batch {
  Array p, a, mu, mut, s, w, fmax;
  bool bounded{false};  ///< whether fmax holds max_normal_force (else +inf: no bounds)
  py::ssize_t k{0}, n{0};
  py::ssize_t first{0};  ///< the index of candidate 0 in messages (a chunk of a larger batch)
  /// Contact i of grasp j (C-contiguous arrays), checked (ValueError naming [first + j, i]).
  grip::Contact<double> at(py::ssize_t j, py::ssize_t i) const {
    const py::ssize_t e = j * n + i;
    return contact(p.data() + 3 * e, a.data() + 3 * e, mu.data()[e], mut.data()[e], s.data()[e], w.data()[e],
                   bounded ? fmax.data()[e] : std::numeric_limits<double>::infinity(),
                   [this, j, i] { return "[" + std::to_string(first + j) + ", " + std::to_string(i) + "]"; });
  }
};

/// The batch's arrays, their shapes checked; max_normal_force may be None (no bounds).
Batch batch(const py::handle& positions, const py::handle& normals, const py::handle& friction,
            const py::handle& torsional_friction, const py::handle& squeeze, const py::handle& weights,
            const py::handle& max_normal_force, py::ssize_t first) {
  Batch b;
  b.first = first;
  auto get = [](const py::handle& h, const char* name, int ndim) {
    Array x = numbers(h, name);
    if (!x || x.ndim() != ndim)
      invalid(std::string(name) + " must be an array of " + std::to_string(ndim) + " dimensions");
    return x;
  };
  b.p = get(positions, "positions", 3);
  b.a = get(normals, "normals", 3);
  b.k = b.p.shape(0);
  b.n = b.p.shape(1);
  if (b.p.shape(2) != 3) invalid("positions must have shape (k, n, 3), not " + shape_of(b.p));
  if (b.a.shape(0) != b.k || b.a.shape(1) != b.n || b.a.shape(2) != 3)
    invalid("normals must have the shape of positions " + shape_of(b.p) + ", not " + shape_of(b.a));
  if (b.n < 1 || b.n > max_contacts)
    invalid("a grasp has 1 to " + std::to_string(max_contacts) + " contacts, not " + std::to_string(b.n));
  b.bounded = !max_normal_force.is_none();
  Array* fields[] = {&b.mu, &b.mut, &b.s, &b.w, &b.fmax};
  const py::handle given[] = {friction, torsional_friction, squeeze, weights, max_normal_force};
  const char* names[] = {"friction", "torsional_friction", "squeeze", "weights", "max_normal_force"};
  for (int f = 0; f < (b.bounded ? 5 : 4); ++f) {
    *fields[f] = get(given[f], names[f], 2);
    if (fields[f]->shape(0) != b.k || fields[f]->shape(1) != b.n)
      invalid(std::string(names[f]) + " must have shape (k, n) = (" + std::to_string(b.k) + ", " + std::to_string(b.n) +
              "), not " + shape_of(*fields[f]));
  }
  return b;
}

/// Runs work(begin, end) over [0, count) in contiguous chunks on `threads` threads (0: all
/// cores), the calling thread one of them; the GIL must be released. A chunk stops at its
/// first ValueError (an invalid contact); the one of the lowest chunk is raised after all
/// threads have joined.
template <class Work>
void parallel(py::ssize_t count, int threads, const Work& work) {
  int t = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  t = static_cast<int>(std::max<py::ssize_t>(1, std::min<py::ssize_t>({py::ssize_t(t), count, py::ssize_t(256)})));
  auto begin = [&](int i) { return count * i / t; };
  std::vector<std::string> errors(static_cast<std::size_t>(t));
  auto run = [&](int i) {
    try {
      work(begin(i), begin(i + 1));
    } catch (const py::value_error& e) {
      errors[static_cast<std::size_t>(i)] = e.what();
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < t; ++i) pool.emplace_back(run, i);
  run(0);
  for (auto& th : pool) th.join();
  for (const std::string& e : errors)
    if (!e.empty()) throw py::value_error(e);
}

template <class G>
G build(const Batch& b, py::ssize_t j) {
  G g;
  for (py::ssize_t i = 0; i < b.n; ++i) (void)g.add(b.at(j, i));
  return g;
}

py::dict evaluate_batch(const py::handle& positions, const py::handle& normals, const py::handle& friction,
                        const py::handle& torsional_friction, const py::handle& squeeze, const py::handle& weights,
                        Model model, Real lever_length, bool closure, bool eps_l1, bool eps_linf, Integer sides,
                        Integer threads, py::ssize_t first) {
  const Batch b = batch(positions, normals, friction, torsional_friction, squeeze, weights, py::none(), first);
  grip::BatchSettings<double> settings;
  settings.lever_length = positive(lever_length.get("lever_length"), "lever_length");
  settings.force_closure = closure;
  settings.epsilon_l1 = eps_l1;
  settings.epsilon_linf = eps_linf;
  const py::ssize_t k = b.k;
  py::array_t<double> sv({k, py::ssize_t(6)}), volume(k), isotropy(k), margin(k), e1(k), einf(k);
  py::array_t<bool> in_closure(k);
  py::array_t<int> status(k);
  double *psv = sv.mutable_data(), *pvol = volume.mutable_data(), *piso = isotropy.mutable_data(),
         *pm = margin.mutable_data(), *pe1 = e1.mutable_data(), *pinf = einf.mutable_data();
  bool* pc = in_closure.mutable_data();
  int* pst = status.mutable_data();
  const int nthreads = threads.get("threads");
  with_sides(sides.get("sides"), [&](auto kk) {
    constexpr int K = decltype(kk)::value;
    dispatch(model, [&](auto tag) {
      using G = typename decltype(tag)::type;
      py::gil_scoped_release release;
      parallel(k, nthreads, [&](py::ssize_t begin, py::ssize_t end) {
        grip::EpsilonWorkspace<double>& ws = workspace();
        for (py::ssize_t j = begin; j < end; ++j) {
          const auto r = grip::evaluate_grasp<K>(build<G>(b, j), settings, ws);
          for (int q = 0; q < 6; ++q) psv[6 * j + q] = r.quality.singular_values(q);
          pvol[j] = r.quality.volume;
          piso[j] = r.quality.isotropy;
          pc[j] = r.closure;
          pm[j] = r.closure_margin;
          pe1[j] = r.epsilon_l1.epsilon;
          pinf[j] = r.epsilon_linf.epsilon;
          pst[j] = static_cast<int>(r.status);
        }
      });
    });
  });
  py::dict out;
  out["singular_values"] = sv;
  out["volume"] = volume;
  out["isotropy"] = isotropy;
  out["closure"] = in_closure;
  out["closure_margin"] = margin;
  out["epsilon_l1"] = e1;
  out["epsilon_linf"] = einf;
  out["status"] = status;
  return out;
}

py::dict solve_batch(const py::handle& positions, const py::handle& normals, const py::handle& friction,
                     const py::handle& torsional_friction, const py::handle& squeeze, const py::handle& weights,
                     const py::handle& max_normal_force, Model model, const py::handle& w_ext,
                     const std::string& method, const grip::ConstrainedSettings<double>& settings, Integer threads,
                     py::ssize_t first) {
  const Batch b = batch(positions, normals, friction, torsional_friction, squeeze, weights, max_normal_force, first);
  if (method != "range_space" && method != "kkt" && method != "constrained")
    invalid("method must be 'range_space', 'kkt' or 'constrained', not '" + method + "'");
  const Array wa = numbers(w_ext, "w_ext");
  if (!wa || wa.ndim() != 2 || wa.shape(0) != b.k || wa.shape(1) != 6)
    invalid("w_ext must have shape (k, 6) = (" + std::to_string(b.k) + ", 6), not " +
            (wa ? shape_of(wa) : std::string("?")));
  for (py::ssize_t j = 0; j < b.k; ++j)
    for (int q = 0; q < 6; ++q)
      if (!std::isfinite(wa.at(j, q)) || std::abs(wa.at(j, q)) > grip::ScalarTraits<double>::max_magnitude)
        invalid("w_ext[" + std::to_string(first + j) + ", " + std::to_string(q) + "] is not finite (or beyond 1e15)");
  const int nthreads = threads.get("threads");
  const py::ssize_t k = b.k;
  int dim = 0;
  dispatch(model, [&](auto tag) { dim = decltype(tag)::type::dim; });
  py::array_t<double> forces({k, b.n, py::ssize_t(dim)}), multipliers({k, py::ssize_t(6)}),
      certificate({k, py::ssize_t(6)}), residual(k);
  py::array_t<int> status(k), iterations(k);
  double *pf = forces.mutable_data(), *pl = multipliers.mutable_data(), *pc = certificate.mutable_data(),
         *pr = residual.mutable_data();
  int *pst = status.mutable_data(), *pit = iterations.mutable_data();
  const int which = method == "range_space" ? 0 : method == "kkt" ? 1 : 2;
  dispatch(model, [&](auto tag) {
    using G = typename decltype(tag)::type;
    py::gil_scoped_release release;
    parallel(k, nthreads, [&](py::ssize_t begin, py::ssize_t end) {
      for (py::ssize_t j = begin; j < end; ++j) {
        const G g = build<G>(b, j);
        grip::Wrench<double> w;
        for (int q = 0; q < 6; ++q) w(q) = wa.data()[6 * j + q];
        auto put = [&](const auto& s) {
          const py::ssize_t m = b.n * dim;
          for (py::ssize_t q = 0; q < m; ++q) pf[j * m + q] = s.forces.size() == m ? s.forces(q) : 0.0;
          for (int q = 0; q < 6; ++q) pl[6 * j + q] = s.multipliers(q);
          pr[j] = s.residual;
          pst[j] = static_cast<int>(s.status);
          pit[j] = s.iterations;
        };
        for (int q = 0; q < 6; ++q) pc[6 * j + q] = 0;
        if (which == 0) {
          put(grip::solve_range_space(g, w));
        } else if (which == 1) {
          put(grip::solve_kkt(g, w));
        } else {
          const auto s = grip::solve_constrained(g, w, settings);
          put(s);
          for (int q = 0; q < 6; ++q) pc[6 * j + q] = s.certificate(q);
        }
      }
    });
  });
  py::dict out;
  out["forces"] = forces;
  out["multipliers"] = multipliers;
  out["certificate"] = certificate;
  out["residual"] = residual;
  out["status"] = status;
  out["iterations"] = iterations;
  return out;
}

/// decompose_forces' answer, its parts as (n, dim) arrays.
struct DecompositionPy {
  RowMatrix external;
  RowMatrix internal;
  grip::Status status{grip::Status::InvalidInput};
};

}  // namespace

void bind_analysis(py::module_& m) {
  py::class_<grip::GraspQuality<double>>(m, "GraspQuality", "Singular-value measures of G (lever length L).")
      .def_readonly("singular_values", &grip::GraspQuality<double>::singular_values, "(6,), descending")
      .def_readonly("sigma_min", &grip::GraspQuality<double>::sigma_min)
      .def_readonly("sigma_max", &grip::GraspQuality<double>::sigma_max)
      .def_readonly("volume", &grip::GraspQuality<double>::volume, "pi^3/6 prod sigma_k")
      .def_readonly("isotropy", &grip::GraspQuality<double>::isotropy, "sigma_min / sigma_max")
      .def_readonly("status", &grip::GraspQuality<double>::status);
  m.def(
      "grasp_quality",
      [](const PyGrasp& g, Real lever_length) {
        const double lever = positive(lever_length.get("lever_length"), "lever_length");
        return g.visit([lever](const auto& x) { return grip::grasp_quality(x, lever); });
      },
      py::arg("grasp"), py::arg("lever_length") = 1.0,
      "The singular values of G with moments divided by lever_length (m), their product volume and isotropy.");

  py::class_<EpsilonPy>(m, "Epsilon", "The Ferrari-Canny measure with linearised cones.")
      .def_readonly("epsilon", &EpsilonPy::epsilon, "radius of the largest ball in the wrench set (N per N of budget)")
      .def_readonly("upper", &EpsilonPy::upper, "an upper bound on epsilon")
      .def_readonly("direction", &EpsilonPy::direction,
                    "(6,) the weakest unit wrench direction (moments / lever_length)")
      .def_readonly("closure", &EpsilonPy::closure)
      .def_readonly("vertices", &EpsilonPy::vertices)
      .def_readonly("facets", &EpsilonPy::facets)
      .def_readonly("status", &EpsilonPy::status);
  m.def(
      "epsilon",
      [](const PyGrasp& g, const std::string& norm, Real lever_length, Integer sides) {
        const grip::EpsilonNorm nm = epsilon_norm(norm);
        const double lever = positive(lever_length.get("lever_length"), "lever_length");
        EpsilonPy out;
        with_sides(sides.get("sides"), [&](auto kk) {
          py::gil_scoped_release release;
          g.visit([&](const auto& x) {
            const auto e = grip::ferrari_canny_epsilon<decltype(kk)::value>(x, nm, lever, workspace());
            out = EpsilonPy{e.epsilon, e.upper, e.direction, e.closure, e.vertices, e.facets, e.status};
          });
        });
        return out;
      },
      py::arg("grasp"), py::arg("norm") = "L1", py::arg("lever_length") = 1.0, py::arg("sides") = 8,
      "Ferrari-Canny epsilon: 'L1' (normal forces summing to 1) or 'Linf' (each at most 1), the friction cones "
      "linearised with `sides` (4, 8 or 16) sides, moments divided by lever_length (m).");

  py::class_<DecompositionPy>(m, "ForceDecomposition",
                              "forces = external + internal: G internal = 0, external the W-orthogonal part that "
                              "balances G forces. Unpacks as (external, internal, status).")
      .def_readonly("external", &DecompositionPy::external, "(n, dim) the part that G maps to G forces")
      .def_readonly("internal", &DecompositionPy::internal, "(n, dim) the internal forces: G internal = 0")
      .def_readonly("status", &DecompositionPy::status)
      .def("__iter__",
           [](const DecompositionPy& d) { return py::iter(py::make_tuple(d.external, d.internal, d.status)); });
  m.def(
      "decompose_forces",
      [](const PyGrasp& g, const py::handle& forces) {
        const Array f = numbers(forces, "forces");
        if (!f || f.ndim() != 2 || f.shape(0) != g.size() || f.shape(1) != g.dim())
          invalid("forces must have shape (" + std::to_string(g.size()) + ", " + std::to_string(g.dim()) + ")");
        Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(f.data(), f.size());
        if (!x.allFinite()) invalid("forces must be finite");
        return g.visit([&](const auto& gr) {
          using GT = std::decay_t<decltype(gr)>;
          const typename GT::ForceVector xv = x;
          const auto d = grip::decompose_forces(gr, xv);
          return DecompositionPy{per_contact_rows(d.external, g.dim()), per_contact_rows(d.internal, g.dim()),
                                 d.status};
        });
      },
      py::arg("grasp"), py::arg("forces"),
      "A ForceDecomposition: forces = external + internal, G internal = 0, external the W-orthogonal part that "
      "balances G forces.");

  m.def("_evaluate_batch", &evaluate_batch);
  m.def("_solve_batch", &solve_batch);
}

}  // namespace grip_python
