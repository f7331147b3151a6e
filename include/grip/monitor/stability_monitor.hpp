#pragma once
/// \file
/// The friction-cone stability monitor (paper, section 5: conditions 4 and 5 are monitored,
/// not imposed): classifies each contact force of any solver as sticking, sliding or separating.

#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/coulomb_kernel.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/core/index.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/monitor/grasp_state.hpp"

namespace grip {

/// Tolerances of a StabilityMonitor.
template <class Scalar>
struct MonitorSettings {
  /// A force x with normal part f_n > 0 counts as inside its cone when
  /// margin(x) >= -(absolute_tolerance + relative_tolerance f_n): solvers that put a force
  /// exactly on the cone leave round-off on either side. For the Coulomb cone this reads
  /// |f_t| <= (mu + relative_tolerance) f_n + absolute_tolerance: the friction coefficient with
  /// relative_tolerance of slack. Negative values make the monitor stricter than the cone.
  Scalar absolute_tolerance{0};                                        ///< N
  Scalar relative_tolerance{ScalarTraits<Scalar>::default_tolerance};  ///< dimensionless
};

/// Monitors the contact forces of a grasp of type GraspT against the cone policy `Cone`
/// (default: the exact cone of the grasp's model, ExactConeT<Model, Scalar>). Any cone type
/// with the interface of cone_support.hpp and `Cone::dim == GraspT::dim` fits, e.g.
/// PyramidCone<8, double> for a hard-finger grasp.
///
/// Classification of contact i with unknowns x_i and normal part f_n:
/// - Separating if f_n <= 0 (a zero force too: eq. 5 asks f.a > 0);
/// - else Sliding if Cone::slips(x_i, slack), i.e. margin(x_i) < -slack with
///   slack = absolute_tolerance + relative_tolerance f_n;
/// - else Sticking.
///
/// Two entry points with the same modes:
/// - evaluate(): the full GraspState (modes, margins, relative margins, force parts, contacts at
///   their max_normal_force, smallest margin); one Cone::measure per contact (CoulombCone: one
///   square root, one division).
/// - classify(): the modes only (GraspModes), for the per-frame decision of a real-time loop;
///   no square root or division per contact for CoulombCone and PyramidCone. For CoulombCone
///   it runs detail::classify_coulomb_grasp (contact/coulomb_kernel.hpp) on Grasp::contacts():
///   8 contacts per instruction with AVX-512, 4 with AVX2, for double where compiled in
///   (coulomb_kernel_lanes).
/// Both have an overload that writes into caller-owned storage, so that a loop keeps one
/// result object and pays no construction per frame. No heap.
template <class GraspT, class Cone = ExactConeT<typename GraspT::ModelType, typename GraspT::ScalarType>>
class StabilityMonitor {
 public:
  using Scalar = typename GraspT::ScalarType;        ///< the grasp's scalar type
  using ConeType = Cone;                             ///< the cone policy the forces are tested against
  using State = GraspState<GraspT>;                  ///< what evaluate() reports
  using Modes = GraspModes<GraspT>;                  ///< what classify() reports
  using ForceVector = typename GraspT::ForceVector;  ///< stacked contact unknowns, grasp.unknowns() values
  static_assert(Cone::dim == GraspT::dim, "the cone must act on the contact model's unknowns");
  static_assert(std::is_same<typename Cone::ScalarType, Scalar>::value, "cone and grasp scalars differ");

  StabilityMonitor() = default;
  /// A monitor with the given tolerances.
  explicit StabilityMonitor(const MonitorSettings<Scalar>& s) : settings_(s) {}

  /// The tolerances in use.
  const MonitorSettings<Scalar>& settings() const { return settings_; }

