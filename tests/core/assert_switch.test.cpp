// core/assert.hpp's switch: which of GRIP_DISABLE_ASSERTS, GRIP_ENABLE_ASSERTS and NDEBUG wins,
// and that a compiled-out GRIP_ASSERT never evaluates its condition. The header chooses anew at
// every inclusion (as <cassert> does), so this file includes it under each setting and puts the
// build's own setting back at its end: in a unity build the files after it see the suite's choice.
// Only functions of this file (internal linkage) expand GRIP_ASSERT under the changed settings,
// so no inline function of grip is compiled two ways.
#include <doctest/doctest.h>

#include <grip/core/assert.hpp>

// The build's setting, to restore at the end.
#ifdef NDEBUG
#define ASSERT_SWITCH_HAD_NDEBUG
#endif
#ifdef GRIP_ENABLE_ASSERTS
#define ASSERT_SWITCH_HAD_ENABLE
#endif
#ifdef GRIP_DISABLE_ASSERTS
#define ASSERT_SWITCH_HAD_DISABLE
#endif
#undef NDEBUG
#undef GRIP_ENABLE_ASSERTS
#undef GRIP_DISABLE_ASSERTS

namespace assert_switch_test {

int g_failures = 0;
void record(const char*, const char*, int) { ++g_failures; }

// 1. Nothing defined: on.
#include <grip/core/assert.hpp>
static_assert(GRIP_ASSERTS_ENABLED == 1, "no switch: asserts on");
int when_default(int& evaluations) {
  GRIP_ASSERT(++evaluations < 0);
  return evaluations;
}

// 2. NDEBUG: off.
#define NDEBUG
#include <grip/core/assert.hpp>
static_assert(GRIP_ASSERTS_ENABLED == 0, "NDEBUG: asserts off");
int when_ndebug(int& evaluations) {
  GRIP_ASSERT(++evaluations < 0);
  return evaluations;
}

// 3. NDEBUG and GRIP_ENABLE_ASSERTS: on.
#define GRIP_ENABLE_ASSERTS
#include <grip/core/assert.hpp>
static_assert(GRIP_ASSERTS_ENABLED == 1, "GRIP_ENABLE_ASSERTS wins over NDEBUG");
int when_enabled(int& evaluations) {
  GRIP_ASSERT(++evaluations < 0);
  return evaluations;
}

// 4. All three: off (GRIP_DISABLE_ASSERTS wins); without NDEBUG too.
#define GRIP_DISABLE_ASSERTS
#include <grip/core/assert.hpp>
static_assert(GRIP_ASSERTS_ENABLED == 0, "GRIP_DISABLE_ASSERTS wins over everything");
#undef NDEBUG
#undef GRIP_ENABLE_ASSERTS
#include <grip/core/assert.hpp>
static_assert(GRIP_ASSERTS_ENABLED == 0, "GRIP_DISABLE_ASSERTS alone: asserts off");
int when_disabled(int& evaluations) {
  GRIP_ASSERT(++evaluations < 0);
  // Off, the condition must still compile, and the names in it count as used.
  const int only_in_assert = 3;
  GRIP_ASSERT(only_in_assert == 3);
  return evaluations;
}
#undef GRIP_DISABLE_ASSERTS

TEST_CASE("GRIP_ASSERT on (no switch, or GRIP_ENABLE_ASSERTS with NDEBUG) evaluates and reports") {
  const grip::AssertHandler previous = grip::set_assert_handler(&record);
  g_failures = 0;
  int n = 0;
  CHECK(when_default(n) == 1);
  CHECK(g_failures == 1);
  CHECK(when_enabled(n) == 2);
  CHECK(g_failures == 2);
  grip::set_assert_handler(previous);
}

TEST_CASE("GRIP_ASSERT off (NDEBUG, or GRIP_DISABLE_ASSERTS) does not evaluate its condition") {
  const grip::AssertHandler previous = grip::set_assert_handler(&record);
  g_failures = 0;
  int n = 0;
  CHECK(when_ndebug(n) == 0);
  CHECK(when_disabled(n) == 0);
  CHECK(g_failures == 0);
  grip::set_assert_handler(previous);
}

}  // namespace assert_switch_test

// Back to the build's own setting for whatever follows this file.
#ifdef ASSERT_SWITCH_HAD_NDEBUG
#define NDEBUG
#else
#undef NDEBUG
#endif
#ifdef ASSERT_SWITCH_HAD_ENABLE
#define GRIP_ENABLE_ASSERTS
#endif
#ifdef ASSERT_SWITCH_HAD_DISABLE
#define GRIP_DISABLE_ASSERTS
#endif
#undef ASSERT_SWITCH_HAD_NDEBUG
#undef ASSERT_SWITCH_HAD_ENABLE
#undef ASSERT_SWITCH_HAD_DISABLE
#include <grip/core/assert.hpp>
