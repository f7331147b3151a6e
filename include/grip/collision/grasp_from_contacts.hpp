#pragma once
/// \file
/// The bridge from collision to the solver: HandContacts -> Contact<Scalar> -> Grasp, with
/// the squeeze of eq. 8, s_i = d_i K_i dr_i (hand/squeeze.hpp).

#include <array>
#include <cmath>

#include "grip/contact/contact.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/collision/collision.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/hand/grasp_type.hpp"

namespace grip {

/// Per-phalanx parameters turning a HandContact into a Contact.
template <class Scalar>
struct ContactParameters {
  using Point = Vector3<Scalar>;  ///< A world point (m); lets expressions bind where a point is asked for.
  /// d_i: the grasp type's contribution table (default: the cylindrical power grip, Table 1
  /// for the fingers and grip's thumb shares; contribution_table(GraspType) gives the others).
  ContributionTable<Scalar> contribution{cylindrical_power_grip<Scalar>()};
  /// K_i (N/m) per [finger][phalanx], the fourth column the digit's metacarpal (the palm);
  /// default 1e4 N/m everywhere (so that a full-hand depth of a few millimetres asks for tens
  /// of newtons of grip; the paper leaves K_i open).
  std::array<std::array<Scalar, 4>, 5> stiffness{{{Scalar(1e4), Scalar(1e4), Scalar(1e4), Scalar(1e4)},
                                                  {Scalar(1e4), Scalar(1e4), Scalar(1e4), Scalar(1e4)},
                                                  {Scalar(1e4), Scalar(1e4), Scalar(1e4), Scalar(1e4)},
                                                  {Scalar(1e4), Scalar(1e4), Scalar(1e4), Scalar(1e4)},
                                                  {Scalar(1e4), Scalar(1e4), Scalar(1e4), Scalar(1e4)}}};
  Scalar friction{Scalar(0.8)};  ///< mu_i (dimensionless), skin on a dry object.
  Scalar torsional_friction{0};  ///< mu_t (m), for SoftFinger grasps.
  Scalar weight{1};              ///< w_i in F2.

  /// K_i of a digit's phalanx or metacarpal.
  Scalar stiffness_of(Finger f, Phalanx p) const { return stiffness[detail::idx(f)][detail::idx(p)]; }
};

/// The solver's contact for one hand contact: position r_i = point - center_of_mass (world
/// axes, m), normal a_i (into the object), friction and weight from `params`, squeeze
/// s_i = d_i K_i dr_i. Check the result with validate(Contact) (fill_grasp does).
template <class Scalar>
Contact<Scalar> to_contact(const HandContact<Scalar>& hc,
                           const typename ContactParameters<Scalar>::Point& center_of_mass,
                           const ContactParameters<Scalar>& params) {
  Contact<Scalar> c;
  c.position = hc.point - center_of_mass;
  c.normal = hc.normal;
  c.friction = params.friction;
  c.torsional_friction = params.torsional_friction;
  c.squeeze = squeeze(params.contribution(hc.finger, hc.phalanx), params.stiffness_of(hc.finger, hc.phalanx), hc.depth);
  c.weight = params.weight;
  return c;
}

/// Clears `grasp` and adds the contacts of `contacts` (in order) for an object whose centre
/// of mass is at `center_of_mass` (world, m). Statuses: InvalidInput if the centre of mass
/// is not finite, a contact fails validate(Contact) (e.g. negative stiffness or friction), or
/// there are more contacts than MaxN; the grasp then holds the contacts added before the
/// failure. Ok otherwise. Ready for solve_kkt / solve_range_space.
template <class Scalar, int PerPhalanx, class Model, int MaxN>
Status fill_grasp(const HandContacts<Scalar, PerPhalanx>& contacts,
                  const typename ContactParameters<Scalar>::Point& center_of_mass,
                  const ContactParameters<Scalar>& params, Grasp<Dynamic, Model, Scalar, MaxN>& grasp) {
  grasp.clear();
  if (!center_of_mass.allFinite()) return Status::InvalidInput;
  for (int i = 0; i < contacts.count; ++i) {
    const Status s = grasp.add(to_contact(contacts[i], center_of_mass, params));
    if (s != Status::Ok) return s;
  }
  return Status::Ok;
}

}  // namespace grip
