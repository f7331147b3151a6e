#pragma once
// Constants and per-scalar tolerance helpers shared by the test files.
#include <type_traits>

namespace grip_test {

constexpr double pi = 3.141592653589793;

/// A tolerance written per scalar type: `d` for double, `f` for float.
template <class S>
constexpr double tol_of(double d, double f) {
  return std::is_same<S, float>::value ? f : d;
}

}  // namespace grip_test
