#pragma once
/// \file
/// Everything in grip. Each header also compiles on its own.

#include "grip/core/scalar_traits.hpp"
#include "grip/core/status.hpp"
#include "grip/core/types.hpp"
#include "grip/core/version.hpp"
#include "grip/core/simd.hpp"

#include "grip/contact/contact.hpp"
#include "grip/contact/contact_model.hpp"
#include "grip/contact/cone_support.hpp"
#include "grip/contact/coulomb_cone.hpp"
#include "grip/contact/pyramid_cone.hpp"
#include "grip/contact/soft_finger_cone.hpp"
#include "grip/contact/normal_cone.hpp"
#include "grip/contact/exact_cone.hpp"
#include "grip/contact/contact_mode.hpp"
#include "grip/contact/coulomb_kernel.hpp"

#include "grip/grasp/grasp.hpp"
#include "grip/grasp/objective.hpp"

#include "grip/solve/solution.hpp"
#include "grip/solve/symmetric_solve.hpp"
#include "grip/solve/solve_range_space.hpp"
#include "grip/solve/solve_kkt.hpp"
#include "grip/solve/constrained_settings.hpp"
#include "grip/solve/projection_jacobian.hpp"
#include "grip/solve/coulomb_pass.hpp"
#include "grip/solve/solve_constrained.hpp"

#include "grip/monitor/grasp_state.hpp"
#include "grip/monitor/stability_monitor.hpp"
#include "grip/monitor/resolution.hpp"

#include "grip/analysis/internal_forces.hpp"
#include "grip/analysis/quality.hpp"
#include "grip/analysis/force_closure.hpp"
#include "grip/analysis/max_wrench.hpp"
#include "grip/analysis/epsilon.hpp"
#include "grip/analysis/batch.hpp"

#include "grip/hand/squeeze.hpp"
#include "grip/hand/hand_model.hpp"
#include "grip/hand/hand_kinematics.hpp"

#include "grip/geometry/shape.hpp"
#include "grip/geometry/sphere_tree.hpp"
#include "grip/geometry/spherical_octree.hpp"
#include "grip/geometry/hand_collision_model.hpp"
#include "grip/geometry/collision.hpp"
#include "grip/geometry/grasp_from_contacts.hpp"
#include "grip/geometry/hand_closure.hpp"

#include "grip/dynamics/rigid_body.hpp"
#include "grip/dynamics/penalty_contact.hpp"
#include "grip/dynamics/external_wrench.hpp"
#include "grip/dynamics/integrator.hpp"

#include "grip/pipeline/obstacle_contacts.hpp"
#include "grip/pipeline/cylinder_scene.hpp"
#include "grip/pipeline/octree_scene.hpp"
#include "grip/pipeline/frame_solver.hpp"
#include "grip/pipeline/constrained_frame_solver.hpp"
#include "grip/pipeline/haptic_pipeline.hpp"
#include "grip/pipeline/close_hand.hpp"
