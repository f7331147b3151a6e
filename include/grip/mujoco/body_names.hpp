#pragma once
/// \file
/// The names of grip's hand in MuJoCo: its bodies and joints as hand_mjcf() writes them, and
/// the entries of a body map (body_map.hpp). Text only, no MuJoCo call. Part of grip::mujoco.

#include <array>

#include "grip/core/index.hpp"
#include "grip/hand/hand_joints.hpp"
#include "grip/hand/hand_model.hpp"

namespace grip {
namespace mujoco {

/// One entry of a body map: a MuJoCo body's name and the grip body it stands for, an index in
/// [0, hand_body_count) (phalanx_index(Finger, Phalanx) gives it).
struct BodyName {
  const char* name{nullptr};  ///< The body's name in the model (mjOBJ_BODY).
  int body{-1};               ///< grip body index, order of hand_model.hpp.
};

/// The name grip gives its body k in [0, hand_body_count) when it writes its hand as MJCF
/// (hand_mjcf.hpp): "thumb_proximal", "thumb_distal", "index_proximal", ..., "little_distal",
/// then "thumb_metacarpal", ..., "little_metacarpal". nullptr outside the range.
constexpr const char* hand_body_name(int k) {
  constexpr const char* names[hand_body_count] = {
      "thumb_proximal",   "thumb_distal",    "index_proximal",  "index_middle",     "index_distal",
      "long_proximal",    "long_middle",     "long_distal",     "ring_proximal",    "ring_middle",
      "ring_distal",      "little_proximal", "little_middle",   "little_distal",    "thumb_metacarpal",
      "index_metacarpal", "long_metacarpal", "ring_metacarpal", "little_metacarpal"};
  return k >= 0 && k < hand_body_count ? names[k] : nullptr;
}

/// The ready map of grip's own hand as hand_mjcf() writes it: body k named hand_body_name(k).
/// The names live as long as the program (string literals).
inline std::array<BodyName, hand_body_count> grip_hand_body_names() {
  std::array<BodyName, hand_body_count> out{};
  for (int k = 0; k < hand_body_count; ++k) out[detail::idx(k)] = BodyName{hand_body_name(k), k};
  return out;
}

/// The name grip gives joint i in [0, hand_dof_count) (order of hand_joints.hpp):
/// "thumb_cmc_flexion", "thumb_cmc_abduction", "thumb_mcp", "thumb_ip", then per finger
/// "<finger>_abduction", "_mcp", "_pip", "_dip" (index, long, ring, little). nullptr outside.
constexpr const char* hand_joint_name(int i) {
  constexpr const char* names[hand_dof_count] = {"thumb_cmc_flexion", "thumb_cmc_abduction",
                                                 "thumb_mcp",         "thumb_ip",
                                                 "index_abduction",   "index_mcp",
                                                 "index_pip",         "index_dip",
                                                 "long_abduction",    "long_mcp",
                                                 "long_pip",          "long_dip",
                                                 "ring_abduction",    "ring_mcp",
                                                 "ring_pip",          "ring_dip",
                                                 "little_abduction",  "little_mcp",
                                                 "little_pip",        "little_dip"};
  return i >= 0 && i < hand_dof_count ? names[i] : nullptr;
}

}  // namespace mujoco
}  // namespace grip
