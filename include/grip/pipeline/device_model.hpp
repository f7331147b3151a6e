#pragma once
/// \file
/// DeviceChannelModel: one device channel driving one finger, for tests and for users without
/// hardware. No heap, no exceptions.
///
/// The finger, along the channel's direction, is a mass, spring and damper (the lumped model of a
/// finger's mechanical impedance; Hajian and Howe 1997 report a few grams, a few N s/m and tens
/// to hundreds of N/m for a fingertip, growing with the grip):
///
///     m x'' = -b x' - k (x - rest) + f(t),
///
/// `rest` being where the person's muscles would hold the finger (put it inside an object to
/// model a person pressing on it). f(t) is the force the channel applies: the host sends
/// commands (send()); each reaches the device `delay` seconds after it was sent; the device
/// updates at `update_rate`, taking at each update the newest command that has arrived, rounding
/// it to its `step` and clipping it to [min_force, max_force], and holds that force until its next
/// update (zero-order hold). With `passivity`, a PassivityController (passivity_controller.hpp)
/// runs at each device update on the arrived command and the finger's position, as firmware on
/// the device would; the held force is then its output.
///
/// advance() integrates the finger to a time by the semi-implicit Euler method with a fixed
/// substep (1e-5 s by default: below a hundredth of the finger's period and of the device's update
/// period for the models here), the device's updates falling on substeps. energy() is the work the
/// channel has taken from the finger, -integral of f x' dt, summed exactly per substep from the
/// held force and the displacement.
///
/// Source of the model's structure (finger, hold, delay): J. E. Colgate and J. M. Brown,
/// "Factors affecting the Z-width of a haptic display", ICRA 1994; A. Z. Hajian and R. D. Howe,
/// "Identification of the mechanical impedance at the human finger tip", J. Biomech. Eng.
/// 119(1), 1997.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "grip/core/status.hpp"
#include "grip/pipeline/passivity_controller.hpp"

namespace grip {

/// The finger along the channel: a mass, spring and damper (see the file comment).
template <class Scalar>
struct FingerImpedance {
  Scalar mass{Scalar(0.01)};  ///< moving mass of finger and device link (kg, > 0)
  Scalar damping{2};          ///< b (N s/m, >= 0)
  Scalar stiffness{100};      ///< k (N/m, >= 0)
  Scalar rest{0};             ///< where the finger's spring holds it (m)
};

/// The device channel (see the file comment). All finite; delay >= 0, update_rate > 0, step >= 0.
template <class Scalar>
struct DeviceChannelSettings {
  Scalar delay{0};               ///< from a command's sending to its arrival at the device (s)
  Scalar update_rate{1000};      ///< device updates per second (Hz)
  Scalar step{0};                ///< the force step the device renders (N; 0: no rounding)
  Scalar min_force{-20};         ///< lowest force (N; 0 for a cable or a brake that only pulls one way)
  Scalar max_force{20};          ///< highest force (N, > min_force)
  bool passivity{false};         ///< run a PassivityController at the device's updates
  Scalar max_damping{10};        ///< its bound (N s/m; PassivitySettings::max_damping)
  Scalar substep{Scalar(1e-5)};  ///< the integration step (s, > 0)
};

/// One device channel and its finger (see the file comment). `Pending`: commands that may be in
/// flight at once (sent, not yet arrived); send() refuses more.
template <class Scalar, int Pending = 64>
class DeviceChannelModel {
 public:
  /// The finger at `position` (m) and `velocity` (m/s) at time 0, the channel at rest (force 0,
  /// no command sent). valid() tells whether the models are in range.
  DeviceChannelModel(const FingerImpedance<Scalar>& finger, const DeviceChannelSettings<Scalar>& channel,
                     Scalar position = 0, Scalar velocity = 0)
      : finger_(finger), channel_(channel), x_(position), v_(velocity), passivity_(passivity_settings(channel)) {}

  /// True when the finger and channel settings are in range (else send() and advance() answer
  /// InvalidInput and nothing moves).
  bool valid() const;

  /// The host's command `force` (N) at time `t` (s, at or after the last send; usually time()).
  /// InvalidInput, and the command dropped, when t or the force is not finite, t goes back, or
  /// Pending commands are already in flight.
  Status send(Scalar t, Scalar force);

  /// Integrates the finger and the channel to time `t` (s, >= time()). InvalidInput when t is not
  /// finite or goes back, or the models are out of range (nothing moves).
  Status advance(Scalar t);

  Scalar time() const { return t_; }           ///< the model's time (s)
  Scalar position() const { return x_; }       ///< x (m)
  Scalar velocity() const { return v_; }       ///< x' (m/s)
  Scalar applied() const { return applied_; }  ///< the force the device holds (N)
  Scalar energy() const { return energy_; }    ///< the work taken from the finger (J; file comment)
  /// The device-side controller (its observed energy and damping; at rest without `passivity`).
  const PassivityController<Scalar, 1>& passivity() const { return passivity_; }

