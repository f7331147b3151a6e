// The haptic loop from Python: grip's per-frame pipeline (contacts, squeeze, external wrench,
// the optimum inside the friction cones warm-started frame to frame, the monitor, per-phalanx
// feedback) over a cylinder scene with box obstacles, and the scripted closing of the hand.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "grasp.hpp"

namespace grip_python {
namespace {

using Scene = grip::CylinderScene<double>;
using Loop = grip::HapticPipeline<double, Scene, grip::ConstrainedFrameSolver<double>>;
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;
constexpr int phalanges = grip::hand_phalanx_count;

/// A number per phalanx: a scalar or (14,), finite and >= least.
std::array<double, phalanges> per_phalanx(const py::handle& obj, const char* name, double least) {
  const std::vector<double> v = per_contact(obj, phalanges, name, least, least > 0 ? "> 0" : ">= 0");
  std::array<double, phalanges> out{};
  for (int k = 0; k < phalanges; ++k) out[static_cast<std::size_t>(k)] = v[static_cast<std::size_t>(k)];
  return out;
}

struct FramePy {
  RowMatrix force, actuation_direction;  ///< (14, 3)
  Eigen::VectorXd actuated, command;     ///< (14,)
  std::vector<bool> in_contact, clamped, sliding;
  grip::Wrench<double> unbalanced{grip::Wrench<double>::Zero()};
  grip::Wrench<double> unrendered{grip::Wrench<double>::Zero()};
  grip::Vector3<double> unrendered_point{grip::Vector3<double>::Zero()};
  grip::Status status{grip::Status::InvalidInput}, solve_status{grip::Status::InvalidInput};
  int contacts{0}, obstacles{0}, sliding_count{0}, separating{0}, clamped_count{0}, solves{0}, iterations{0};
  bool held{false};
  double min_margin{0};
  grip::Vector3<double> object_position{grip::Vector3<double>::Zero()};
  Eigen::Matrix3d object_rotation{Eigen::Matrix3d::Identity()};
};

class PyHapticLoop {
 public:
  PyHapticLoop(Real radius_arg, Real half_length_arg, Real mass_arg, const py::handle& position,
               const py::handle& rotation, const std::vector<std::pair<py::object, py::object>>& boxes,
               const grip::HandDimensions<double>& hand, Real friction_arg, const py::handle& stiffness,
               const py::handle& device_limit, const grip::ContributionTable<double>& contribution, Real dt_arg,
               Integer max_iterations_arg, bool bound_by_device, Real obstacle_stiffness_arg, Real obstacle_damping_arg,
               bool net_wrench, const std::optional<grip::ChannelGuardSettings<double>>& guard) {
    const double radius = radius_arg.get("radius"), half_length = half_length_arg.get("half_length"),
                 mass = mass_arg.get("mass"), friction = friction_arg.get("friction"), dt = dt_arg.get("dt"),
                 obstacle_stiffness = obstacle_stiffness_arg.get("obstacle_stiffness"),
                 obstacle_damping = obstacle_damping_arg.get("obstacle_damping");
    const int max_iterations = max_iterations_arg.get("max_iterations");
    if (!(radius > 0) || !(half_length > 0) || !(mass > 0) || !std::isfinite(radius + half_length + mass))
      invalid("radius, half_length and mass must be finite and > 0");
    scene_.radius = radius;
    scene_.half_length = half_length;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const std::string box = "boxes[" + std::to_string(i) + "]";
      const auto lower = vec3(boxes[i].first, (box + " (lower corner)").c_str());
      const auto upper = vec3(boxes[i].second, (box + " (upper corner)").c_str());
      if (scene_.obstacles.add_box(lower, upper) != grip::Status::Ok)
        invalid(box + ": an obstacle box needs lower < upper and room in the scene");
    }
    grip::HapticSettings<double> s;
    s.hand = hand;
    if (!(friction >= 0) || !std::isfinite(friction)) invalid("friction must be finite and >= 0");
    s.friction = friction;
    s.stiffness = per_phalanx(stiffness, "stiffness", 1e-9);
    s.device_limit = per_phalanx(device_limit, "device_limit", 0.0);
    s.contribution = contribution;
    s.obstacle_material.stiffness = obstacle_stiffness;
    s.obstacle_material.damping = obstacle_damping;
    if (!(obstacle_stiffness >= 0) || !(obstacle_damping >= 0) || !std::isfinite(obstacle_stiffness + obstacle_damping))
      invalid("obstacle_stiffness and obstacle_damping must be finite and >= 0");
    if (!(dt > 0) || !std::isfinite(dt)) invalid("dt must be finite and > 0");
    s.dt = dt;
    s.bound_by_device = bound_by_device;
    if (guard) {
      const grip::InvalidMember bad = grip::invalid_member(*guard);
      if (bad.member != nullptr) invalid(std::string("guard.") + bad.member + " must be " + bad.range);
      s.guard_commands = true;
      s.guard = *guard;
    }
    if (max_iterations < 1) invalid("max_iterations must be >= 1, not " + std::to_string(max_iterations));
    object_.mass = mass;
    object_.principal_inertia = grip::solid_cylinder_inertia<double>(mass, radius, half_length);
    object_.position = vec3(position, "position");
    const Array r = numbers(rotation, "rotation");
    if (!r || r.ndim() != 2 || r.shape(0) != 3 || r.shape(1) != 3) invalid("rotation must have shape (3, 3)");
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = r.at(i, j);
    if (!m.allFinite() || !((m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9) ||
        m.determinant() < 0)
      invalid("rotation must be a rotation matrix (orthonormal to 1e-9, determinant 1)");
    object_.orientation = Eigen::Quaterniond(m);
    if (grip::validate(object_) != grip::Status::Ok) invalid("the object is invalid");
    loop_ = std::make_unique<Loop>(s, scene_, object_);
    loop_->solver().settings.max_iterations = max_iterations;
    loop_->device().net_wrench = net_wrench;
  }

