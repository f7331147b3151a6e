#pragma once
/// \file
/// ChannelGuard: what stands between a device policy's command (device_policy.hpp) and the
/// hardware, channel by channel. It holds the command between the device's updates, limits its
/// slew, ramps a channel in at contact onset, takes every command to zero when the input goes
/// stale or is bad, and rounds to the device's steps with the rounding error carried over. No
/// heap, no exceptions; O(channels) per call.
///
/// Each call update(now, wanted, fresh) at time `now` (s, not decreasing) does, in order:
/// 1. Input. `wanted` is bad when a value is not finite or |wanted_c| > max_command, or when
///    `now` is not finite or goes back: every target is then 0 and the status InvalidInput.
///    With `fresh` false (no new glove or tracker data this frame) the targets stay the last
///    good ones; after stale_after seconds without fresh data every target is 0 (stale()).
/// 2. Hold. Between the device's updates (a call at least 1 / update_rate s after the last
///    update, the first call being one) the command is held: update() returns at once. The
///    steps below run at an update only. A bad `now` keeps the last good time, so the command
///    holds until a good time comes.
/// 3. Onset. A channel whose target leaves 0 starts its onset: for onset_time seconds its
///    target is scaled by the time since then over onset_time (a ramp from 0).
/// 4. Slew. The exact command c moves toward the target by at most slew_rate times the time
///    since the last update. A target of 0 (stale, bad input) is therefore reached without a
///    jump, in at most |c| / slew_rate seconds.
/// 5. Steps. With step > 0 the rendered command is c plus the carried rounding error, rounded
///    to a multiple of step; the new error is carried to the next update (first-order noise
///    shaping: the rendered mean follows c, and each rendered value is within step of c).
///
/// Bounds that hold exactly, on the exact command c (command_exact()): |c(t_k) - c(t_k-1)| <=
/// slew_rate (t_k - t_k-1) between updates (no change at the first update); from rest,
/// |c(t)| <= |target| (t - t0) / onset_time during an onset begun at t0; c is held between
/// updates; with stale or bad input |c| falls by slew_rate per second to 0. The rendered
/// command() differs from c by at most step.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "grip/core/index.hpp"
#include "grip/core/status.hpp"

namespace grip {

/// Settings of ChannelGuard. Reals must be finite where stated, or update() answers
/// InvalidInput with zero commands.
template <class Scalar>
struct ChannelGuardSettings {
  Scalar update_rate{200};  ///< device updates per second (Hz, > 0, finite)
  Scalar step{0};           ///< the device's command step (command units, >= 0; 0: no rounding)
  Scalar slew_rate{std::numeric_limits<Scalar>::infinity()};    ///< largest change per second (units/s, > 0)
  Scalar onset_time{0};                                         ///< ramp-in time at contact onset (s, >= 0)
  Scalar stale_after{std::numeric_limits<Scalar>::infinity()};  ///< input age that zeroes the targets (s, > 0)
  Scalar max_command{std::numeric_limits<Scalar>::infinity()};  ///< larger |wanted| is bad input (units, > 0)
};

/// A member of ChannelGuardSettings outside its range: its name and its range, or both nullptr.
struct InvalidMember {
  const char* member{nullptr};  ///< e.g. "update_rate"; nullptr when every member is in range
  const char* range{nullptr};   ///< e.g. "finite and > 0"
};

/// The first member of `s` outside its range (see ChannelGuardSettings), or {} when none is.
template <class Scalar>
InvalidMember invalid_member(const ChannelGuardSettings<Scalar>& s) {
  if (!(std::isfinite(s.update_rate) && s.update_rate > Scalar(0))) return {"update_rate", "finite and > 0"};
  if (!(std::isfinite(s.step) && s.step >= Scalar(0))) return {"step", "finite and >= 0"};
  if (!(s.slew_rate > Scalar(0))) return {"slew_rate", "> 0 (inf: no limit)"};
  if (!(std::isfinite(s.onset_time) && s.onset_time >= Scalar(0))) return {"onset_time", "finite and >= 0"};
  if (!(s.stale_after > Scalar(0))) return {"stale_after", "> 0 (inf: no watchdog)"};
  if (!(s.max_command > Scalar(0))) return {"max_command", "> 0 (inf: no bound)"};
  return {};
}

/// The guard of `Channels` command channels (see the file comment).
template <class Scalar, int Channels>
class ChannelGuard {
 public:
  /// One command per channel (the device's units, e.g. N).
  using Commands = std::array<Scalar, Channels>;

  /// A guard at rest (commands 0) with `settings`, checked at each update().
  explicit ChannelGuard(const ChannelGuardSettings<Scalar>& settings = {}) : settings_(settings) {}