 private:
  static PassivitySettings<Scalar> passivity_settings(const DeviceChannelSettings<Scalar>& c) {
    PassivitySettings<Scalar> p;
    p.max_damping = c.max_damping;
    p.min_force = c.min_force;
    p.max_force = c.max_force;
    return p;
  }
  /// The device's update at the current time: takes the arrived commands, renders the force.
  void device_update();

  FingerImpedance<Scalar> finger_;
  DeviceChannelSettings<Scalar> channel_;
  Scalar t_{0};
  Scalar x_{0};
  Scalar v_{0};
  Scalar applied_{0};
  Scalar arrived_{0};  ///< the newest command that has reached the device
  Scalar energy_{0};
  Scalar last_sent_{-std::numeric_limits<Scalar>::infinity()};
  long long substeps_{0};     ///< substeps made since time 0
  long long next_update_{0};  ///< the substep of the next device update
  int updates_{0};
  std::array<Scalar, static_cast<std::size_t>(Pending)> when_{};   ///< arrival times in flight
  std::array<Scalar, static_cast<std::size_t>(Pending)> force_{};  ///< their forces
  int head_{0};
  int count_{0};
  PassivityController<Scalar, 1> passivity_;
};

// ---------------------------------------------------------------------------------------------
// Definitions.

template <class Scalar, int Pending>
bool DeviceChannelModel<Scalar, Pending>::valid() const {
  const auto fin = [](Scalar v) { return std::isfinite(v); };
  const FingerImpedance<Scalar>& f = finger_;
  const DeviceChannelSettings<Scalar>& c = channel_;
  return fin(f.mass) && f.mass > Scalar(0) && fin(f.damping) && f.damping >= Scalar(0) && fin(f.stiffness) &&
         f.stiffness >= Scalar(0) && fin(f.rest) && fin(c.delay) && c.delay >= Scalar(0) && fin(c.update_rate) &&
         c.update_rate > Scalar(0) && fin(c.step) && c.step >= Scalar(0) && fin(c.min_force) && fin(c.max_force) &&
         c.min_force < c.max_force && fin(c.max_damping) && c.max_damping > Scalar(0) && fin(c.substep) &&
         c.substep > Scalar(0) && fin(x_) && fin(v_);
}

template <class Scalar, int Pending>
Status DeviceChannelModel<Scalar, Pending>::send(Scalar t, Scalar force) {
  if (!valid() || !std::isfinite(t) || !std::isfinite(force) || t < last_sent_ || count_ >= Pending)
    return Status::InvalidInput;
  const int slot = (head_ + count_) % Pending;
  when_[static_cast<std::size_t>(slot)] = t + channel_.delay;
  force_[static_cast<std::size_t>(slot)] = force;
  ++count_;
  last_sent_ = t;
  return Status::Ok;
}

template <class Scalar, int Pending>
void DeviceChannelModel<Scalar, Pending>::device_update() {
  // A command counts as arrived at the update at or after its arrival time, to a part in 1e6 of
  // a substep (arrival times on the update grid must not miss it by rounding).
  const Scalar slack = Scalar(1e-6) * channel_.substep;
  while (count_ > 0 && when_[static_cast<std::size_t>(head_)] <= t_ + slack) {
    arrived_ = force_[static_cast<std::size_t>(head_)];
    head_ = (head_ + 1) % Pending;
    --count_;
  }
  Scalar f = arrived_;
  if (channel_.step > Scalar(0)) f = channel_.step * std::round(f / channel_.step);
  f = std::min(std::max(f, channel_.min_force), channel_.max_force);
  if (channel_.passivity) {
    const Scalar dt = Scalar(1) / channel_.update_rate;
    (void)passivity_.update(dt, {f}, {x_});  // in range: checked by valid(), x finite
    f = passivity_.command()[0];
  }
  applied_ = f;
  ++updates_;
}

template <class Scalar, int Pending>
Status DeviceChannelModel<Scalar, Pending>::advance(Scalar t) {
  if (!valid() || !std::isfinite(t) || t < t_) return Status::InvalidInput;
  const Scalar h = channel_.substep;
  const Scalar per_update = Scalar(1) / (channel_.update_rate * h);  // substeps per device update
  const FingerImpedance<Scalar>& f = finger_;
  // Substeps whose start lies before t (to a part in 1e6 of a substep).
  const auto target = static_cast<long long>(std::floor(t / h + Scalar(1e-6)));
  while (substeps_ < target) {
    if (substeps_ >= next_update_) {
      device_update();
      next_update_ = static_cast<long long>(std::ceil(Scalar(updates_) * per_update - Scalar(1e-6)));
    }
    const Scalar a = (applied_ - f.damping * v_ - f.stiffness * (x_ - f.rest)) / f.mass;
    v_ += h * a;
    const Scalar dx = h * v_;
    x_ += dx;
    energy_ -= applied_ * dx;
    ++substeps_;
    t_ = Scalar(substeps_) * h;
  }
  return Status::Ok;
}

}  // namespace grip
