// libFuzzer target over grip's public solvers (clang -fsanitize=fuzzer,address,undefined).
// The input format and the checks are in solver_input.hpp: the bytes decode into a grasp and
// an external wrench, and every solver runs under the hostile-input test's oracle with Eigen's
// heap check armed. Any broken promise aborts, which libFuzzer reports as a crash.
//
// Seeds and past findings: tests/fuzz/corpus/solvers/ (each also replayed by the doctest case
// in tests/hostile/fuzz_findings.test.cpp). Build and run (N minutes = 60 N seconds):
//   cmake --workflow --preset ci-fuzz && bash cmake/fuzz.sh 600
#define EIGEN_RUNTIME_NO_MALLOC
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz/solver_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const char* msg = grip_fuzz::check_solver_input(data, size);
  if (grip_fuzz::broken(msg)) {
    std::fprintf(stderr, "broken promise: %s\n", msg);
    std::abort();
  }
  return 0;
}
