#pragma once
/// \file
/// The outcome of every fallible call in grip.

namespace grip {

/// Outcome of a fallible call. Results that carry a Status always hold finite
/// numbers, whatever the status; each function documents which numbers.
enum class Status {
  Ok,              ///< Success: the result is the exact answer, to round-off or tolerance.
  InvalidInput,    ///< NaN/Inf, zero or non-unit normal, negative friction/squeeze, weight below min_weight,
                   ///< magnitude beyond ScalarTraits::max_magnitude, index or capacity exceeded.
  Singular,        ///< The grasp matrix has rank < 6: some wrench cannot be balanced at all.
  Infeasible,      ///< No forces inside the friction cones balance the wrench (the grasp slips).
  IterationLimit,  ///< An iterative solver stopped at its bound before reaching its tolerance.
  OutOfRange,      ///< An input beyond its calibrated range or a limit: the result is clamped to it.
};

/// A short English name of the status, for logs ("ok", "invalid input", ...).
constexpr const char* to_string(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::InvalidInput: return "invalid input";
    case Status::Singular: return "singular";
    case Status::Infeasible: return "infeasible";
    case Status::IterationLimit: return "iteration limit";
    case Status::OutOfRange: return "out of range";
  }
  return "unknown";
}

}  // namespace grip