  /// One frame at time `now` (s); see the file comment. Returns Ok, or InvalidInput for bad
  /// input or settings (targets 0; with bad settings the commands are zeroed at once).
  Status update(Scalar now, const Commands& wanted, bool fresh);
  /// A frame at time `now` whose input was bad (the caller's own check failed): update() with
  /// every target 0; returns InvalidInput (or that of a bad `now` or bad settings).
  Status reject(Scalar now) {
    Commands bad;
    bad.fill(std::numeric_limits<Scalar>::quiet_NaN());
    return update(now, bad, true);
  }

  const Commands& command() const { return rendered_; }     ///< what the device renders
  const Commands& command_exact() const { return exact_; }  ///< before rounding to steps
  bool stale() const { return stale_; }                     ///< the last update found the input stale
  /// Returns every channel to rest (commands 0, no onset, no carried error, no time).
  void reset() { *this = ChannelGuard(settings_); }

 private:
  bool settings_ok() const;

  ChannelGuardSettings<Scalar> settings_;
  Commands target_{};                    ///< the last good wanted commands
  Commands exact_{};                     ///< c, the slew-limited command
  Commands rendered_{};                  ///< c rounded to steps, with the carried error
  Commands carry_{};                     ///< the rounding error carried to the next update
  Commands onset_at_{};                  ///< when each channel's onset began (s)
  std::array<bool, Channels> active_{};  ///< the channel's target was nonzero at the last update
  Scalar last_fresh_{0};                 ///< when fresh input came last (s)
  Scalar last_update_{0};                ///< the last device update (s)
  Scalar last_call_{0};                  ///< the last call (s)
  bool started_{false};
  bool updated_{false};  ///< a device update has happened
  bool stale_{false};
};

// ---------------------------------------------------------------------------------------------
// Definitions.

template <class Scalar, int Channels>
bool ChannelGuard<Scalar, Channels>::settings_ok() const {
  return invalid_member(settings_).member == nullptr;
}

template <class Scalar, int Channels>
Status ChannelGuard<Scalar, Channels>::update(Scalar now, const Commands& wanted, bool fresh) {
  if (!settings_ok()) {
    rendered_.fill(Scalar(0));
    exact_.fill(Scalar(0));
    return Status::InvalidInput;
  }
  if (!started_) {
    if (!std::isfinite(now)) return Status::InvalidInput;
    started_ = true;
    last_fresh_ = last_update_ = last_call_ = now;
  }
  const bool time_ok = std::isfinite(now) && now >= last_call_;
  if (time_ok) last_call_ = now;
  bool good = time_ok;
  for (int c = 0; c < Channels && good; ++c)
    good = std::isfinite(wanted[detail::idx(c)]) && std::abs(wanted[detail::idx(c)]) <= settings_.max_command;
  const Scalar t = last_call_;  // a bad time keeps the last good one
  if (good && fresh) {
    target_ = wanted;
    last_fresh_ = t;
  }
  stale_ = t - last_fresh_ > settings_.stale_after;
  if (!good || stale_) target_.fill(Scalar(0));
  const Status status = good ? Status::Ok : Status::InvalidInput;
  // Held between the device's updates; the first call is an update. An update is due once a
  // period has passed, less a millionth of it or the clock's rounding (8 units in the last
  // place of t), so that a loop's rounded clock skips none.
  const Scalar since = t - last_update_;
  const Scalar period = Scalar(1) / settings_.update_rate;
  const Scalar rounding = Scalar(8) * std::numeric_limits<Scalar>::epsilon() * std::abs(t);
  if (updated_ && since < period - std::max(Scalar(1e-6) * period, rounding)) return status;
  updated_ = true;
  last_update_ = t;
  // The slew allowance of this update: none at the first (no interval yet), unlimited for an
  // infinite slew_rate.
  const Scalar reach =
      std::isfinite(settings_.slew_rate) ? settings_.slew_rate * since : std::numeric_limits<Scalar>::infinity();
  for (int c = 0; c < Channels; ++c) {
    const auto i = detail::idx(c);
    Scalar goal = target_[i];
    if (goal != Scalar(0) && !active_[i]) onset_at_[i] = t;
    active_[i] = goal != Scalar(0);
    if (active_[i] && settings_.onset_time > Scalar(0)) {
      const Scalar f = (t - onset_at_[i]) / settings_.onset_time;
      if (f < Scalar(1)) goal *= f;
    }
    const Scalar d = goal - exact_[i];
    exact_[i] = std::abs(d) <= reach ? goal : exact_[i] + std::copysign(reach, d);
    if (settings_.step > Scalar(0)) {
      const Scalar v = exact_[i] + carry_[i];
      rendered_[i] = settings_.step * std::round(v / settings_.step);
      carry_[i] = v - rendered_[i];
    } else {
      rendered_[i] = exact_[i];
    }
  }
  return status;
}

}  // namespace grip
