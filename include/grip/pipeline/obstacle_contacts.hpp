#pragma once
/// \file
/// The obstacle contacts a scene reports to the haptic pipeline each frame.

#include <array>

#include "grip/dynamics/penalty_contact.hpp"

namespace grip {

/// Most obstacle contacts one frame may report to the pipeline.
constexpr int max_obstacle_contacts = 32;

/// The obstacle contacts of one frame, in the conventions of PenaltyContact (points from the
/// object's centre of mass, normals into the object). The pipeline fills in depth_rate from
/// the object's twist; a scene may leave it 0.
template <class Scalar>
struct ObstacleContactSet {
  std::array<PenaltyContact<Scalar>, max_obstacle_contacts> items{};  ///< items[0..count)
  int count{0};                                                       ///< <= max_obstacle_contacts
};

}  // namespace grip
