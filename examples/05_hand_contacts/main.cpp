// The contacts of a power grasp: a virtual hand (default 0.19 m anthropometry) closes on a
// cylinder of 35 mm radius; print each phalanx in contact (finger, phalanx, depth dr_i,
// squeeze s_i = d_i K_i dr_i), then the feedback forces that hold the cylinder against gravity.
#include <cstdio>

#include <Eigen/Geometry>

#include <grip/collision/grasp_from_contacts.hpp>
#include <grip/collision/hand_closure.hpp>
#include <grip/solve/solve_range_space.hpp>

namespace {
const char* finger_name(grip::Finger f) {
  static const char* names[] = {"thumb", "index", "long", "ring", "little"};
  return names[static_cast<int>(f)];
}
const char* phalanx_name(grip::Phalanx p) {
  static const char* names[] = {"proximal", "middle", "distal"};
  return names[static_cast<int>(p)];
}
}  // namespace

int main() {
  using namespace grip;
  using S = double;
  using Iso = Eigen::Transform<S, 3, Eigen::Isometry>;

  // Set-up (once): the object's octree in its own frame, the hand's dimensions.
  static SphericalOctree<S, 16384> cylinder;  // static storage: about 1.3 MB
  const Shape<S> shape(make_cylinder<S>(0.035, 0.07));
  if (cylinder.build(shape, 5) != Status::Ok) return 1;
  const HandDimensions<S> dims = HandDimensions<S>::standard(0.19);

  // The cylinder lies across the palm (axis along the hand's y), just under the fingers.
  Iso object = Iso::Identity();
  object.linear() = Eigen::AngleAxis<S>(1.5707963267948966, Vector3<S>::UnitX()).toRotationMatrix();
  object.translation() = Vector3<S>(dims.base[1].x() + 0.02, 0, -(0.035 + dims.radius[2] + 0.001));
  const Iso wrist = Iso::Identity();

  // Joint angles: in an application the glove gives them; here, close the hand until 2 mm deep.
  JointAngles<S> angles = JointAngles<S>::Zero();
  if (close_hand(dims, wrist, cylinder, shape, object, 0.002, 0.02, angles) != Status::Ok) return 1;

  // One frame: kinematics, hand hierarchy, contacts (the octree finds what can touch, the
  // cylinder's exact distance decides depth, point and normal), grasp.
  HandPosture<S> posture;
  HandCollisionModel<S> hand;
  HandContacts<S> contacts;
  if (forward_kinematics(dims, wrist, angles, posture) != Status::Ok) return 1;
  if (hand.set_posture(posture) != Status::Ok) return 1;
  if (detect_contacts(hand, cylinder, shape, object, contacts) != Status::Ok) return 1;

  ContactParameters<S> params;  // Table 1 shares, K = 1e4 N/m, mu = 0.8
  Grasp<Dynamic, HardFinger, S, 16> grasp;
  const Vector3<S> com = object.translation();
  if (fill_grasp(contacts, com, params, grasp) != Status::Ok) return 1;

  std::printf("joint angles (deg):");
  for (int k = 0; k < hand_joint_count; ++k) std::printf(" %.1f", angles(k) * 57.29577951308232);
  std::printf("\n%d contacts\n", contacts.count);
  std::printf("%-7s %-9s %9s %10s   %s\n", "finger", "phalanx", "dr (mm)", "s (N)", "normal into object");
  for (int i = 0; i < contacts.count; ++i) {
    const HandContact<S>& c = contacts[i];
    std::printf("%-7s %-9s %9.3f %10.3f   (%+.2f %+.2f %+.2f)\n", finger_name(c.finger), phalanx_name(c.phalanx),
                c.depth * 1e3, grasp.contact(i).squeeze, c.normal.x(), c.normal.y(), c.normal.z());
  }

  // Hold 0.3 kg against gravity: the forces each phalanx must feel (-f_i).
  Wrench<S> w_ext = Wrench<S>::Zero();
  w_ext(2) = -0.3 * 9.81;
  const auto sol = solve_range_space(grasp, w_ext);
  std::printf("solve: %s, residual %.2e\n", to_string(sol.status), sol.residual);
  for (int i = 0; i < grasp.size(); ++i) {
    const Vector3<S> f = sol.forces.template segment<3>(3 * i);
    std::printf("%-7s %-9s |f| = %6.3f N\n", finger_name(contacts[i].finger), phalanx_name(contacts[i].phalanx),
                f.norm());
  }
  return 0;
}
