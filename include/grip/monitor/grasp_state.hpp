#pragma once
/// \file
/// The state of a grasp as a stability monitor reports it: per-contact modes and margins.

#include <array>
#include <cstddef>

#include "grip/contact/cone_support.hpp"
#include "grip/contact/contact_mode.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"

namespace grip {

/// The monitor's report on one contact.
template <class Scalar>
struct ContactState {
  ContactMode mode{ContactMode::Separating};                  ///< see ContactMode
  Scalar margin{cone_margin_floor<Scalar>()};                 ///< the cone's margin (N), >= 0 inside
  Scalar relative_margin{cone_margin_floor<Scalar>()};        ///< the cone's relative margin, <= 1
  Scalar normal_force{0};                                     ///< f_n = f.a (N)
  Vector3<Scalar> tangential_force{Vector3<Scalar>::Zero()};  ///< f_t = f - f_n a (N)
  Scalar moment{0};  ///< torsional moment about a (N m): soft finger only, else 0
  /// True when the contact has a max_normal_force and f_n reaches it to the monitor's tolerance
  /// (f_n >= c - absolute_tolerance - relative_tolerance c): the finger or device channel gives
  /// all it can.
  bool at_bound{false};
};

/// The contact modes of a grasp under given forces, without margins: what
/// StabilityMonitor::classify() reports, the first part of a GraspState, and all that
/// resolve() and sticking_grasp() read. Fixed storage, no heap.
///
/// Invariant: under Status::InvalidInput, size() is 0, stable is false and the counts are 0;
/// otherwise sticking_count + sliding_count + separating_count == size().
template <class GraspT>
struct GraspModes {
  static constexpr int capacity = GraspT::capacity;  ///< most contacts reported

  /// Per-contact modes; entries [0, size()) are meaningful.
  std::array<ContactMode, detail::idx(capacity)> modes{};
  int count{0};             ///< number of contacts reported (the grasp's size())
  int sticking_count{0};    ///< contacts in ContactMode::Sticking
  int sliding_count{0};     ///< contacts in ContactMode::Sliding
  int separating_count{0};  ///< contacts in ContactMode::Separating
  /// True when status is Ok, there is at least one contact and every contact sticks: the
  /// paper's conditions 4 and 5 hold at every contact.
  bool stable{false};
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput (see StabilityMonitor)

  /// Number of contacts reported.
  int size() const { return count; }
  /// The mode of contact i. Precondition (GRIP_ASSERT): 0 <= i < size().
  ContactMode mode(int i) const {
    GRIP_ASSERT(i < count);
    return modes[detail::idx(i)];
  }
  /// True if contact i slides.
  bool is_sliding(int i) const { return mode(i) == ContactMode::Sliding; }
  /// True if contact i separates.
  bool is_separating(int i) const { return mode(i) == ContactMode::Separating; }
  /// True if contact i sticks.
  bool is_sticking(int i) const { return mode(i) == ContactMode::Sticking; }
  /// True when status == Status::Ok.
  bool ok() const { return status == Status::Ok; }
};

/// The monitor's full report on a whole grasp of type GraspT: the modes (GraspModes) plus,
/// per contact, margins and the parts of the force. Fixed storage, no heap.
///
/// Invariant: every number is finite; contact(i).mode == mode(i) for i < size(). Under
/// Status::InvalidInput, size() is 0, stable is false, the counts are 0 and min_margin is
/// cone_margin_floor().
template <class GraspT>
struct GraspState : GraspModes<GraspT> {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;

  /// Per-contact states; entries [0, size()) are meaningful.
  std::array<ContactState<Scalar>, detail::idx(GraspT::capacity)> contacts{};
  /// Smallest margin over the contacts (N); cone_margin_floor() when there are none.
  Scalar min_margin{cone_margin_floor<Scalar>()};
  int min_margin_index{-1};  ///< the contact with min_margin, -1 when there are none
  int at_bound_count{0};     ///< contacts with ContactState::at_bound

  /// The state of contact i. Precondition (GRIP_ASSERT): 0 <= i < size().
  const ContactState<Scalar>& contact(int i) const {
    GRIP_ASSERT(i < this->count);
    return contacts[detail::idx(i)];
  }
};

}  // namespace grip