  /// Writes into `out` the state of `grasp` under the stacked contact unknowns `forces`
  /// (grasp.unknowns() values, e.g. Solution::forces of any solver); every field of `out` that
  /// GraspState documents as meaningful is overwritten.
  /// Status InvalidInput (and the reset state documented at GraspState) when the grasp is
  /// incomplete, forces.size() != grasp.unknowns(), or a force is NaN, Inf or beyond
  /// ScalarTraits::max_magnitude; Ok otherwise.
  void evaluate(const GraspT& grasp, const ForceVector& forces, State& out) const {
    out.min_margin = cone_margin_floor<Scalar>();
    out.min_margin_index = -1;
    out.at_bound_count = 0;
    if (!start(grasp, forces, out)) return;
    int counts[3] = {0, 0, 0};
    for (int i = 0; i < grasp.size(); ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = forces.template segment<GraspT::dim>(i * GraspT::dim);
      ContactState<Scalar>& cs = out.contacts[detail::idx(i)];
      const ConeMeasure<Scalar> m = cone.measure(x);
      cs.normal_force = m.normal_force;
      cs.tangential_force = m.tangential_force;
      cs.moment = m.moment;
      cs.margin = m.margin;
      cs.relative_margin = m.relative_margin;
      cs.mode = mode_of(!(m.normal_force > Scalar(0)), m.margin < -slack(m.normal_force));
      const Scalar bound = grasp.contact(i).max_normal_force;
      cs.at_bound = bound < std::numeric_limits<Scalar>::infinity() && m.normal_force >= bound - slack(bound);
      out.at_bound_count += cs.at_bound ? 1 : 0;
      out.modes[detail::idx(i)] = cs.mode;
      ++counts[static_cast<int>(cs.mode)];
      if (i == 0 || cs.margin < out.min_margin) {
        out.min_margin = cs.margin;
        out.min_margin_index = i;
      }
    }
    finish(counts, out);
  }

  /// The state of `grasp` under `forces`, by value (see the overload that writes into storage).
  State evaluate(const GraspT& grasp, const ForceVector& forces) const {
    State st;
    evaluate(grasp, forces, st);
    return st;
  }

  /// Same as evaluate().
  State operator()(const GraspT& grasp, const ForceVector& forces) const { return evaluate(grasp, forces); }

  /// Writes into `out` the modes of the contacts of `grasp` under `forces`: the same modes,
  /// counts, `stable` and status as evaluate(), without margins.
  void classify(const GraspT& grasp, const ForceVector& forces, Modes& out) const {
    if constexpr (std::is_same<Cone, CoulombCone<Scalar>>::value) {
      // Every field is written once: the verdict, or the InvalidInput state.
      if (shape_ok(grasp, forces)) {
        const detail::CoulombCounts c = detail::classify_coulomb_grasp(grasp, forces, settings_.absolute_tolerance,
                                                                       settings_.relative_tolerance, out.modes.data());
        if (c.invalid == 0) {
          out.count = grasp.size();
          const int counts[3] = {grasp.size() - c.sliding - c.separating, c.sliding, c.separating};
          finish(counts, out);
          return;
        }
      }
      invalidate(out);
    } else {
      classify_each(grasp, forces, out);
    }
  }

  /// The modes of the contacts of `grasp` under `forces`, by value.
  Modes classify(const GraspT& grasp, const ForceVector& forces) const {
    Modes m;
    classify(grasp, forces, m);
    return m;
  }

 private:
  /// classify() one contact at a time through the Cone's interface.
  void classify_each(const GraspT& grasp, const ForceVector& forces, Modes& out) const {
    if (!start(grasp, forces, out)) return;
    int sliding_count = 0, separating_count = 0;
    for (int i = 0; i < grasp.size(); ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = forces.template segment<GraspT::dim>(i * GraspT::dim);
      // Branch-free: modes of neighbouring contacts are not predictable.
      const Scalar fn = cone.normal_part(x);
      const bool separating = !(fn > Scalar(0));
      const bool sliding = cone.slips(x, slack(fn));
      out.modes[detail::idx(i)] = mode_of(separating, sliding);
      separating_count += int(separating);
      sliding_count += int(sliding & !separating);
    }
    const int counts[3] = {grasp.size() - sliding_count - separating_count, sliding_count, separating_count};
    finish(counts, out);
  }

