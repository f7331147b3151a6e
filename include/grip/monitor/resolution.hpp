#pragma once
/// \file
/// The resolution step after monitoring (paper, section 5): what the fingers can actually
/// transmit, the wrench left unbalanced on the object, and the grasp of the contacts that
/// still stick, for re-solving.

#include <array>
#include <cstddef>

#include "grip/contact/exact_cone.hpp"
#include "grip/core/index.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/monitor/grasp_state.hpp"
#include "grip/monitor/stability_monitor.hpp"

namespace grip {

/// What the contacts transmit once slipping and separating contacts are resolved.
///
/// Invariant: every number is finite. Under InvalidInput `transmitted` is zero (of
/// grasp.unknowns() values when that is known, else empty) and the wrenches are zero.
template <class GraspT>
struct Resolution {
  /// The grasp's scalar type (float or double).
  using Scalar = typename GraspT::ScalarType;
  /// Per contact: sticking -> its force unchanged; sliding -> the projection onto its cone (the
  /// kinetic friction force the finger can transmit); separating -> 0.
  typename GraspT::ForceVector transmitted;
  /// Net wrench on the object, G x_transmitted + w_ext ([N; N m]): zero for a stable grasp under
  /// balanced forces; otherwise what accelerates the object (makes it slip or fall).
  Wrench<Scalar> unbalanced{Wrench<Scalar>::Zero()};
  /// The wrench of the transmitted forces of the non-sticking contacts only. Re-solving the
  /// sticking contacts against `w_ext + released_wrench` redistributes the load they must take.
  Wrench<Scalar> released_wrench{Wrench<Scalar>::Zero()};
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput (state not Ok, sizes differ, bad w_ext)

  /// True when status == Status::Ok.
  bool ok() const { return status == Status::Ok; }
};

/// Resolves `forces` of `grasp` given the monitor's modes of them (a GraspState or the GraspModes of
/// StabilityMonitor::classify(); same grasp, same forces)
/// and the external wrench w_ext, projecting sliding forces onto the cone policy `Cone`
/// (default: the grasp model's exact cone; use the monitor's cone). O(n), no heap.
/// InvalidInput if state is not Ok, its size differs from the grasp's, forces.size() differs
/// from grasp.unknowns(), or w_ext is invalid.
template <class GraspT, class Cone = ExactConeT<typename GraspT::ModelType, typename GraspT::ScalarType>>
Resolution<GraspT> resolve(const GraspT& grasp, const typename GraspT::ForceVector& forces,
                           const GraspModes<GraspT>& state, const Wrench<typename GraspT::ScalarType>& w_ext) {
  using S = typename GraspT::ScalarType;
  using M = typename GraspT::ModelType;
  constexpr int d = GraspT::dim;
  static_assert(Cone::dim == d, "the cone must act on the contact model's unknowns");
  Resolution<GraspT> r;
  r.transmitted.setZero(grasp.unknowns());
  if (!state.ok() || state.size() != grasp.size() || forces.size() != grasp.unknowns() || validate(w_ext) != Status::Ok)
    return r;
  Wrench<S> total = w_ext;
  for (int i = 0; i < grasp.size(); ++i) {
    const auto& c = grasp.contact(i);
    const typename Cone::Vector x = forces.template segment<d>(i * d);
    typename Cone::Vector y = Cone::Vector::Zero();
    switch (state.mode(i)) {
      case ContactMode::Sticking: y = x; break;
      case ContactMode::Sliding: y = Cone::from_contact(c).project(x); break;
      case ContactMode::Separating: break;
    }
    r.transmitted.template segment<d>(i * d) = y;
    const Wrench<S> w = M::wrench(c, typename GraspT::ContactVector(y));
    total += w;
    if (state.mode(i) != ContactMode::Sticking) r.released_wrench += w;
  }
  r.unbalanced = total;
  r.status = Status::Ok;
  return r;
}

/// The contacts of a grasp that stick, as a grasp of their own (for re-solving), with the map
/// back to the original contact indices. Fixed storage, no heap.
template <class GraspT>
struct StickingGrasp {
  /// A Dynamic grasp of the same model and scalar, bounded by the original capacity.
  using GraspType = Grasp<Dynamic, typename GraspT::ModelType, typename GraspT::ScalarType, GraspT::capacity>;
  GraspType grasp;  ///< the sticking contacts, in their original order
  /// original_index[k] is the index in the original grasp of grasp.contact(k); -1 past size().
  std::array<int, detail::idx(GraspT::capacity)> original_index{};
  Status status{Status::InvalidInput};  ///< Ok, or InvalidInput (state not Ok or of another size)

  /// True when status == Status::Ok.
  bool ok() const { return status == Status::Ok; }

  /// Writes the unknowns `sub` of the sticking grasp (e.g. a re-solve's forces) into their
  /// slots of `full` (the original grasp's unknowns); other slots are left as they are.
  /// No-op unless ok() and the sizes match.
  void scatter(const typename GraspType::ForceVector& sub, typename GraspT::ForceVector& full) const {
    constexpr int d = GraspT::dim;
    if (!ok() || sub.size() != grasp.unknowns()) return;
    for (int k = 0; k < grasp.size(); ++k) {
      const int i = original_index[detail::idx(k)];
      if ((i + 1) * d > full.size()) return;
      full.template segment<d>(i * d) = sub.template segment<d>(k * d);
    }
  }
};

/// The sticking contacts of `grasp` per `state` (the monitor's modes: GraspState or GraspModes). A typical
/// re-solve after a slip:
///     auto res = resolve(grasp, x, state, w_ext);
///     auto sub = sticking_grasp(grasp, state);
///     auto sol = solve_range_space(sub.grasp, w_ext + res.released_wrench);
///     auto x2 = res.transmitted; sub.scatter(sol.forces, x2);
template <class GraspT>
StickingGrasp<GraspT> sticking_grasp(const GraspT& grasp, const GraspModes<GraspT>& state) {
  StickingGrasp<GraspT> out;
  out.original_index.fill(-1);
  if (!state.ok() || state.size() != grasp.size()) return out;
  int k = 0;
  for (int i = 0; i < grasp.size(); ++i) {
    if (!state.is_sticking(i)) continue;
    if (out.grasp.add(grasp.contact(i)) != Status::Ok) return StickingGrasp<GraspT>{};
    out.original_index[detail::idx(k++)] = i;
  }
  out.status = Status::Ok;
  return out;
}

}  // namespace grip
