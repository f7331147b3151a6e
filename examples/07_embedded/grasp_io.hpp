#pragma once
// Plain C structs at the controller's boundary and their conversion to grip types
// (examples/07_embedded only).
#include <grip/contact/contact.hpp>
#include <grip/grasp/grasp.hpp>
#include <grip/monitor/stability_monitor.hpp>

constexpr int kGripFingers = 5;

/// One finger contact as the sensors deliver it (SI units, object frame).
struct GripContactIn {
  float position[3];  ///< m, from the object's centre of mass
  float normal[3];    ///< unit, into the object
  float friction;     ///< mu
  float squeeze;      ///< N
};

/// What one controller step produces.
struct GripStepOut {
  float force[kGripFingers][3];      ///< N, the force each finger applies on the object
  unsigned char mode[kGripFingers];  ///< grip::ContactMode per finger
  unsigned char stable;              ///< 1 when every contact sticks
  float residual;                    ///< |G f + w_ext| (N, N m)
};

/// The contacts into `grasp` (out of line, like monitor_and_store: its temporaries stay off the
/// stack of the solve).
template <class GraspT>
__attribute__((noinline)) grip::Status load_grasp(GraspT& grasp, const GripContactIn* in) {
  for (int i = 0; i < kGripFingers; ++i) {
    grip::Contact<float> c;
    c.position = grip::Vector3<float>(in[i].position[0], in[i].position[1], in[i].position[2]);
    c.normal = grip::Vector3<float>(in[i].normal[0], in[i].normal[1], in[i].normal[2]);
    c.friction = in[i].friction;
    c.squeeze = in[i].squeeze;
    if (grasp.set(i, c) != grip::Status::Ok) return grip::Status::InvalidInput;
  }
  return grip::Status::Ok;
}

inline grip::Wrench<float> load_wrench(const float* w) {
  grip::Wrench<float> r;
  for (int k = 0; k < 6; ++k) r(k) = w[k];
  return r;
}

/// Each contact's friction-cone mode (grip::monitor_grasp) and the forces into `out`. Out of
/// line: the monitor's state is then not on the stack while the solver runs (the step's
/// deepest call chain is the solve's).
template <class GraspT, class Forces>
__attribute__((noinline)) void monitor_and_store(const GraspT& grasp, const Forces& f, float residual,
                                                 GripStepOut* out) {
  const grip::GraspState<GraspT> state = grip::monitor_grasp(grasp, f);
  for (int i = 0; i < kGripFingers; ++i) {
    for (int k = 0; k < 3; ++k) out->force[i][k] = f(3 * i + k);
    out->mode[i] =
        static_cast<unsigned char>(state.status == grip::Status::Ok ? state.mode(i) : grip::ContactMode::Separating);
  }
  out->stable = state.stable ? 1 : 0;
  out->residual = residual;
}
