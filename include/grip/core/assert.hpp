// No #pragma once: like <cassert>, this header chooses GRIP_ASSERT anew at every inclusion, from
// the switches defined at that point (so a translation unit may include it again after
// changing them). The handler below is defined once, under its own guard.
/// \file
/// GRIP_ASSERT(cond): the check of a precondition that grip does not answer with a Status (the
/// index of an unchecked accessor such as `Grasp::contact(i)`) and of an internal invariant.
///
/// The switch, decided at each inclusion of this header, first rule that applies:
/// 1. `GRIP_DISABLE_ASSERTS` defined: off;
/// 2. `GRIP_ENABLE_ASSERTS` defined: on (also with NDEBUG);
/// 3. `NDEBUG` defined: off (release and embedded builds);
/// 4. otherwise on (debug and test builds).
/// `GRIP_ASSERTS_ENABLED` is then 1 or 0. Every translation unit of one program must make the
/// same choice (as with `assert`): grip's inline functions expand the macro where they are
/// defined.
///
/// Off, `GRIP_ASSERT(cond)` does not evaluate `cond` (it is an operand of `sizeof`, so it must
/// still compile, and the names it uses count as used): no code, no cost. On, a false `cond`
/// calls the assert handler with the condition's text, the file and the line. The default
/// handler writes `file:line: grip assertion failed: cond` to stderr and calls std::abort().
/// Neither throws nor allocates, so the check may stay on in real-time paths of a debug build.
/// `grip::set_assert_handler` installs another handler (a logger, a test's recorder, a
/// reset on a device). A handler that returns lets the caller go on past the broken
/// precondition, into what the unchecked code then does: that is for tests that check an assert
/// fires without breaking memory; in a program a handler should end it.

#ifndef GRIP_CORE_ASSERT_HPP_HANDLER
#define GRIP_CORE_ASSERT_HPP_HANDLER

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace grip {

/// What a failing GRIP_ASSERT calls: the condition as written, the file and the line.
using AssertHandler = void (*)(const char* condition, const char* file, int line);

namespace detail {

/// The installed handler; null means the default (write to stderr, abort). Constant-initialised:
/// no static-initialisation order to mind, no guard.
inline std::atomic<AssertHandler> assert_handler{nullptr};

/// The default handler: `file:line: grip assertion failed: condition` on stderr, then abort.
/// No heap, no formatted output (the line is written digit by digit).
[[noreturn]] inline void default_assert_handler(const char* condition, const char* file, int line) noexcept {
  char digits[16];
  int n = 0;
  unsigned v = line > 0 ? static_cast<unsigned>(line) : 0u;
  do {
    digits[n++] = static_cast<char>('0' + static_cast<int>(v % 10u));
    v /= 10u;
  } while (v != 0u && n < 15);
  char text[17];
  for (int k = 0; k < n; ++k) text[k] = digits[n - 1 - k];
  text[n] = '\0';
  std::fputs(file, stderr);
  std::fputc(':', stderr);
  std::fputs(text, stderr);
  std::fputs(": grip assertion failed: ", stderr);
  std::fputs(condition, stderr);
  std::fputc('\n', stderr);
  std::fflush(stderr);
  std::abort();
}

/// Called by a failing GRIP_ASSERT: the installed handler, or the default one.
inline void assert_failed(const char* condition, const char* file, int line) noexcept {
  const AssertHandler h = assert_handler.load(std::memory_order_acquire);
  if (h == nullptr) default_assert_handler(condition, file, line);
  h(condition, file, line);
}

}  // namespace detail

/// Installs `handler` for every later failing GRIP_ASSERT (of any thread) and returns the one it
/// replaces; nullptr restores the default handler (stderr and abort). Never throws.
inline AssertHandler set_assert_handler(AssertHandler handler) noexcept {
  return detail::assert_handler.exchange(handler, std::memory_order_acq_rel);
}

}  // namespace grip

#endif  // GRIP_CORE_ASSERT_HPP_HANDLER

#undef GRIP_ASSERTS_ENABLED
#undef GRIP_ASSERT

#if defined(GRIP_DISABLE_ASSERTS)
/// 1 where GRIP_ASSERT checks its condition, 0 where it is compiled out (here: GRIP_DISABLE_ASSERTS).
#define GRIP_ASSERTS_ENABLED 0
#elif defined(GRIP_ENABLE_ASSERTS)
/// 1 where GRIP_ASSERT checks its condition, 0 where it is compiled out (here: GRIP_ENABLE_ASSERTS).
#define GRIP_ASSERTS_ENABLED 1
#elif defined(NDEBUG)
/// 1 where GRIP_ASSERT checks its condition, 0 where it is compiled out (here: NDEBUG).
#define GRIP_ASSERTS_ENABLED 0
#else
/// 1 where GRIP_ASSERT checks its condition, 0 where it is compiled out (here: the default, on).
#define GRIP_ASSERTS_ENABLED 1
#endif

/// The form of GRIP_ASSERT when off: `cond` compiled, never evaluated.
#define GRIP_DETAIL_ASSERT_OFF(cond) static_cast<void>(sizeof(static_cast<bool>(cond)))
/// The form of GRIP_ASSERT when on: the handler when `cond` is false.
#define GRIP_DETAIL_ASSERT_ON(cond) \
  (static_cast<bool>(cond) ? static_cast<void>(0) : ::grip::detail::assert_failed(#cond, __FILE__, __LINE__))

#if GRIP_ASSERTS_ENABLED
/// Checks `cond` in debug and test builds (see the file comment for the switch).
#define GRIP_ASSERT(cond) GRIP_DETAIL_ASSERT_ON(cond)
#else
/// Compiled out: `cond` is not evaluated (see the file comment for the switch).
#define GRIP_ASSERT(cond) GRIP_DETAIL_ASSERT_OFF(cond)
#endif
