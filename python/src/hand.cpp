// The hand and collision from Python: hand dimensions, forward kinematics of the 14 flexion
// joints, shapes (sphere, box, cylinder, capsule and unions of up to four) with their exact
// signed distance, the contacts of a posed hand with a shape (the exact narrow phase), and the
// grasp types' contribution tables d of eq. 8; the whole hand written as MJCF for MuJoCo (text
// only: grip/mujoco/hand_mjcf.hpp calls no MuJoCo function).

#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <grip/mujoco/hand_mjcf.hpp>

#include "mesh.hpp"

namespace grip_python {
namespace {

using Dims = grip::HandDimensions<double>;
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;
using PyShape = grip::Shape<double, 4>;
using Prim = grip::ShapePrimitive<double>;
using Table = grip::ContributionTable<double>;

/// A contribution table from a (5, 3) array of shares [digit][phalanx] and the palm's share.
Table table_of(const py::handle& share, Real palm_share) {
  const Array a = numbers(share, "share");
  const double palm = palm_share.get("palm");
  if (!a || a.ndim() != 2 || a.shape(0) != 5 || a.shape(1) != 3) invalid("share must have shape (5, 3)");
  Table t{};
  for (int f = 0; f < 5; ++f)
    for (int p = 0; p < 3; ++p) {
      t.share[f][p] = a.at(f, p);
      if (!(t.share[f][p] >= 0) || !std::isfinite(t.share[f][p])) invalid("shares must be finite and >= 0");
    }
  if (t.share[0][1] != 0) invalid("the thumb has no middle phalanx: share[0, 1] must be 0");
  if (!(palm >= 0) || !std::isfinite(palm)) invalid("palm must be finite and >= 0");
  t.palm = palm;
  return t;
}

grip::Finger finger_of(int f) {
  if (f < 0 || f > 4) invalid("finger must be 0 (thumb) to 4 (little), not " + std::to_string(f));
  return static_cast<grip::Finger>(f);
}

/// A (3, 3) rotation, the identity for None (validate() checks it).
Eigen::Matrix3d rotation(const py::handle& obj) {
  if (obj.is_none()) return Eigen::Matrix3d::Identity();
  const Array a = numbers(obj, "rotation");
  if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) invalid("rotation must have shape (3, 3)");
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = a.at(i, j);
  return r;
}

Prim checked(const Prim& p, const char* what) {
  if (grip::validate(p) != grip::Status::Ok)
    invalid(std::string("invalid ") + what + ": sizes must be finite and > 0, the rotation orthonormal (to 1e-3)");
  return p;
}

RowMatrix rows(const std::array<grip::Vector3<double>, 5>& v) {
  RowMatrix m(5, 3);
  for (int f = 0; f < 5; ++f) m.row(f) = v[static_cast<std::size_t>(f)].transpose();
  return m;
}

/// The posture of the paper's hand (14 angles) or of the whole hand (20 joints), by q's length.
grip::HandPosture<double> posture(const Dims& dims, const py::handle& wrist, const py::handle& q) {
  grip::HandPosture<double> out;
  const Array a = numbers(q, "angles");
  const bool whole = a && a.ndim() == 1 && a.shape(0) == grip::hand_dof_count;
  const grip::Status st = whole ? grip::forward_kinematics(dims, pose(wrist, "wrist"), joints(q), out)
                                : grip::forward_kinematics(dims, pose(wrist, "wrist"), angles(q), out);
  if (st != grip::Status::Ok) invalid("the hand dimensions are invalid");
  return out;
}

py::dict capsules(const grip::HandPosture<double>& p) {
  const int n = p.bodies == grip::all_hand_bodies ? grip::hand_body_count : grip::hand_phalanx_count;
  RowMatrix base(n, 3), tip(n, 3), axis(grip::hand_dof_count, 3), point(grip::hand_dof_count, 3);
  Eigen::VectorXd radius(n);
  for (int k = 0; k < n; ++k) {
    const auto& c = p.phalanges[static_cast<std::size_t>(k)];
    base.row(k) = c.base.transpose();
    tip.row(k) = c.tip.transpose();
    radius(k) = c.radius;
  }
  for (int i = 0; i < grip::hand_dof_count; ++i) {
    axis.row(i) = p.joints[static_cast<std::size_t>(i)].axis.transpose();
    point.row(i) = p.joints[static_cast<std::size_t>(i)].point.transpose();
  }
  py::dict d;
  d["base"] = base;
  d["tip"] = tip;
  d["radius"] = radius;
  d["joint_axis"] = axis;
  d["joint_point"] = point;
  return d;
}

/// The contacts of the posed `model` with `field` placed by `object`: by the octree's broad
/// phase when one is given, else directly (every sample in reach of the field's box).
template <int PerPhalanx, class Field>
py::dict contacts_of(const grip::HandCollisionModel<double, 8>& model, const Field& field, const Octree* octree,
                     const Iso& object) {
  grip::HandContacts<double, PerPhalanx> out;
  const grip::Status st = octree != nullptr ? grip::detect_contacts(model, *octree, field, object, out)
                                            : grip::detect_contacts_direct(model, field, object, out);
  const int m = out.count;
  Eigen::VectorXi phalanx(m), sample(m);
  Eigen::VectorXd depth(m), along(m);
  RowMatrix point(m, 3), normal(m, 3);
  for (int i = 0; i < m; ++i) {
    const auto& c = out.items[static_cast<std::size_t>(i)];
    phalanx(i) = grip::phalanx_index(c.finger, c.phalanx);
    sample(i) = c.sample;
    depth(i) = c.depth;
    along(i) = c.axis_parameter;
    point.row(i) = c.point.transpose();
    normal.row(i) = c.normal.transpose();
  }
  py::dict d;
  d["phalanx"] = phalanx;
  d["point"] = point;
  d["normal"] = normal;
  d["depth"] = depth;
  d["sample"] = sample;
  d["axis_parameter"] = along;
  d["status"] = st;
  return d;
}

template <class Field>
py::dict contacts_with(const grip::HandCollisionModel<double, 8>& model, const Field& field, const Octree* octree,
                       const Iso& object, int per_phalanx) {
  switch (per_phalanx) {
    case 1: return contacts_of<1>(model, field, octree, object);
    case 2: return contacts_of<2>(model, field, octree, object);
    case 4: return contacts_of<4>(model, field, octree, object);
    default: invalid("per_phalanx must be 1, 2 or 4, not " + std::to_string(per_phalanx));
  }
}

/// The options of grip::mujoco::hand_mjcf() from Python, each checked here so that the
/// ValueError names the one that is wrong (the library answers InvalidInput for all).
struct MjcfArgs {
  const Dims* dims;
  std::string prefix;
  py::handle wrist;
  bool mocap;
  Real servo_gain, timestep, friction;
  Integer condim;
  std::string worldbody, extra, model;
  Real palm_mass, joint_damping, armature, density, torsional_friction;
};

void mjcf_name(const std::string& s, const char* name) {
  if (!grip::mujoco::detail::mjcf_name_ok(s))
    invalid(std::string(name) + " may hold only the characters A-Z a-z 0-9 _ - ., not \"" + s + "\"");
}

double mjcf_real(const Real& x, const char* name, bool positive) {
  const double v = x.get(name);
  if (!std::isfinite(v) || (positive ? !(v > 0) : !(v >= 0)))
    invalid(std::string(name) + " must be finite and " + (positive ? "> 0" : ">= 0") + ", not " + std::to_string(v));
  return v;
}

std::string hand_mjcf_of(const MjcfArgs& a) {
  const Dims dims = a.dims ? *a.dims : Dims::standard();
  if (grip::validate(dims) != grip::Status::Ok) invalid("dims are invalid (grip's checks of HandDimensions fail)");
  grip::mujoco::HandMjcf o;
  mjcf_name(a.prefix, "prefix");
  mjcf_name(a.model, "model");
  o.prefix = a.prefix;
  o.model = a.model;
  if (!a.wrist.is_none()) {
    const grip::Isometry3<double> w = pose(a.wrist, "wrist");
    const Eigen::Matrix3d r = w.linear();
    if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9) || !(r.determinant() > 0))
      invalid("wrist must be a proper rigid motion: its rotation orthonormal to 1e-9, determinant +1");
    o.wrist = Iso::Identity();
    o.wrist.linear() = r;
    o.wrist.translation() = w.translation();
  }
  o.mocap = a.mocap;
  o.servo_gain = mjcf_real(a.servo_gain, "servo_gain", false);
  o.timestep = mjcf_real(a.timestep, "timestep", true);
  o.friction = mjcf_real(a.friction, "friction", false);
  o.torsional_friction = mjcf_real(a.torsional_friction, "torsional_friction", false);
  o.palm_mass = mjcf_real(a.palm_mass, "palm_mass", true);
  o.joint_damping = mjcf_real(a.joint_damping, "joint_damping", false);
  o.armature = mjcf_real(a.armature, "armature", false);
  o.density = mjcf_real(a.density, "density", true);
  o.condim = a.condim.get("condim");
  if (o.condim != 1 && o.condim != 3 && o.condim != 4 && o.condim != 6)
    invalid("condim must be 1, 3, 4 or 6, not " + std::to_string(o.condim));
  o.worldbody = a.worldbody;
  o.extra = a.extra;
  std::string out;
  if (grip::mujoco::hand_mjcf(dims, o, out) != grip::Status::Ok) invalid("hand_mjcf refused its options");
  return out;
}

}  // namespace

