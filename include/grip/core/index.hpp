#pragma once
/// \file
/// detail::idx(i): the std::size_t subscript of a signed index (or of an enumerator). grip counts contacts, nodes,
/// triangles and phalanges in int (as Eigen's Index is signed), while std::array and built-in
/// arrays take std::size_t; idx() is the one conversion between the two, checked by
/// GRIP_ASSERT(i >= 0) where asserts are on (core/assert.hpp) and a plain cast where they are off.

#include <cstddef>
#include <type_traits>

#include "grip/core/assert.hpp"

namespace grip {
namespace detail {

/// The subscript of index `i >= 0` (int, long or another signed integer) as std::size_t, e.g.
/// `items[detail::idx(i)]`, or a size in a constant expression, `std::array<T, idx(capacity)>`.
/// Precondition (GRIP_ASSERT): i >= 0; then the same value as static_cast<std::size_t>(i). With
/// asserts on and a handler that returns, a negative i gives 0.
template <class Int, std::enable_if_t<std::is_integral<Int>::value && std::is_signed<Int>::value, int> = 0>
constexpr std::size_t idx(Int i) noexcept {
  GRIP_ASSERT(i >= 0);
#if GRIP_ASSERTS_ENABLED
  // A handler that returns lets a negative i through: it gives 0, not a subscript of 2^31 or
  // 2^63 (and g++, seeing that, does not warn of one under -Warray-bounds on 32-bit targets).
  return i < 0 ? std::size_t{0} : static_cast<std::size_t>(i);
#else
#if defined(__GNUC__)
  // The precondition, told to the optimiser: without it g++ sees a path with i < 0 and warns
  // of a subscript of 2^31 (-Warray-bounds, 32-bit targets).
  if (i < 0) __builtin_unreachable();
#endif
  return static_cast<std::size_t>(i);
#endif
}

/// The subscript of an enumerator whose underlying type is signed (a Finger, a Phalanx), e.g.
/// `per_finger[detail::idx(f)]`. Precondition (GRIP_ASSERT): its value is >= 0.
template <class Enum, std::enable_if_t<std::is_enum<Enum>::value, int> = 0>
constexpr std::size_t idx(Enum e) noexcept {
  return idx(static_cast<std::underlying_type_t<Enum>>(e));
}

}  // namespace detail
}  // namespace grip
