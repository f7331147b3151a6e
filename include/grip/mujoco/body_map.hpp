#pragma once
/// \file
/// Which MuJoCo body is which part of the hand: a map from body names to grip's bodies (the
/// 14 phalanges and 5 metacarpals, order of hand/hand_model.hpp), bound once to a model.
/// Part of the optional component grip::mujoco (MuJoCo's C API, 2.2 or newer).
///
/// Several MuJoCo bodies may stand for one grip body (a robot's knuckle and its proximal
/// link both as the proximal phalanx); a grip body may have none (a robot hand without a
/// thumb's middle phalanx, or without a palm). No heap.

#include <array>
#include <cstring>

#include <mujoco/mujoco.h>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/mujoco/body_names.hpp"

namespace grip {
namespace mujoco {

/// What a set-up call found wrong, beside its Status (InvalidInput for all but None).
enum class Problem {
  None,            ///< Nothing: the set-up succeeded.
  NullModel,       ///< The model (or the data) pointer is null.
  ModelNotFinite,  ///< The model's timestep is not finite and positive, or its gravity not finite.
  EmptyMap,        ///< No entry, a null entry array, or more entries than the map holds.
  NameMissing,     ///< An entry's name is null or is not a body of the model (entry()).
  BodyOutOfRange,  ///< An entry's grip body is outside [0, hand_body_count) (entry()).
  BodyTwice,       ///< An entry names a body that an earlier entry named (entry()).
  WorldBody,       ///< An entry names the world body (entry()).
  ObjectMissing,   ///< The object's name is null or is not a body of the model.
  ObjectNotFree,   ///< The object body has no free joint (exactly one joint, mjJNT_FREE).
  ObjectInHand,    ///< The object body is one of the map's bodies.
};

/// A short English name of a problem, for messages ("name missing", ...).
constexpr const char* to_string(Problem p) {
  switch (p) {
    case Problem::None: return "none";
    case Problem::NullModel: return "null model or data";
    case Problem::ModelNotFinite: return "timestep or gravity not finite";
    case Problem::EmptyMap: return "empty or oversized body map";
    case Problem::NameMissing: return "body name not in the model";
    case Problem::BodyOutOfRange: return "grip body index out of range";
    case Problem::BodyTwice: return "body named twice";
    case Problem::WorldBody: return "the world body is not a hand body";
    case Problem::ObjectMissing: return "object body not in the model";
    case Problem::ObjectNotFree: return "object body has no free joint";
    case Problem::ObjectInHand: return "object body is a hand body";
  }
  return "unknown";
}

/// A body map bound to one model: for each entry, the model's body id and its grip body.
/// Capacity 64 entries. Lookups are linear in the entries (a hand has a few dozen).
class BodyMap {
 public:
  static constexpr int capacity = 64;  ///< Most entries a map holds.

  /// Binds `count` entries to the model `m`. InvalidInput with problem() and entry() (the
  /// offending entry's index, -1 when none) on: a null model (NullModel); no entry or more than
  /// `capacity` (EmptyMap); a name that is null or not a body (NameMissing); a grip body out of
  /// range (BodyOutOfRange); the world body (WorldBody); a body named twice (BodyTwice). The map
  /// is then empty. Ok otherwise.
  Status bind(const mjModel* m, const BodyName* entries, int count);

  /// Number of bound entries (0 unless the last bind() succeeded).
  int size() const { return size_; }
  /// The problem the last bind() found (Problem::None after success).
  Problem problem() const { return problem_; }
  /// The entry the last failed bind() stopped at, or -1.
  int entry() const { return entry_; }
  /// The grip body of the model's body `mj_body`, or -1 when the map does not name it.
  int grip_body(int mj_body) const;
  /// The model's body id of entry i in [0, size()).
  int mujoco_body(int i) const { return mj_body_[detail::idx(i)]; }
  /// The root body (child of the world) of the map's bodies when they share one (the hand's
  /// base), or -1 when they have different roots.
  int root() const { return root_; }

 private:
  Status fail(Problem p, int entry) {
    size_ = 0;
    root_ = -1;
    problem_ = p;
    entry_ = entry;
    return Status::InvalidInput;
  }
  std::array<int, capacity> mj_body_{};
  std::array<int, capacity> grip_body_{};
  int size_{0};
  int root_{-1};
  Problem problem_{Problem::None};
  int entry_{-1};
};

// ---------------------------------------------------------------------------------------------

inline Status BodyMap::bind(const mjModel* m, const BodyName* entries, int count) {
  if (m == nullptr) return fail(Problem::NullModel, -1);
  if (entries == nullptr || count <= 0 || count > capacity) return fail(Problem::EmptyMap, -1);
  int root = -2;
  for (int i = 0; i < count; ++i) {
    const BodyName& e = entries[i];
    if (e.name == nullptr) return fail(Problem::NameMissing, i);
    if (e.body < 0 || e.body >= hand_body_count) return fail(Problem::BodyOutOfRange, i);
    const int id = mj_name2id(m, mjOBJ_BODY, e.name);
    if (id < 0) return fail(Problem::NameMissing, i);
    if (id == 0) return fail(Problem::WorldBody, i);
    for (int j = 0; j < i; ++j)
      if (mj_body_[detail::idx(j)] == id) return fail(Problem::BodyTwice, i);
    mj_body_[detail::idx(i)] = id;
    grip_body_[detail::idx(i)] = e.body;
    const int r = m->body_rootid[id];
    root = root == -2 ? r : (root == r ? root : -1);
  }
  size_ = count;
  root_ = root;
  problem_ = Problem::None;
  entry_ = -1;
  return Status::Ok;
}

inline int BodyMap::grip_body(int mj_body) const {
  for (int i = 0; i < size_; ++i)
    if (mj_body_[detail::idx(i)] == mj_body) return grip_body_[detail::idx(i)];
  return -1;
}

}  // namespace mujoco
}  // namespace grip