  /// The tolerance of the slip test for a contact with normal part fn (N).
  Scalar slack(Scalar fn) const { return settings_.absolute_tolerance + settings_.relative_tolerance * fn; }

  /// Separating wins over sliding.
  static ContactMode mode_of(bool separating, bool sliding) {
    return static_cast<ContactMode>(separating ? static_cast<int>(ContactMode::Separating)
                                               : static_cast<int>(sliding) * static_cast<int>(ContactMode::Sliding));
  }

  /// Resets the modes part of `out` to the InvalidInput state; true when the input is valid
  /// (and then count = grasp.size()).
  static bool start(const GraspT& grasp, const ForceVector& forces, Modes& out) {
    invalidate(out);
    if (!shape_ok(grasp, forces) || !detail::cone_input_valid(forces)) return false;
    out.count = grasp.size();
    return true;
  }

  /// True when the grasp is complete and `forces` has its size (the values are not checked).
  static bool shape_ok(const GraspT& grasp, const ForceVector& forces) {
    return grasp.complete() && forces.size() == grasp.unknowns();
  }

  /// The InvalidInput state of the modes part of `out` (modes themselves left as they are).
  static void invalidate(Modes& out) {
    out.count = 0;
    out.sticking_count = out.sliding_count = out.separating_count = 0;
    out.stable = false;
    out.status = Status::InvalidInput;
  }

  /// Stores the counts (indexed by ContactMode) and the verdict.
  static void finish(const int (&counts)[3], Modes& out) {
    out.sticking_count = counts[static_cast<int>(ContactMode::Sticking)];
    out.sliding_count = counts[static_cast<int>(ContactMode::Sliding)];
    out.separating_count = counts[static_cast<int>(ContactMode::Separating)];
    out.status = Status::Ok;
    out.stable = out.count > 0 && out.sticking_count == out.count;
  }

  MonitorSettings<Scalar> settings_{};
};

/// StabilityMonitor<GraspT, Cone>(settings).evaluate(grasp, forces): the one-call form, with
/// the cone policy first so it can be named alone: `monitor_grasp<PyramidCone<4, double>>(g, x)`.
template <class Cone, class GraspT>
GraspState<GraspT> monitor_grasp(const GraspT& grasp, const typename GraspT::ForceVector& forces,
                                 const MonitorSettings<typename GraspT::ScalarType>& settings = {}) {
  return StabilityMonitor<GraspT, Cone>(settings).evaluate(grasp, forces);
}

/// The exact-cone monitor of the grasp's model: monitor_grasp<ExactConeT<Model, Scalar>>.
template <class GraspT>
GraspState<GraspT> monitor_grasp(const GraspT& grasp, const typename GraspT::ForceVector& forces,
                                 const MonitorSettings<typename GraspT::ScalarType>& settings = {}) {
  return StabilityMonitor<GraspT>(settings).evaluate(grasp, forces);
}

/// StabilityMonitor<GraspT, Cone>(settings).classify(grasp, forces): the modes only, cone first.
template <class Cone, class GraspT>
GraspModes<GraspT> classify_grasp(const GraspT& grasp, const typename GraspT::ForceVector& forces,
                                  const MonitorSettings<typename GraspT::ScalarType>& settings = {}) {
  return StabilityMonitor<GraspT, Cone>(settings).classify(grasp, forces);
}

/// The exact-cone classification of the grasp's model: classify_grasp<ExactConeT<Model, Scalar>>.
template <class GraspT>
GraspModes<GraspT> classify_grasp(const GraspT& grasp, const typename GraspT::ForceVector& forces,
                                  const MonitorSettings<typename GraspT::ScalarType>& settings = {}) {
  return StabilityMonitor<GraspT>(settings).classify(grasp, forces);
}

}  // namespace grip
