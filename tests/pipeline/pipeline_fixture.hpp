#pragma once
// A hand closed on a 0.4 kg horizontal cylinder held in the air (no table unless a test adds
// one), for the pipeline tests, in float or double; sums of what the hand feels; and what
// each phalanx should feel by an independent solve of the pipeline's contacts.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>

#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/cylinder_scene.hpp>
#include <grip/pipeline/haptic_pipeline.hpp>
#include <grip/solve/solve_kkt.hpp>

#include "support/tolerance.hpp"

namespace grip_test {

template <class S>
struct HeldCylinder {
  using Isometry = Eigen::Transform<S, 3, Eigen::Isometry>;
  static constexpr double mass = 0.4, radius = 0.035, half_length = 0.06;

  grip::HapticSettings<S> settings;
  grip::CylinderScene<S> scene;
  grip::RigidBody<S> object;
  grip::WristState<S> wrist;
  grip::JointAngles<S> closed{grip::JointAngles<S>::Zero()};
  int touching = 0;

  HeldCylinder() {
    settings.hand.thumb_cmc.y() = S(-0.005);  // thumb opposing the long finger
    settings.hand.base[0].y() = S(-0.005);
    settings.contribution(grip::Finger::Thumb, grip::Phalanx::Proximal) = S(0.5);  // a firmer thumb
    settings.contribution(grip::Finger::Thumb, grip::Phalanx::Distal) = S(0.7);
    settings.stiffness.fill(S(1.5e4));
    settings.device_limit.fill(S(100));
    scene.radius = S(radius);
    scene.half_length = S(half_length);
    object.mass = S(mass);
    object.principal_inertia = grip::solid_cylinder_inertia<S>(S(mass), S(radius), S(half_length));
    object.position = grip::Vector3<S>(S(0.1), S(0.2), S(0.5));
    grip::Matrix3<S> r;  // axis (body z) along world y, palm down over it
    r.col(0) = grip::Vector3<S>::UnitZ();
    r.col(1) = grip::Vector3<S>::UnitX();
    r.col(2) = grip::Vector3<S>::UnitY();
    object.orientation = Eigen::Quaternion<S>(r);
    const S l = settings.hand.hand_length;
    const grip::Vector3<S> offset(S(0.374) * l + S(0.03), S(0), -(S(radius) + S(0.045) * l - S(0.002)));
    wrist.pose = Isometry::Identity();
    wrist.pose.translation() = object.position - offset;
    const grip::ClosedHand<S> c = grip::close_hand_in_scene<S>(scene, settings.hand, wrist.pose, object, S(0.002));
    closed = c.angles;
    touching = c.touching;
  }

