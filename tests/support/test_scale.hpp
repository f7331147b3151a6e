#pragma once
// The size of the suite's statistical loops. GRIP_TEST_SCALE (a positive number, default 1)
// multiplies the trial counts of the heaviest randomised tests; the sanitizer configuration sets
// it below 1, since a memory or undefined-behaviour error shows on the first grasps of a loop as
// well as on the last, while an -O0 build under AddressSanitizer runs them 20 to 50 times
// slower. A check that counts events over the trials (for example "closure held in at least 3 of
// 10 trials") takes its bound from scaled_bound, so a smaller run still checks that they occur.
#include <cmath>
#include <cstdlib>

namespace grip_test {

/// GRIP_TEST_SCALE, or 1 when it is unset, not a number or not in (0, 1e3].
inline double test_scale() {
  const char* v = std::getenv("GRIP_TEST_SCALE");
  if (v == nullptr || *v == '\0') return 1.0;
  char* end = nullptr;
  const double s = std::strtod(v, &end);
  return end != v && s > 0.0 && s <= 1e3 ? s : 1.0;
}

/// `n` trials at scale 1: round(n * test_scale()), at least `at_least` (and at least 1).
inline int scaled(int n, int at_least = 1) {
  const long k = std::lround(n * test_scale());
  const long lo = at_least > 1 ? at_least : 1;
  return static_cast<int>(k < lo ? lo : k);
}

/// The bound `b` on a count of events over `full` trials, for a run of `trials`: `b` itself at
/// full scale or more; below it a quarter of the proportional bound, since a count of rare
/// events over few trials varies by far more than its share (1 pose apart in 50 trials where
/// 200 trials give 12). Compare with `>`: count > scaled_bound(...) still asks for one event at
/// least in the smallest run.
inline int scaled_bound(int b, int trials, int full) { return trials >= full ? b : b * trials / full / 4; }

}  // namespace grip_test
