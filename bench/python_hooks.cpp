// grip's C++ times beside its Python calls: the module grip._grip_bench, built only with the
// benchmarks (GRIP_BUILD_BENCH and GRIP_BUILD_PYTHON, never into a wheel), for
// bench/bench_peers.py and bench/bench_python.py. It takes the grip.Grasp objects of grip._grip
// (pybind11 shares registered types between modules of one build).

#include <algorithm>
#include <chrono>
#include <limits>

#include <pybind11/pybind11.h>

#include "../python/src/grasp.hpp"

namespace grip_python {
namespace {

/// The least of `repeats` solve_constrained calls on `g` at the default settings, each timed in
/// C++ (steady_clock, GIL released), in seconds, with the last call's status, iterations and
/// passes: grip's C++ mode beside its Python call on the same instance (bench/bench_peers.py).
py::tuple time_constrained(const PyGrasp& g, const py::handle& w_ext, int repeats) {
  const auto w = wrench(w_ext, "w_ext");
  double least = std::numeric_limits<double>::infinity();
  grip::Status status = grip::Status::InvalidInput;
  int iterations = 0, passes = 0;
  {
    py::gil_scoped_release release;
    g.visit([&](const auto& x) {
      for (int r = 0; r < std::max(1, repeats); ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto s = grip::solve_constrained(x, w);
#if defined(__GNUC__)
        asm volatile("" : : "g"(s.forces.data()) : "memory");  // the solve stays inside the clock reads
#endif
        const auto t1 = std::chrono::steady_clock::now();
        least = std::min(least, std::chrono::duration<double>(t1 - t0).count());
        status = s.status;
        iterations = s.iterations;
        passes = s.passes;
      }
    });
  }
  return py::make_tuple(least, status, iterations, passes);
}

/// Nanoseconds per call of solve_range_space on `g`, measured in C++ over `repeats` calls:
/// the baseline of the Python call's overhead (bench/bench_python.py).
double time_range_space(const PyGrasp& g, const py::handle& w_ext, int repeats) {
  const auto w = wrench(w_ext, "w_ext");
  py::gil_scoped_release release;
  double sink = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < repeats; ++r) g.visit([&](const auto& x) { sink += grip::solve_range_space(x, w).residual; });
  const auto t1 = std::chrono::steady_clock::now();
  volatile double keep = sink;
  (void)keep;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / std::max(1, repeats);
}

}  // namespace
}  // namespace grip_python

PYBIND11_MODULE(_grip_bench, m) {
  m.doc() = "grip's C++ times for the benchmarks (not part of the package)";
  pybind11::module_::import("grip._grip");  // grip.Grasp's type
  m.def("time_constrained", &grip_python::time_constrained, pybind11::arg("grasp"), pybind11::arg("w_ext"),
        pybind11::arg("repeats"));
  m.def("time_range_space", &grip_python::time_range_space, pybind11::arg("grasp"), pybind11::arg("w_ext"),
        pybind11::arg("repeats"));
}