  FramePy step(const py::handle& wrist, const py::handle& angles, const py::handle& v, const py::handle& w,
               const py::handle& a, const py::handle& alpha, bool fresh) {
    grip::WristState<double> ws;
    ws.pose = pose(wrist, "wrist");
    ws.linear_velocity = vec3(v, "linear_velocity");
    ws.angular_velocity = vec3(w, "angular_velocity");
    ws.linear_acceleration = vec3(a, "linear_acceleration");
    ws.angular_acceleration = vec3(alpha, "angular_acceleration");
    const grip::JointAngles<double> q = grip_python::angles(angles);
    grip::HapticFrame<double> f;
    {
      py::gil_scoped_release release;
      (void)loop_->step(ws, q, f, fresh);
    }
    FramePy out;
    out.force.resize(phalanges, 3);
    out.actuation_direction.resize(phalanges, 3);
    out.actuated.resize(phalanges);
    out.command.resize(phalanges);
    for (int k = 0; k < phalanges; ++k) {
      const auto& p = f.phalanges[static_cast<std::size_t>(k)];
      out.force.row(k) = p.force.transpose();
      out.actuation_direction.row(k) = p.actuation_direction.transpose();
      out.actuated(k) = p.actuated;
      out.command(k) = p.command;
      out.in_contact.push_back(p.in_contact);
      out.clamped.push_back(p.clamped);
      out.sliding.push_back(p.sliding);
    }
    out.unbalanced = f.unbalanced;
    out.unrendered = loop_->device_command().unrendered;
    out.unrendered_point = loop_->device_command().point;
    out.status = f.status;
    out.solve_status = f.solve_status;
    out.contacts = f.contacts;
    out.obstacles = f.obstacles;
    out.sliding_count = f.sliding;
    out.separating = f.separating;
    out.clamped_count = f.clamped;
    out.solves = f.solves;
    out.iterations = f.iterations;
    out.held = f.held;
    out.min_margin = f.min_margin;
    out.object_position = loop_->object().position;
    out.object_rotation = loop_->object().rotation();
    return out;
  }

