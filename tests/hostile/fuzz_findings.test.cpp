// Every input in tests/fuzz/corpus/solvers/ (the solver fuzz target's seeds, among them each
// input with which the fuzzer ever found a broken promise) replayed through the target's own
// decoding and oracle (tests/fuzz/solver_input.hpp): none may break a promise. A fuzzer
// finding is kept by adding its input file there, named for what it found.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/solver_input.hpp"

namespace fuzz_findings_test {

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_CASE("fuzz findings: every committed solver input keeps the oracle's promises") {
  const std::filesystem::path dir = std::filesystem::path(GRIP_TEST_DATA_DIR) / ".." / "fuzz" / "corpus" / "solvers";
  REQUIRE(std::filesystem::is_directory(dir));
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  // The finding of issue 25 (float soft fingers, a denormal squeeze: the reported residual
  // underflowed to 0) must be among them.
  REQUIRE(std::count(files.begin(), files.end(), dir / "denormal_squeeze_residual") == 1);
  // And the least-squares refinement's: one float soft finger on a lever arm of 1e-22 m, whose
  // torsion column, scaled by 1 / L, overflowed when squared (inf times 0 made a NaN force).
  REQUIRE(std::count(files.begin(), files.end(), dir / "torsion_on_a_lever_of_1e-22") == 1);
  for (const auto& f : files) {
    const std::vector<std::uint8_t> bytes = read_bytes(f);
    const char* msg = grip_fuzz::check_solver_input(bytes.data(), bytes.size());
    INFO(f.filename().string(), ": ", msg ? msg : "");
    CHECK_FALSE(grip_fuzz::broken(msg));
  }
}

}  // namespace fuzz_findings_test
