#pragma once
/// \file
/// A pass over contacts held in blocks of SIMD lanes (core/simd.hpp) that sums per lane
/// (namespace grip::detail). Where the contacts always fit one block (a capacity of one pack,
/// the usual small grasp), the block writes each per-lane sum instead of adding it to a cleared
/// one: the pass then neither reads nor adds its sums. Otherwise every block adds to cleared
/// sums, unless Peel.
///
/// - for_each_block<Single, Width, Peel>(blocks, body): Single (every call has at most one
///   block) compiles body(0, std::true_type) alone, called when blocks is 1. Otherwise
///   body(o, std::false_type) for o = 0, Width, ..., (blocks - 1) Width, except that with Peel
///   the block at 0 takes the first form (for a small body: a large one is kept to one form,
///   since two copies of it cost more, in instruction fetch and in compile time and memory, than
///   the sums save). Where the build optimises for size (-Os, __OPTIMIZE_SIZE__: a
///   microcontroller's flash) every block takes the second form, so the body is compiled once.
///   The caller clears its sums first in every build.
/// - lane_add<First>(sum, v): sum = v when First, sum + v otherwise.
/// - lane_add_mul<First>(sum, a, b): sum = a b when First, sum + a b (one rounding, mul_add)
///   otherwise.
/// - lane_sub_mul<First>(sum, a, b): sum = 0 - a b when First, sum - a b otherwise.
/// - GRIP_BLOCK_BODY: written after a body lambda's parameter list, inlines the body into the
///   pass where the compiler allows it (GCC, clang), as the pass's own loop body would be.
/// The values are those of sums cleared to zero and added to, but for the sign of a zero and,
/// where the compiler fuses a product into the addition that follows it, that one rounding.

#include <type_traits>

#include "grip/core/simd.hpp"

#if defined(__GNUC__) || defined(__clang__)
#define GRIP_BLOCK_BODY __attribute__((always_inline))
#else
#define GRIP_BLOCK_BODY
#endif

namespace grip {
namespace detail {

template <bool First, class P>
GRIP_ALWAYS_INLINE void lane_add(P& sum, P v) {
  if constexpr (First) {
    sum = v;
  } else {
    sum = sum + v;
  }
}

template <bool First, class P>
GRIP_ALWAYS_INLINE void lane_add_mul(P& sum, P a, P b) {
  if constexpr (First) {
    sum = a * b;
  } else {
    sum = mul_add(a, b, sum);
  }
}

template <bool First, class P>
GRIP_ALWAYS_INLINE void lane_sub_mul(P& sum, P a, P b) {
  if constexpr (First) {
    sum = P::set1(typename P::Scalar(0)) - a * b;
  } else {
    sum = sum - a * b;
  }
}

// Inlined in every build, -Os included: the pass's sums and the body's references to them then
// stay in the pass's own frame.
template <bool Single, int Width, bool Peel = false, class Body>
inline GRIP_BLOCK_BODY void for_each_block(int blocks, Body&& body) {
#if !defined(__OPTIMIZE_SIZE__)
  if constexpr (Single) {
    if (blocks > 0) body(0, std::true_type{});
  } else if constexpr (Peel) {
    if (blocks <= 0) return;
    body(0, std::true_type{});
    for (int b = 1; b < blocks; ++b) body(b * Width, std::false_type{});
  } else {
    for (int b = 0; b < blocks; ++b) body(b * Width, std::false_type{});
  }
#else
  for (int b = 0; b < blocks; ++b) body(b * Width, std::false_type{});
#endif
}

}  // namespace detail
}  // namespace grip