  using Pipeline = grip::HapticPipeline<S, grip::CylinderScene<S>>;
  Pipeline pipeline() const { return Pipeline(settings, scene, object); }
  /// The pipeline with another frame solver.
  template <class Solver>
  grip::HapticPipeline<S, grip::CylinderScene<S>, Solver> pipeline_with() const {
    return grip::HapticPipeline<S, grip::CylinderScene<S>, Solver>(settings, scene, object);
  }
  /// The pipeline with another device policy.
  template <class Device>
  grip::HapticPipeline<S, grip::CylinderScene<S>, grip::RangeSpaceFrameSolver, Device> pipeline_with_device() const {
    return grip::HapticPipeline<S, grip::CylinderScene<S>, grip::RangeSpaceFrameSolver, Device>(settings, scene,
                                                                                                object);
  }
};

/// The round-off tolerance (support/tolerance.hpp) of a held frame's forces, in newtons: k
/// rounding errors of the scalar type, times the condition of the pipeline's last grasp
/// (grasp_condition), times the frame's force scale, |w_ext| plus the sum of |f_i| over the
/// phalanges. A moment's tolerance is this times the object's size (the largest |r_i|).
template <class S, class P>
double frame_force_tolerance(const P& pipeline, const grip::HapticFrame<S>& f, double k) {
  double scale = static_cast<double>(f.external.total().template head<3>().norm());
  for (const auto& ph : f.phalanges) scale += static_cast<double>(ph.force.norm());
  return roundoff<S>(k, grasp_condition(pipeline.grasp()), scale);
}

/// The largest distance (m) from the object's centre of mass to one of the pipeline's contacts.
template <class P>
double contact_reach(const P& pipeline) {
  double reach = 0;
  const auto& contacts = pipeline.hand_contacts();
  for (int i = 0; i < contacts.count; ++i)
    reach = std::max(reach, static_cast<double>((contacts[i].point - pipeline.object().position).norm()));
  return reach;
}

/// Sum over phalanges of the feedback forces (N, world).
template <class S>
grip::Vector3<S> total_feedback(const grip::HapticFrame<S>& f) {
  grip::Vector3<S> sum = grip::Vector3<S>::Zero();
  for (const auto& p : f.phalanges) sum += p.force;
  return sum;
}

/// Moment about the object's centre of mass of the forces the fingers apply (-feedback).
template <class S, class P>
grip::Vector3<S> finger_moment(const grip::HapticFrame<S>& f, const P& pipeline) {
  grip::Vector3<S> m = grip::Vector3<S>::Zero();
  const auto& contacts = pipeline.hand_contacts();
  for (int i = 0; i < contacts.count; ++i) {
    const auto& c = contacts.items[static_cast<std::size_t>(i)];
    const int k = grip::phalanx_index(c.finger, c.phalanx);
    m +=
        (c.point - pipeline.object().position).cross(grip::Vector3<S>(-f.phalanges[static_cast<std::size_t>(k)].force));
  }
  return m;
}

/// What each phalanx should feel, from an independent solve: the paper's KKT system
/// (solve_kkt) of the contacts the pipeline reports, with eq. 8's squeeze and the pipeline's
/// weights written out here, under the weight alone (the object at rest). With no contact
/// outside its cone, the optimum inside the cones is this one too.
template <class S, class P>
std::array<grip::Vector3<S>, grip::hand_phalanx_count> independent_feedback(const P& p,
                                                                            const grip::HapticSettings<S>& st) {
  using namespace grip;
  constexpr int max_n = P::max_contacts < 24 ? P::max_contacts : 24;  // the dense KKT system on the stack
  Grasp<Dynamic, HardFinger, S, max_n> g;
  REQUIRE(p.hand_contacts().count <= max_n);
  const auto& hc = p.hand_contacts();
  std::array<int, max_n> phalanx{};
  for (int i = 0; i < hc.count; ++i) {
    const int k = phalanx_index(hc[i].finger, hc[i].phalanx);
    const S d = st.contribution(hc[i].finger, hc[i].phalanx);
    Contact<S> c;
    c.position = hc[i].point - p.object().position;
    c.normal = hc[i].normal;
    c.friction = st.friction;
    c.squeeze = d * st.stiffness[static_cast<std::size_t>(k)] * hc[i].depth;  // s_i = d_i K_i dr_i
    c.weight = S(1) / std::max(c.squeeze, st.weight_floor);
    REQUIRE(g.add(c) == Status::Ok);
    phalanx[static_cast<std::size_t>(i)] = k;
  }
  Wrench<S> w_ext = Wrench<S>::Zero();
  w_ext(2) = -p.object().mass * S(9.81);
  const auto sol = solve_kkt(g, w_ext);
  REQUIRE(sol.status == Status::Ok);
  std::array<Vector3<S>, hand_phalanx_count> feel;
  feel.fill(Vector3<S>::Zero());  // (Eigen vectors are not zeroed by {})
  for (int i = 0; i < hc.count; ++i)
    feel[static_cast<std::size_t>(phalanx[static_cast<std::size_t>(i)])] -= sol.forces.template segment<3>(3 * i);
  return feel;
}

}  // namespace grip_test
