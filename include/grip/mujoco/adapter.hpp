#pragma once
/// \file
/// grip inside MuJoCo: after mj_forward() or mj_step(), the contacts between a hand's bodies
/// and one object body become a grip grasp, the object's state its external wrench, and a grip
/// solver's forces what each hand body should feel (FeltForces, the form the device policies
/// of pipeline/device_policy.hpp take). Part of the optional component grip::mujoco.
///
/// Classes of the contacts of the object (docs/mujoco.md):
/// - with a body of the map: a contact of the grasp, in MuJoCo's order;
/// - with another body of the hand (same root body as the map's, not in the map): ignored,
///   and counted (ignored());
/// - with anything else (a table, an obstacle, the world): an external force, MuJoCo's own
///   contact force, added to w_ext when AdapterSettings::obstacles is set.
/// Contacts that MuJoCo excludes (exclude != 0, or no constraint row) are skipped.
///
/// A grasp contact: r_i = contact point (MuJoCo's pos, midway between the surfaces) minus the
/// object's centre of mass (xipos); a_i = MuJoCo's normal, turned to point into the object;
/// mu_i = the smaller tangential coefficient (friction[0], friction[1]); mu_t = the torsional
/// one (friction[2], m) for condim 4 and 6; condim 1 gives mu_i = mu_t = 0. The grasp's
/// Model decides what is used: HardFinger ignores mu_t, FrictionlessPoint every mu. The
/// squeeze s_i = d_i K_i dr_i (eq. 8) with dr_i the penetration (-dist, at least 0) and d_i,
/// K_i, w_i of the contact's grip body from AdapterSettings::contact.
///
/// No heap, no exceptions: update() and solve() may run in a control loop.

#include <array>
#include <cmath>

#include <mujoco/mujoco.h>

#include "grip/contact/contact.hpp"
#include "grip/core/index.hpp"
#include "grip/core/status.hpp"
#include "grip/collision/grasp_from_contacts.hpp"
#include "grip/grasp/grasp.hpp"
#include "grip/mujoco/body_map.hpp"
#include "grip/mujoco/object_wrench.hpp"
#include "grip/pipeline/device_policy.hpp"

namespace grip {
namespace mujoco {

/// What the adapter adds to a grasp and to w_ext.
template <class Scalar>
struct AdapterSettings {
  ContactParameters<Scalar> contact{};  ///< d_i, K_i, w_i per grip body (friction: MuJoCo's, not these).
  bool inertial{true};                  ///< Add the object's inertial wrench (false: gravity statics).
  bool obstacles{true};                 ///< Add the contacts with bodies outside the hand to w_ext.
};

/// The adapter for a hand (a BodyMap) and one object body. MaxContacts bounds the grasp.
template <class Model = HardFinger, class Scalar = double, int MaxContacts = 64>
class Adapter {
 public:
  using GraspType = Grasp<Dynamic, Model, Scalar, MaxContacts>;  ///< The grasp update() fills.
  using ForceVector = typename GraspType::ForceVector;           ///< A solver's contact unknowns.

  /// Set-up, once per model: binds the map's `count` entries and the object's body. Statuses:
  /// InvalidInput with problem() and entry() naming what is wrong (BodyMap::bind()'s problems,
  /// and ModelNotFinite, ObjectMissing, ObjectNotFree, ObjectInHand); Ok otherwise.
  Status bind(const mjModel* m, const char* object, const BodyName* entries, int count,
              const AdapterSettings<Scalar>& settings = {});

  /// Reads `d` (after mj_forward or mj_step of the bound model): the grasp, the object's
  /// wrench and the contact counts. Statuses: InvalidInput when not bound, a pointer is null, or
  /// a contact or the wrench is not finite (the grasp then empty); OutOfRange when the hand
  /// touches the object at more than MaxContacts points (the grasp holds the first MaxContacts,
  /// dropped() counts the rest); Ok otherwise, with or without contacts.
  Status update(const mjModel* m, const mjData* d);