void bind_hand(py::module_& m) {
  py::enum_<grip::GraspType>(m, "GraspType", "A grasp type, with its contribution table (docs/hand.md).")
      .value("CylindricalPower", grip::GraspType::CylindricalPower, "the whole hand round a cylinder (Table 1)")
      .value("SphericalPower", grip::GraspType::SphericalPower, "the whole hand round a ball, the palm under it")
      .value("TipPinch", grip::GraspType::TipPinch, "the thumb's and the index's distal pads")
      .value("Tripod", grip::GraspType::Tripod, "the thumb's distal pad against the index's and long finger's")
      .value("LateralPinch", grip::GraspType::LateralPinch, "the thumb's pad against the index's middle phalanx");
  py::class_<Table>(m, "ContributionTable",
                    "Share d of each phalanx and of the palm in eq. 8: normal forces as fractions of the four "
                    "fingers' summed force, so that the fingers sum to 1 (docs/hand.md, Grasp types).")
      .def(py::init(&table_of), py::arg("share"), py::arg("palm") = 0.0,
           "share (5, 3) [digit][phalanx], thumb first (its middle, column 1, is 0); palm; all finite and >= 0")
      .def_property_readonly(
          "share",
          [](const Table& t) {
            RowMatrix s(5, 3);
            for (int f = 0; f < 5; ++f)
              for (int p = 0; p < 3; ++p) s(f, p) = t.share[f][p];
            return s;
          },
          "(5, 3) [digit][phalanx], thumb first; a copy")
      .def_readonly("palm", &Table::palm)
      .def_property_readonly(
          "by_phalanx",
          [](const Table& t) {
            Eigen::VectorXd d(grip::hand_phalanx_count);
            for (int k = 0; k < grip::hand_phalanx_count; ++k) d(k) = t(grip::phalanx_finger(k), grip::phalanx_kind(k));
            return d;
          },
          "(14,) d of each phalanx in the order of docs/hand.md (hand_contacts' phalanx index)")
      .def(
          "finger_total", [](const Table& t, Integer f) { return t.finger_total(finger_of(f.get("finger"))); },
          py::arg("finger"), "sum over a digit's phalanges, 0 (thumb) to 4 (little)")
      .def("four_finger_total", &Table::four_finger_total, "sum over index to little: 1 in grip's tables")
      .def("total", &Table::total, "sum of every share, thumb and palm included");
  m.def(
      "contribution_table", [](grip::GraspType g) { return grip::contribution_table<double>(g); },
      py::arg("grasp_type") = grip::GraspType::CylindricalPower, "The ContributionTable of a GraspType.");

  py::class_<Dims>(m, "HandDimensions", "The hand model's sizes (m) and joint axes, hand frame (docs/hand.md).")
      .def_static(
          "standard",
          [](Real length, bool left) {
            const double L = length.get("hand_length");
            if (!(L > 0) || !std::isfinite(L)) invalid("hand_length must be finite and > 0");
            return Dims::standard(L, left ? grip::Side::Left : grip::Side::Right);
          },
          py::arg("hand_length") = 0.19, py::arg("left") = false,
          "anthropometric defaults (Buchholz 1992) for a hand of length L (m); left=True mirrors it")
      .def_property_readonly("left", [](const Dims& d) { return d.side == grip::Side::Left; })
      .def_property_readonly(
          "joint_lower",
          [](const Dims& d) { return std::vector<double>(d.limits.lower.begin(), d.limits.lower.end()); },
          "(20,) the whole hand's lower joint limits (rad)")
      .def_property_readonly(
          "joint_upper",
          [](const Dims& d) { return std::vector<double>(d.limits.upper.begin(), d.limits.upper.end()); },
          "(20,) the whole hand's upper joint limits (rad)")
      .def_readonly("hand_length", &Dims::hand_length)
      .def_property_readonly("length",
                             [](const Dims& d) { return std::vector<double>(d.length.begin(), d.length.end()); })
      .def_property_readonly("radius",
                             [](const Dims& d) { return std::vector<double>(d.radius.begin(), d.radius.end()); })
      .def_property(
          "base", [](const Dims& d) { return rows(d.base); },
          [](Dims& d, const py::handle& v) {
            const Array a = numbers(v, "base");
            if (!a || a.ndim() != 2 || a.shape(0) != 5 || a.shape(1) != 3) invalid("base must have shape (5, 3)");
            for (int f = 0; f < 5; ++f)
              d.base[static_cast<std::size_t>(f)] = grip::Vector3<double>(a.at(f, 0), a.at(f, 1), a.at(f, 2));
          },
          "(5, 3) first joint of each digit (m); settable (forward_kinematics checks the dimensions)")
      .def_property(
          "thumb_cmc", [](const Dims& d) { return grip::Vector3<double>(d.thumb_cmc); },
          [](Dims& d, const py::handle& v) { d.thumb_cmc = vec3(v, "thumb_cmc"); }, "(3,) the thumb's CMC joint (m)")
      .def_property_readonly(
          "rest_direction", [](const Dims& d) { return rows(d.rest_direction); }, "(5, 3) unit")
      .def_property_readonly(
          "flexion_axis", [](const Dims& d) { return rows(d.flexion_axis); }, "(5, 3) unit")
      .def_property_readonly("joint_upper_limit", [](const Dims& d) {
        return std::vector<double>(d.joint_upper_limit.begin(), d.joint_upper_limit.end());
      });

  m.def(
      "forward_kinematics",
      [](const py::handle& wrist, const py::handle& q, const Dims* dims) {
        return capsules(posture(dims ? *dims : Dims::standard(), wrist, q));
      },
      py::arg("wrist"), py::arg("angles"), py::arg("dims") = nullptr,
      "The hand posed: wrist (4, 4) hand frame to world; angles (14,), the paper's flexions (rad), or (20,), the "
      "whole hand's joints. Returns a dict: base and tip (n, 3) (m, world) and radius (n,) of each body's capsule "
      "(n = 14 phalanges, or 19 with the palm's metacarpals), joint_axis and joint_point (20, 3), in the orders of "
      "docs/hand.md (a joint the hand holds fixed has a zero axis).");
  m.def(
      "point_jacobian",
      [](const py::handle& wrist, const py::handle& q, Integer body_index, const py::handle& point, const Dims* dims) {
        const int body = body_index.get("body");
        const grip::HandPosture<double> p = posture(dims ? *dims : Dims::standard(), wrist, q);
        if (body < 0 || body >= grip::hand_body_count || !(p.bodies >> body & 1u))
          invalid("body must be one of the posed hand's bodies, not " + std::to_string(body));
        grip::PointJacobian<double> J;
        if (grip::point_jacobian(p, body, vec3(point, "point"), J) != grip::Status::Ok)
          invalid("the point must be finite");
        return RowMatrix(J);
      },
      py::arg("wrist"), py::arg("angles"), py::arg("body"), py::arg("point"), py::arg("dims") = nullptr,
      "(3, 20) Jacobian of a world point carried by body `body` (0..13 phalanges, 14..18 metacarpals) with "
      "respect to the 20 joints; J.T @ f is the joint torques of a force f on that point (docs/hand.md).");

  py::class_<Prim>(m, "Primitive", "A sphere, box, cylinder or capsule with its pose in the object frame.");
  m.def(
      "sphere",
      [](Real r, const py::handle& c) {
        return checked(grip::make_sphere(r.get("radius"), vec3(c, "center")), "sphere");
      },
      py::arg("radius"), py::arg("center") = std::vector<double>{0, 0, 0});
  m.def(
      "box",
      [](const py::handle& h, const py::handle& c, const py::handle& rot) {
        return checked(grip::make_box(vec3(h, "half_extents"), vec3(c, "center"), rotation(rot)), "box");
      },
      py::arg("half_extents"), py::arg("center") = std::vector<double>{0, 0, 0}, py::arg("rotation") = py::none());
  m.def(
      "cylinder",
      [](Real r, Real h, const py::handle& c, const py::handle& rot) {
        return checked(grip::make_cylinder(r.get("radius"), h.get("half_length"), vec3(c, "center"), rotation(rot)),
                       "cylinder");
      },
      py::arg("radius"), py::arg("half_length"), py::arg("center") = std::vector<double>{0, 0, 0},
      py::arg("rotation") = py::none(), "axis along the rotation's third column (object z by default)");
  m.def(
      "capsule",
      [](Real r, Real h, const py::handle& c, const py::handle& rot) {
        return checked(grip::make_capsule(r.get("radius"), h.get("half_length"), vec3(c, "center"), rotation(rot)),
                       "capsule");
      },
      py::arg("radius"), py::arg("half_length"), py::arg("center") = std::vector<double>{0, 0, 0},
      py::arg("rotation") = py::none());

  py::class_<PyShape>(m, "Shape", "The union of 1 to 4 primitives, with its exact signed distance (object frame).")
      .def(py::init([](const std::vector<Prim>& prims) {
             if (prims.empty() || prims.size() > 4)
               invalid("a shape has 1 to 4 primitives, not " + std::to_string(prims.size()));
             PyShape s;
             for (const Prim& p : prims) (void)s.add(p);
             return s;
           }),
           py::arg("primitives"))
      .def(
          "distance", [](const PyShape& s, const py::handle& points) { return distances(s, points); },
          py::arg("points"), "(distance (m,), outward normal (m, 3)) at points (m, 3): negative inside");

  m.def(
      "hand_contacts",
      [](const py::object& field, const py::handle& wrist, const py::handle& q, const py::handle& object_pose,
         const Dims* dims, Integer phalanx_contacts, const py::object& octree) {
        const int per_phalanx = phalanx_contacts.get("per_phalanx");
        const grip::HandPosture<double> p = posture(dims ? *dims : Dims::standard(), wrist, q);
        const Iso object = object_pose.is_none() ? Iso::Identity() : pose(object_pose, "object_pose");
        grip::HandCollisionModel<double, 8> model;
        if (model.set_posture(p) != grip::Status::Ok) invalid("the posed hand is invalid");
        const Octree* tree = nullptr;
        if (!octree.is_none()) {
          if (!py::isinstance<PyOctree>(octree)) invalid("octree must be a grip.SphericalOctree");
          const PyOctree& o = octree.cast<const PyOctree&>();
          if (!o.field.is(field)) invalid("the octree must be the one built from this field");
          tree = o.tree.get();
        }
        if (py::isinstance<PyShape>(field))
          return contacts_with(model, field.cast<const PyShape&>(), tree, object, per_phalanx);
        if (py::isinstance<PyMesh>(field))
          return contacts_with(model, *field.cast<const PyMesh&>().shape, tree, object, per_phalanx);
        invalid("field must be a grip.Shape or a grip.Mesh");
      },
      py::arg("field"), py::arg("wrist"), py::arg("angles"), py::arg("object_pose") = py::none(),
      py::arg("dims") = nullptr, py::arg("per_phalanx") = 1, py::arg("octree") = py::none(),
      "Contacts of the posed hand with `field` (a Shape or a Mesh, object frame) placed by object_pose (4, 4) "
      "(identity by default), through `octree` (a SphericalOctree of the same field) when given, else directly: "
      "a dict of phalanx (m,) (0..13; 14..18 the palm's bodies with 20 joints), point (m, 3) on the surface and normal "
      "(m, 3) into the object (world), "
      "depth (m,) (m, > 0), sample, axis_parameter and status. Exact at faces, edges and corners (docs/collision.md).");
  const grip::mujoco::HandMjcf mjcf_defaults{};
  m.def(
      "hand_mjcf",
      [](const Dims* dims, const std::string& prefix, const py::handle& wrist, bool mocap, Real servo_gain,
         Real timestep, Real friction, Integer condim, const std::string& worldbody, const std::string& extra,
         const std::string& model, Real palm_mass, Real joint_damping, Real armature, Real density,
         Real torsional_friction) {
        return hand_mjcf_of(MjcfArgs{dims, prefix, wrist, mocap, servo_gain, timestep, friction, condim, worldbody,
                                     extra, model, palm_mass, joint_damping, armature, density, torsional_friction});
      },
      py::arg("dims") = nullptr, py::kw_only(), py::arg("prefix") = mjcf_defaults.prefix, py::arg("wrist") = py::none(),
      py::arg("mocap") = mjcf_defaults.mocap, py::arg("servo_gain") = mjcf_defaults.servo_gain,
      py::arg("timestep") = mjcf_defaults.timestep, py::arg("friction") = mjcf_defaults.friction,
      py::arg("condim") = mjcf_defaults.condim, py::arg("worldbody") = mjcf_defaults.worldbody,
      py::arg("extra") = mjcf_defaults.extra, py::arg("model") = mjcf_defaults.model,
      py::arg("palm_mass") = mjcf_defaults.palm_mass, py::arg("joint_damping") = mjcf_defaults.joint_damping,
      py::arg("armature") = mjcf_defaults.armature, py::arg("density") = mjcf_defaults.density,
      py::arg("torsional_friction") = mjcf_defaults.torsional_friction,
      "grip's whole hand (dims, HandDimensions.standard() for None) as a complete MJCF document (a str) that "
      "MuJoCo moves exactly as forward_kinematics: a body 'hand' at `wrist` ((4, 4) hand frame to world, m; "
      "the identity for None), free and welded to a mocap body 'hand_target' when mocap is True, else fixed; "
      "the 19 bodies hand_body_names() with their capsules (origins at the phalanges' bases); the 20 hinge "
      "joints hand_joint_names() in grip's order with its limits (rad), in qpos after the hand's free joint "
      "(7 numbers, when mocap); with servo_gain > 0 (N m/rad) a position actuator per joint (ctrl: target "
      "angle, rad). Every name is prefixed by `prefix`; worldbody is XML placed in <worldbody> after the hand, "
      "extra XML after it (assets, contacts). timestep (s), friction and torsional_friction (m) and condim "
      "(1, 3, 4, 6) of the hand geoms, palm_mass (kg), joint_damping (N m s/rad), armature (kg m^2), density "
      "(kg/m^3). ValueError names an invalid option. No MuJoCo call: load the text with "
      "mujoco.MjModel.from_xml_string.");
  m.def(
      "hand_body_names",
      [] {
        std::vector<std::string> names;
        for (int k = 0; k < grip::hand_body_count; ++k) names.emplace_back(grip::mujoco::hand_body_name(k));
        return names;
      },
      "The 19 body names hand_mjcf() writes, in grip's body order (0..13 phalanges, 14..18 metacarpals).");
  m.def(
      "hand_joint_names",
      [] {
        std::vector<std::string> names;
        for (int i = 0; i < grip::hand_dof_count; ++i) names.emplace_back(grip::mujoco::hand_joint_name(i));
        return names;
      },
      "The 20 joint (and actuator) names hand_mjcf() writes, in grip's joint order (docs/hand.md).");
}

}  // namespace grip_python
