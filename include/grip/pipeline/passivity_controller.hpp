#pragma once
/// \file
/// PassivityController: a time-domain passivity observer and controller per device channel, run
/// on the device side at each of the device's updates, where the force it outputs is the force
/// the actuator holds until the next update. No heap, no exceptions; O(channels) per update.
///
/// Conventions per channel: `position` x (m) is the finger's position along the channel's
/// direction, `force` f (N) the force on the finger along that direction (a virtual wall at
/// x > 0 pushes back with f < 0). Over an update interval the actuator holds f_{k-1}, so the
/// energy the channel takes from the finger is exactly -f_{k-1} (x_k - x_{k-1}), whatever the
/// finger does within the interval. The observer sums it:
///
///     E_k = E_{k-1} - f_{k-1} (x_k - x_{k-1}),   E_0 = 0   (J).
///
/// A passive channel (the virtual object with its sampling, delay and quantisation, seen from
/// the finger) has E_k >= 0 at every k. When E_k < 0 the channel has given the finger energy it
/// never took: the controller then adds a damper to the wanted force f,
///
///     v = (x_k - x_{k-1}) / dt,   alpha = min(-E_k / (dt v^2), max_damping),   f <- f - alpha v,
///
/// which, were v held, dissipates -E_k over the next interval; the observer counts what it
/// really dissipates at the next update. The output is then clipped to [min_force, max_force].
/// max_damping bounds the damper: a held damper of alpha on a moving mass m updated every dt is
/// stable only for alpha < 2 m / dt, so max_damping should stay below that (half of it is a safe
/// choice). The range grows with the update rate: run the controller at the device's own rate,
/// faster than the commands arrive where the device can. The energy the controller cannot
/// dissipate within the bound or the force limits stays in E_k, and it goes on dissipating at
/// the next updates.
///
/// Source: B. Hannaford and J.-H. Ryu, "Time-domain passivity control of haptic interfaces",
/// IEEE Trans. Robot. Autom. 18(1), 2002 (the observer and the series damper); J.-H. Ryu,
/// Y. S. Kim and B. Hannaford, "Sampled- and continuous-time passivity and stability of virtual
/// environments", IEEE Trans. Robot. 20(4), 2004 (the energy of a held force from the
/// displacement, exact under zero-order hold).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "grip/core/status.hpp"

namespace grip {

/// Settings of PassivityController.
template <class Scalar>
struct PassivitySettings {
  /// The controller's largest damping (N s/m, finite and > 0): below 2 m / dt (file comment); the
  /// default suits a moving mass of 10 g or more updated at 1 kHz.
  Scalar max_damping{10};
  Scalar min_force{-std::numeric_limits<Scalar>::infinity()};  ///< the lowest output (N, < max_force)
  Scalar max_force{std::numeric_limits<Scalar>::infinity()};   ///< the highest output (N)
};

/// The passivity observer and controller of `Channels` device channels (see the file comment).
template <class Scalar, int Channels>
class PassivityController {
 public:
  /// One value per channel.
  using Values = std::array<Scalar, Channels>;

  /// A controller at rest: no energy observed, no previous update.
  explicit PassivityController(const PassivitySettings<Scalar>& settings = {}) : settings_(settings) {}

  /// One device update, `dt` seconds after the previous one (ignored at the first): the wanted
  /// `force` per channel (N) and the finger's `position` along each channel (m), both at this
  /// update. Returns Ok; or InvalidInput (every output 0, the energies kept) when dt is not
  /// finite and > 0 after the first update, a value is not finite, or the settings are out of
  /// range (max_damping finite and > 0, min_force < max_force). After a bad update the held
  /// force is 0, so the next good one observes no energy from that interval.
  Status update(Scalar dt, const Values& force, const Values& position);

  const Values& command() const { return command_; }  ///< the force to hold until the next update (N)
  const Values& energy() const { return energy_; }    ///< E_k per channel (J)
  const Values& damping() const { return damping_; }  ///< alpha of the last update (N s/m)
  /// Back to rest: no energy, no previous update.
  void reset() { *this = PassivityController(settings_); }

 private:
  PassivitySettings<Scalar> settings_;
  Values command_{};   ///< f_k, held until the next update
  Values energy_{};    ///< E_k
  Values damping_{};   ///< alpha_k
  Values position_{};  ///< x_k of the last good update
  bool started_{false};
};

// ---------------------------------------------------------------------------------------------
// Definitions.

template <class Scalar, int Channels>
Status PassivityController<Scalar, Channels>::update(Scalar dt, const Values& force, const Values& position) {
  const PassivitySettings<Scalar>& s = settings_;
  bool good = std::isfinite(s.max_damping) && s.max_damping > Scalar(0) && !std::isnan(s.min_force) &&
              !std::isnan(s.max_force) && s.min_force < s.max_force &&
              (!started_ || (std::isfinite(dt) && dt > Scalar(0)));
  for (std::size_t c = 0; c < static_cast<std::size_t>(Channels) && good; ++c)
    good = std::isfinite(force[c]) && std::isfinite(position[c]);
  if (!good) {
    command_.fill(Scalar(0));
    damping_.fill(Scalar(0));
    return Status::InvalidInput;
  }
  for (std::size_t c = 0; c < static_cast<std::size_t>(Channels); ++c) {
    Scalar f = force[c];
    Scalar alpha(0);
    if (started_) {
      const Scalar dx = position[c] - position_[c];
      energy_[c] -= command_[c] * dx;
      if (energy_[c] < Scalar(0) && dx != Scalar(0)) {
        const Scalar v = dx / dt;
        // -E / (dt v^2) = -E dt / dx^2; min() also takes an overflow to infinity to the bound.
        alpha = std::min(-energy_[c] * dt / (dx * dx), s.max_damping);
        f -= alpha * v;
      }
    }
    command_[c] = std::min(std::max(f, s.min_force), s.max_force);
    damping_[c] = alpha;
    position_[c] = position[c];
  }
  started_ = true;
  return Status::Ok;
}

}  // namespace grip