  /// Solves the grasp with `solver`, any callable (grasp, w_ext) -> Solution-like (forces,
  /// status): e.g. [](const auto& g, const auto& w) { return solve_constrained(g, w); }. Fills
  /// `felt` with what each grip body feels (the sum of -f_i over its contacts, at their
  /// force-weighted point; FeltForces::finish() is left to a caller with a grip posture).
  /// Returns the solver's status; with no contact, Singular and zero forces.
  template <class Solver>
  Status solve(Solver&& solver, FeltForces<Scalar>& felt);

  const GraspType& grasp() const { return grasp_; }                      ///< The last update()'s grasp.
  const ObjectWrench<Scalar>& object_wrench() const { return wrench_; }  ///< Its w_ext, by term.
  Wrench<Scalar> external_wrench() const { return wrench_.total(); }     ///< w_ext (N; N m).
  const ForceVector& forces() const { return forces_; }                  ///< The last solve()'s x.
  /// The force contact i of the grasp applies to the object (N, world), from the last solve().
  Vector3<Scalar> force_on_object(int i) const;
  int mujoco_contact(int i) const { return contact_[detail::idx(i)]; }  ///< Index in d->contact.
  int mujoco_body(int i) const { return body_[detail::idx(i)]; }        ///< The hand body's id.
  int grip_body(int i) const { return grip_body_[detail::idx(i)]; }     ///< Its grip body.
  int object() const { return object_; }                                ///< The object's body id (-1 when not bound).
  const Vector3<Scalar>& center_of_mass() const { return com_; }        ///< The object's, at update() (m, world).
  int ignored() const { return ignored_; }                              ///< Contacts with unmapped hand bodies.
  int obstacle_contacts() const { return obstacles_; }                  ///< Contacts added to w_ext.
  int dropped() const { return dropped_; }                              ///< Hand contacts beyond MaxContacts.
  const BodyMap& map() const { return map_; }                           ///< The bound map.
  Problem problem() const { return problem_; }                          ///< What the last bind() found wrong.
  int entry() const { return map_.entry(); }                            ///< The map entry it stopped at, or -1.

