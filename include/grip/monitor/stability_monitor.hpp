#pragma once
/// \file
/// The friction-cone stability monitor (paper, section 5: conditions 4 and 5 are monitored,
/// not imposed): classifies each contact force of any solver as sticking, sliding or separating.

#include <cmath>
#include <cstddef>
#include <type_traits>

#include "grip/contact/exact_cone.hpp"
#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/monitor/grasp_state.hpp"

namespace grip {

/// Tolerances of a StabilityMonitor.
template <class Scalar>
struct MonitorSettings {
  /// A force counts as inside its cone when margin >= -(absolute_tolerance + relative_tolerance
  /// (|f_n| + |f_t| + |m|)) (m: soft-finger moment, else 0): solvers that put a force exactly on the cone leave round-off on either side.
  Scalar absolute_tolerance{0};                                      ///< N
  Scalar relative_tolerance{ScalarTraits<Scalar>::default_tolerance};  ///< dimensionless
};

/// Monitors the contact forces of a grasp of type GraspT against the cone policy `Cone`
/// (default: the exact cone of the grasp's model, ExactConeT<Model, Scalar>). Any cone type
/// with the interface of cone_support.hpp and `Cone::dim == GraspT::dim` fits, e.g.
/// PyramidCone<8, double> for a hard-finger grasp.
///
/// Classification of contact i with unknown x_i and normal part f_n:
/// - Separating if f_n <= 0 (a zero force too: eq. 5 asks f.a > 0);
/// - else Sliding if margin(x_i) < -(absolute_tolerance + relative_tolerance (|f_n| + |f_t| + |m|));
/// - else Sticking.
/// Cost: one Cone::measure per contact (CoulombCone: ~20 flops, one square root, one
/// division), no heap.
template <class GraspT, class Cone = ExactConeT<typename GraspT::ModelType, typename GraspT::ScalarType>>
class StabilityMonitor {
 public:
  using Scalar = typename GraspT::ScalarType;
  using ConeType = Cone;
  using State = GraspState<GraspT>;
  static_assert(Cone::dim == GraspT::dim, "the cone must act on the contact model's unknowns");
  static_assert(std::is_same<typename Cone::ScalarType, Scalar>::value, "cone and grasp scalars differ");

  StabilityMonitor() = default;
  /// A monitor with the given tolerances.
  explicit StabilityMonitor(const MonitorSettings<Scalar>& s) : settings_(s) {}

  /// The tolerances in use.
  const MonitorSettings<Scalar>& settings() const { return settings_; }

  /// The state of `grasp` under the stacked contact unknowns `forces` (grasp.unknowns() values,
  /// e.g. Solution::forces of any solver).
  /// Status InvalidInput (and the reset state documented at GraspState) when the grasp is
  /// incomplete, forces.size() != grasp.unknowns(), or a force is NaN, Inf or beyond
  /// ScalarTraits::max_magnitude; Ok otherwise.
  State evaluate(const GraspT& grasp, const typename GraspT::ForceVector& forces) const {
    State st;
    constexpr int d = GraspT::dim;
    if (!grasp.complete() || forces.size() != grasp.unknowns() || !detail::cone_input_valid(forces)) return st;
    st.count = grasp.size();
    for (int i = 0; i < grasp.size(); ++i) {
      const Cone cone = Cone::from_contact(grasp.contact(i));
      const typename Cone::Vector x = forces.template segment<d>(i * d);
      ContactState<Scalar>& cs = st.contacts[static_cast<std::size_t>(i)];
      const ConeMeasure<Scalar> m = cone.measure(x);
      cs.normal_force = m.normal_force;
      cs.tangential_force = m.tangential_force;
      cs.moment = m.moment;
      cs.margin = m.margin;
      cs.relative_margin = m.relative_margin;
      const Scalar slack = settings_.absolute_tolerance +
                           settings_.relative_tolerance * (std::abs(m.normal_force) + m.tangential_norm + std::abs(m.moment));
      if (!(cs.normal_force > Scalar(0))) {
        cs.mode = ContactMode::Separating;
        ++st.separating_count;
      } else if (cs.margin < -slack) {
        cs.mode = ContactMode::Sliding;
        ++st.sliding_count;
      } else {
        cs.mode = ContactMode::Sticking;
        ++st.sticking_count;
      }
      if (st.min_margin_index < 0 || cs.margin < st.min_margin) {
        st.min_margin = cs.margin;
        st.min_margin_index = i;
      }
    }
    st.status = Status::Ok;
    st.stable = st.count > 0 && st.sticking_count == st.count;
    return st;
  }

  /// Same as evaluate().
  State operator()(const GraspT& grasp, const typename GraspT::ForceVector& forces) const {
    return evaluate(grasp, forces);
  }

 private:
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

}  // namespace grip