  /// The joint angles at which the hand posed at `wrist` closes on the object (see close_hand_in_scene).
  py::tuple close_hand(const py::handle& wrist, Real depth_arg) const {
    const double depth = depth_arg.get("depth");
    if (!(depth >= 0) || !std::isfinite(depth)) invalid("depth must be finite and >= 0");
    const auto c =
        grip::close_hand_in_scene<double>(scene_, loop_->settings().hand, pose(wrist, "wrist"), loop_->object(), depth);
    return py::make_tuple(Eigen::VectorXd(c.angles), c.touching, c.status);
  }

 private:
  Scene scene_;
  grip::RigidBody<double> object_;
  std::unique_ptr<Loop> loop_;
};

/// (rows, 3) rows of finite numbers: exactly `rows` of them.
template <std::size_t N>
std::array<grip::Vector3<double>, N> fixed_rows3(const py::handle& obj, const char* name) {
  const Array a = rows3(obj, name);
  if (a.shape(0) != static_cast<py::ssize_t>(N))
    invalid(std::string(name) + " must have shape (" + std::to_string(N) + ", 3), not " + shape_of(a));
  std::array<grip::Vector3<double>, N> out{};
  for (std::size_t i = 0; i < N; ++i)
    out[i] = grip::Vector3<double>(a.at(py::ssize_t(i), 0), a.at(py::ssize_t(i), 1), a.at(py::ssize_t(i), 2));
  return out;
}

/// net_wrench_vector_command from Python: the hand's bodies' felt forces and points, which are
/// in contact, and each phalanx's limit (a scalar or (14,), N, >= 0).
grip::NetWrenchVectorCommand<double> vector_command(const py::handle& force, const py::handle& point,
                                                    const py::handle& in_contact, const py::handle& limit) {
  constexpr std::size_t bodies = grip::hand_body_count;
  const auto f = fixed_rows3<bodies>(force, "force");
  const auto p = fixed_rows3<bodies>(point, "point");
  const py::array_t<bool, py::array::c_style | py::array::forcecast> touch =
      py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(in_contact);
  if (!touch || touch.ndim() != 1 || touch.shape(0) != py::ssize_t(bodies))
    invalid("in_contact must have shape (" + std::to_string(bodies) + ",)");
  std::array<bool, bodies> t{};
  for (std::size_t i = 0; i < bodies; ++i) t[i] = touch.at(py::ssize_t(i));
  const auto c = per_phalanx(limit, "limit", 0.0);
  py::gil_scoped_release release;
  return grip::net_wrench_vector_command(f, p, t, c);
}

}  // namespace

void bind_pipeline(py::module_& m) {
  using Guard = grip::ChannelGuardSettings<double>;
  py::class_<Guard>(m, "ChannelGuardSettings",
                    "The command guard of HapticLoop(guard=...): each phalanx's command held between the device's "
                    "updates, rounded to its step, slew-limited, ramped in at contact onset, and ramped to zero when "
                    "the input is stale or bad (docs/pipeline.md).")
      .def(py::init([](double update_rate, double step, double slew_rate, double onset_time, double stale_after,
                       double max_command) {
             Guard g;
             g.update_rate = update_rate;
             g.step = step;
             g.slew_rate = slew_rate;
             g.onset_time = onset_time;
             g.stale_after = stale_after;
             g.max_command = max_command;
             return g;
           }),
           py::kw_only(), py::arg("update_rate") = Guard{}.update_rate, py::arg("step") = Guard{}.step,
           py::arg("slew_rate") = Guard{}.slew_rate, py::arg("onset_time") = Guard{}.onset_time,
           py::arg("stale_after") = Guard{}.stale_after, py::arg("max_command") = Guard{}.max_command)
      .def_readwrite("update_rate", &Guard::update_rate, "device updates per second (Hz, > 0, finite)")
      .def_readwrite("step", &Guard::step, "the device's command step (N, >= 0; 0: no rounding)")
      .def_readwrite("slew_rate", &Guard::slew_rate, "largest change of a command per second (N/s, > 0)")
      .def_readwrite("onset_time", &Guard::onset_time, "ramp-in time at contact onset (s, >= 0)")
      .def_readwrite("stale_after", &Guard::stale_after, "input age after which the commands go to zero (s, > 0)")
      .def_readwrite("max_command", &Guard::max_command, "a larger wanted command is bad input (N, > 0)");
  using Vc = grip::NetWrenchVectorCommand<double>;
  py::class_<Vc>(m, "NetWrenchVectorCommand", "The forces of 3-D force devices on the 14 phalanges (N, world).")
      .def_property_readonly(
          "force",
          [](const Vc& c) {
            RowMatrix f(phalanges, 3);
            for (int k = 0; k < phalanges; ++k) f.row(k) = c.force[static_cast<std::size_t>(k)].transpose();
            return f;
          },
          "(14, 3) each phalanx's force, |force[k]| <= limit[k] (N)")
      .def_readonly("unrendered", &Vc::unrendered,
                    "(6,) the felt net wrench the forces do not render (N; N m about `point`)")
      .def_readonly("point", &Vc::point, "(3,) the moments' reference point: the mean of the contact bodies' points")
      .def_readonly("iterations", &Vc::iterations)
      .def_readonly("status", &Vc::status);
  m.def("net_wrench_vector_command", &vector_command, py::arg("force"), py::arg("point"), py::arg("in_contact"),
        py::arg("limit"),
        "The forces within each phalanx's ball |F_k| <= limit[k] whose net wrench on the hand comes closest to "
        "that of the bodies' felt forces (force, point: (19, 3), N and m, world; in_contact (19,); limit a scalar "
        "or (14,), N), ties toward each phalanx's own force (docs/pipeline.md).");
  py::class_<FramePy>(m, "HapticFrame", "What one frame of the haptic loop computed (world frame, SI units).")
      .def_readonly("force", &FramePy::force, "(14, 3) what each phalanx feels, -f summed over its contacts (N)")
      .def_readonly("actuation_direction", &FramePy::actuation_direction, "(14, 3) unit, the device's push direction")
      .def_readonly("actuated", &FramePy::actuated, "(14,) force . actuation_direction (N)")
      .def_readonly("command", &FramePy::command,
                    "(14,) what the device renders (N): actuated clamped to [0, limit], or the push of the closest net "
                    "wrench (net_wrench); then through the guard, if any")
      .def_readonly("in_contact", &FramePy::in_contact)
      .def_readonly("clamped", &FramePy::clamped)
      .def_readonly("sliding", &FramePy::sliding)
      .def_readonly("unbalanced", &FramePy::unbalanced, "(6,) w_ext + G f' left unbalanced (zero when held)")
      .def_readonly("unrendered", &FramePy::unrendered,
                    "(6,) the felt net wrench the device's commands do not render (N; N m about unrendered_point)")
      .def_readonly("unrendered_point", &FramePy::unrendered_point,
                    "(3,) unrendered's moment point: the mean of the contact bodies' points (m)")
      .def_readonly("status", &FramePy::status)
      .def_readonly("solve_status", &FramePy::solve_status)
      .def_readonly("contacts", &FramePy::contacts)
      .def_readonly("obstacles", &FramePy::obstacles)
      .def_readonly("sliding_count", &FramePy::sliding_count)
      .def_readonly("separating", &FramePy::separating)
      .def_readonly("clamped_count", &FramePy::clamped_count)
      .def_readonly("solves", &FramePy::solves)
      .def_readonly("iterations", &FramePy::iterations)
      .def_readonly("held", &FramePy::held, "the grasp is stable: the object moves with the hand")
      .def_readonly("min_margin", &FramePy::min_margin)
      .def_readonly("object_position", &FramePy::object_position,
                    "(3,) the object's centre of mass after the frame (m)")
      .def_readonly("object_rotation", &FramePy::object_rotation, "(3, 3) body to world after the frame");
  py::class_<PyHapticLoop>(
      m, "HapticLoop",
      "grip's per-frame haptic pipeline over a solid cylinder (its axis the body's z) with box "
      "obstacles; forces by the optimum inside the exact friction cones, warm-started frame to "
      "frame (max_iterations: the bound on each solve's interior-point iterations, "
      "ConstrainedSettings' default). bound_by_device: each contact's normal force is bounded "
      "by its phalanx's device_limit shared among that phalanx's contacts, so that the forces "
      "are ones the device can render, or the grasp slips (Infeasible) when even those cannot "
      "hold the object; False: no bounds, the device clips. contribution: the phalanges' shares d "
      "(a ContributionTable, the cylindrical power grip by default); obstacle_stiffness (N/m) and "
      "obstacle_damping (N s/m) per obstacle contact point. net_wrench: the device renders the pushes whose net "
      "wrench on the hand comes closest to the felt one, not each phalanx clipped. guard: a "
      "ChannelGuardSettings to pass the commands through, or None.")
      .def(py::init<Real, Real, Real, const py::handle&, const py::handle&,
                    const std::vector<std::pair<py::object, py::object>>&, const grip::HandDimensions<double>&, Real,
                    const py::handle&, const py::handle&, const grip::ContributionTable<double>&, Real, Integer, bool,
                    Real, Real, bool, const std::optional<Guard>&>(),
           py::kw_only(), py::arg("radius") = 0.035, py::arg("half_length") = 0.06, py::arg("mass") = 0.4,
           py::arg("position"), py::arg("rotation") = Eigen::Matrix3d::Identity(),
           py::arg("boxes") = std::vector<std::pair<py::object, py::object>>{},
           py::arg("hand") = grip::HandDimensions<double>::standard(), py::arg("friction") = 0.8,
           py::arg("stiffness") = 3e4, py::arg("device_limit") = 10.0,
           py::arg("contribution") = grip::cylindrical_power_grip<double>(), py::arg("dt") = 1e-3,
           py::arg("max_iterations") = grip::ConstrainedSettings<double>{}.max_iterations,
           py::arg("bound_by_device") = grip::HapticSettings<double>{}.bound_by_device,
           py::arg("obstacle_stiffness") = 2e4, py::arg("obstacle_damping") = 50.0, py::arg("net_wrench") = false,
           py::arg("guard") = py::none())
      .def("step", &PyHapticLoop::step, py::arg("wrist"), py::arg("angles"),
           py::arg("linear_velocity") = std::vector<double>{0, 0, 0},
           py::arg("angular_velocity") = std::vector<double>{0, 0, 0},
           py::arg("linear_acceleration") = std::vector<double>{0, 0, 0},
           py::arg("angular_acceleration") = std::vector<double>{0, 0, 0}, py::arg("fresh") = true,
           "One frame: the wrist's pose (4, 4) and motion (world, m/s, m/s^2, rad/s, rad/s^2) and the 14 joint "
           "angles in; a HapticFrame out. fresh=False: the glove and tracker gave no new data (the guard's "
           "watchdog counts the input's age). The GIL is released during the frame.")
      .def("close_hand", &PyHapticLoop::close_hand, py::arg("wrist"), py::arg("depth") = 0.002,
           "(angles (14,), touching, status): the posture at which the hand posed at `wrist` closes on the object, "
           "each joint flexing from the palm outwards until a phalanx penetrates by `depth` (m).");
}

}  // namespace grip_python