 private:
  Status fail(Problem p) {
    object_ = -1;
    problem_ = p;
    return Status::InvalidInput;
  }
  void reset_counts() {
    grasp_.clear();
    wrench_ = ObjectWrench<Scalar>{};
    ignored_ = obstacles_ = dropped_ = 0;
  }
  BodyMap map_{};
  AdapterSettings<Scalar> settings_{};
  GraspType grasp_{};
  ObjectWrench<Scalar> wrench_{};
  ForceVector forces_{};
  Vector3<Scalar> com_{Vector3<Scalar>::Zero()};  // the object's centre of mass at update() (world)
  std::array<int, detail::idx(MaxContacts)> contact_{};
  std::array<int, detail::idx(MaxContacts)> body_{};
  std::array<int, detail::idx(MaxContacts)> grip_body_{};
  int object_{-1};
  int dof_{-1};
  int ignored_{0}, obstacles_{0}, dropped_{0};
  Problem problem_{Problem::None};
};

// ---------------------------------------------------------------------------------------------

template <class Model, class Scalar, int MaxContacts>
Status Adapter<Model, Scalar, MaxContacts>::bind(const mjModel* m, const char* object, const BodyName* entries,
                                                 int count, const AdapterSettings<Scalar>& settings) {
  reset_counts();
  if (m == nullptr) return fail(Problem::NullModel);
  bool finite = std::isfinite(m->opt.timestep) && m->opt.timestep > 0;
  for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(m->opt.gravity[k]);
  if (!finite) return fail(Problem::ModelNotFinite);
  if (map_.bind(m, entries, count) != Status::Ok) return fail(map_.problem());
  const int id = object == nullptr ? -1 : mj_name2id(m, mjOBJ_BODY, object);
  if (id <= 0) return fail(Problem::ObjectMissing);
  if (map_.grip_body(id) >= 0) return fail(Problem::ObjectInHand);
  if (m->body_jntnum[id] != 1 || m->jnt_type[m->body_jntadr[id]] != mjJNT_FREE) return fail(Problem::ObjectNotFree);
  object_ = id;
  dof_ = m->jnt_dofadr[m->body_jntadr[id]];
  settings_ = settings;
  problem_ = Problem::None;
  return Status::Ok;
}

template <class Model, class Scalar, int MaxContacts>
Status Adapter<Model, Scalar, MaxContacts>::update(const mjModel* m, const mjData* d) {
  reset_counts();
  if (object_ < 0 || m == nullptr || d == nullptr) return Status::InvalidInput;
  using V = Vector3<double>;
  const V com(d->xipos[3 * object_], d->xipos[3 * object_ + 1], d->xipos[3 * object_ + 2]);
  if (!com.allFinite()) return Status::InvalidInput;
  ObjectWrench<Scalar> w = free_body_wrench<Scalar>(m, d, object_, dof_);
  if (!settings_.inertial) w.inertial.setZero();
  Wrench<double> obstacles = Wrench<double>::Zero();
  const int hand_root = map_.root();
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.exclude != 0 || c.efc_address < 0) continue;
    const int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
    if (b1 != object_ && b2 != object_) continue;
    const int other = b1 == object_ ? b2 : b1;
    const int k = map_.grip_body(other);
    if (k < 0) {
      if (hand_root >= 0 && other != 0 && m->body_rootid[other] == hand_root) {
        ++ignored_;
      } else if (settings_.obstacles) {
        obstacles += contact_wrench_on(m, d, i, object_, com);
        ++obstacles_;
      }
      continue;
    }
    if (grasp_.size() >= MaxContacts) {
      ++dropped_;
      continue;
    }
    // The normal points from geom1 to geom2: into the object when the object holds geom2.
    const double sign = b2 == object_ ? 1.0 : -1.0;
    const Finger f = phalanx_finger(k);
    const Phalanx p = phalanx_kind(k);
    const ContactParameters<Scalar>& cp = settings_.contact;
    Contact<Scalar> gc;
    gc.position = (V(c.pos[0], c.pos[1], c.pos[2]) - com).template cast<Scalar>();
    gc.normal = (sign * V(c.frame[0], c.frame[1], c.frame[2])).template cast<Scalar>();
    gc.friction = c.dim >= 3 ? static_cast<Scalar>(std::fmin(c.friction[0], c.friction[1])) : Scalar(0);
    gc.torsional_friction = c.dim >= 4 ? static_cast<Scalar>(c.friction[2]) : Scalar(0);
    const Scalar depth = c.dist < 0 ? static_cast<Scalar>(-c.dist) : Scalar(0);
    gc.squeeze = squeeze(cp.contribution(f, p), cp.stiffness_of(f, p), depth);
    gc.weight = cp.weight;
    const int n = grasp_.size();
    if (grasp_.add(gc) != Status::Ok) {
      reset_counts();
      return Status::InvalidInput;
    }
    contact_[detail::idx(n)] = i;
    body_[detail::idx(n)] = other;
    grip_body_[detail::idx(n)] = k;
  }
  w.obstacles = obstacles.cast<Scalar>();
  if (validate(w.total()) != Status::Ok) {
    reset_counts();
    return Status::InvalidInput;
  }
  wrench_ = w;
  com_ = com.cast<Scalar>();
  return dropped_ > 0 ? Status::OutOfRange : Status::Ok;
}

template <class Model, class Scalar, int MaxContacts>
template <class Solver>
Status Adapter<Model, Scalar, MaxContacts>::solve(Solver&& solver, FeltForces<Scalar>& felt) {
  felt = FeltForces<Scalar>{};
  if (grasp_.size() == 0) {
    forces_.resize(0);
    return Status::Singular;
  }
  const auto sol = solver(grasp_, wrench_.total());
  forces_ = sol.forces;
  for (int i = 0; i < grasp_.size(); ++i) {
    felt.add(grip_body_[detail::idx(i)], -force_on_object(i), Vector3<Scalar>(grasp_.contact(i).position + com_));
  }
  return sol.status;
}

template <class Model, class Scalar, int MaxContacts>
Vector3<Scalar> Adapter<Model, Scalar, MaxContacts>::force_on_object(int i) const {
  constexpr int dim = Model::dim;
  const typename Model::template Vector<Scalar> xi = forces_.template segment<dim>(i * dim);
  return Model::wrench(grasp_.contact(i), xi).template head<3>();
}

}  // namespace mujoco
}  // namespace grip
