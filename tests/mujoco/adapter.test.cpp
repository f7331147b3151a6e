// The MuJoCo adapter (grip/mujoco/adapter.hpp) on scenes MuJoCo simulates: a box squeezed
// between two pads of a tracker-driven rig, held, lifted with an acceleration, resting on a
// table, and touched by a pad outside the map. References are MuJoCo's own: the object's
// acceleration from mj_objectAcceleration (after mj_rnePostConstraint, an accelerometer's
// path, not the adapter's qacc), its mass, and its contact forces from mj_contactForce.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <grip/mujoco/adapter.hpp>
#include <grip/solve/solve_constrained.hpp>
#include <grip/solve/solve_range_space.hpp>

#include "mujoco/mujoco_support.hpp"
#include "support/allocation_counter.hpp"

using namespace grip;
using grip::mujoco::Adapter;
using grip::mujoco::BodyName;
using grip::mujoco::Problem;

namespace {

constexpr double box_mass = 0.2;

// A box (6 cm, 0.2 kg) between two pads 1 mm inside its faces, on a rig welded to a mocap
// target (so that the rig moves with real velocities and its contacts carry friction); a third pad at `c_offset` along
// y (0.035 touches the box's +y face, 0.2 keeps clear); a table whose top is at `table_top`.
std::string scene(double rig_z, double c_offset, double table_top) {
  const std::string pad = "<geom type=\"box\" size=\"0.005 0.02 0.02\" friction=\"1 0.005 0.0001\" condim=\"3\"/>";
  return "<mujoco><option timestep=\"0.001\" cone=\"elliptic\" impratio=\"10\"/><worldbody>"
         "<geom name=\"table\" type=\"box\" pos=\"0 0 " +
         std::to_string(table_top - 0.05) +
         "\" size=\"0.3 0.3 0.05\"/>"
         "<body name=\"target\" mocap=\"true\" pos=\"0 0 " +
         std::to_string(rig_z) +
         "\"/>"
         "<body name=\"rig\" pos=\"0 0 " +
         std::to_string(rig_z) +
         "\"><freejoint/>"
         "<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"0.01 0.01 0.01\"/>"
         "<body name=\"pad_a\" pos=\"0.034 0 0\">" +
         pad +
         "</body>"
         "<body name=\"pad_b\" pos=\"-0.034 0 0\">" +
         pad +
         "</body>"
         "<body name=\"pad_c\" pos=\"0 " +
         std::to_string(c_offset) + " 0\" euler=\"0 0 1.5707963267948966\">" + pad +
         "</body></body>"
         "<body name=\"box\" pos=\"0 0 " +
         std::to_string(rig_z) +
         "\"><freejoint/>"
         "<geom type=\"box\" size=\"0.03 0.03 0.03\" mass=\"" +
         std::to_string(box_mass) +
         "\" condim=\"3\"/></body>"
         "<body name=\"fixed\" pos=\"0.5 0 0.05\"><geom type=\"sphere\" size=\"0.01\"/></body>"
         "</worldbody><equality><weld body1=\"target\" body2=\"rig\" solref=\"0.01 1\"/></equality></mujoco>";
}

const BodyName pads[] = {{"pad_a", phalanx_index(Finger::Index, Phalanx::Distal)},
                         {"pad_b", phalanx_index(Finger::Thumb, Phalanx::Distal)}};

struct Sim {
  grip_test::ModelPtr m;
  grip_test::DataPtr d;
  explicit Sim(const std::string& xml) {
    std::string error;
    m = grip_test::load_mjcf(xml, &error);
    INFO(error);
    REQUIRE(m != nullptr);
    d.reset(mj_makeData(m.get()));
    mj_forward(m.get(), d.get());
  }
};

// MuJoCo's own wrench on `body` from its contacts with `other` (or every other body when
// other < 0), about the body's centre of mass.
Wrench<double> mujoco_wrench(const Sim& s, int body, int other) {
  const Eigen::Vector3d com(s.d->xipos + 3 * body);
  Wrench<double> w = Wrench<double>::Zero();
  for (int i = 0; i < s.d->ncon; ++i) {
    const mjContact& c = s.d->contact[i];
    const int b1 = s.m->geom_bodyid[c.geom1], b2 = s.m->geom_bodyid[c.geom2];
    if (other >= 0 && b1 != other && b2 != other) continue;
    w += grip::mujoco::contact_wrench_on(s.m.get(), s.d.get(), i, body, com);
  }
  return w;
}

// m (a - g) of `body` by MuJoCo's accelerometer path (mj_objectAcceleration reads a - g).
Eigen::Vector3d accelerometer_force(Sim& s, int body) {
  mj_rnePostConstraint(s.m.get(), s.d.get());
  mjtNum acc[6];
  mj_objectAcceleration(s.m.get(), s.d.get(), mjOBJ_BODY, body, acc, 0);
  return s.m->body_mass[body] * Eigen::Vector3d(acc[3], acc[4], acc[5]);
}

auto constrained = [](const auto& g, const auto& w) { return solve_constrained(g, w); };

// Every solved force inside its exact cone: f . a >= 0 and |f_t| <= mu f_n (relative 1e-9).
template <class A>
bool in_cones(const A& a) {
  for (int i = 0; i < a.grasp().size(); ++i) {
    const Eigen::Vector3d f = a.force_on_object(i);
    const Contact<double>& c = a.grasp().contact(i);
    const double fn = f.dot(c.normal);
    const double ft = (f - fn * c.normal).norm();
    if (!(fn >= -1e-9 * f.norm() && ft <= c.friction * fn + 1e-9 * f.norm())) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("mujoco adapter: a held box: felt sum m (g - a), MuJoCo's own hand forces, exact cones") {
  Sim s(scene(0.2, 0.2, 0.0));
  Adapter<> a;
  REQUIRE(a.bind(s.m.get(), "box", pads, 2) == Status::Ok);
  const int box = a.object();
  const double z0 = 0.2;
  int checked = 0;
  for (int step = 0; step < 600; ++step) {
    // Hold still for 0.3 s, then lift at 3 m/s^2.
    const double t = step * s.m->opt.timestep, lift = t > 0.3 ? t - 0.3 : 0.0;
    s.d->mocap_pos[2] = z0 + 0.5 * 3.0 * lift * lift;
    mj_step(s.m.get(), s.d.get());
    if (step % 50 != 49) continue;
    REQUIRE(a.update(s.m.get(), s.d.get()) == Status::Ok);
    REQUIRE(a.grasp().size() >= 2);
    CHECK(a.ignored() == 0);
    CHECK(a.obstacle_contacts() == 0);
    FeltForces<double> felt;
    REQUIRE(a.solve(constrained, felt) == Status::Ok);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < hand_body_count; ++k) sum += felt.force[detail::idx(k)];
    CHECK(felt.in_contact[detail::idx(pads[0].body)]);
    CHECK(felt.in_contact[detail::idx(pads[1].body)]);
    // The hand feels m (g - a): -m (a - g) from MuJoCo's accelerometer.
    const Eigen::Vector3d expected = -accelerometer_force(s, box);
    INFO("step " << step << " felt " << sum.transpose() << " expected " << expected.transpose());
    CHECK((sum - expected).norm() <= 1e-6 * (1 + expected.norm()));
    // grip's contacts apply the wrench MuJoCo's contacts apply (the same Newton-Euler).
    Wrench<double> grip_wrench = Wrench<double>::Zero();
    for (int i = 0; i < a.grasp().size(); ++i)
      grip_wrench += HardFinger::wrench(a.grasp().contact(i), Eigen::Vector3d(a.force_on_object(i)));
    const Wrench<double> mj = mujoco_wrench(s, box, -1);
    CHECK((grip_wrench - mj).norm() <= 1e-6 * (1 + mj.norm()));
    CHECK(in_cones(a));
    if (t > 0.35) CHECK(expected.z() < -box_mass * (9.81 + 1.0));  // lifted: heavier than m g
    if (t < 0.3 && t > 0.2) CHECK(std::abs(expected.z() + box_mass * 9.81) < 0.05 * box_mass * 9.81);
    ++checked;
  }
  CHECK(checked == 12);
}

TEST_CASE("mujoco adapter: the table as an external force, a pad outside the map ignored and counted") {
  // The box rests on the table (its bottom 1 mm into it) between the pads; pad_c touches +y.
  Sim s(scene(0.029, 0.034, 0.0));
  Adapter<> a;
  REQUIRE(a.bind(s.m.get(), "box", pads, 2) == Status::Ok);
  for (int step = 0; step < 200; ++step) mj_step(s.m.get(), s.d.get());
  REQUIRE(a.update(s.m.get(), s.d.get()) == Status::Ok);
  CHECK(a.obstacle_contacts() >= 1);
  CHECK(a.ignored() >= 1);
  const int box = a.object();
  const int table = 0, pad_c = mj_name2id(s.m.get(), mjOBJ_BODY, "pad_c");
  CHECK((a.object_wrench().obstacles - mujoco_wrench(s, box, table)).norm() <= 1e-9);
  // The mapped pads' MuJoCo wrench balances w_ext minus the ignored pad's.
  const Wrench<double> hand = mujoco_wrench(s, box, mj_name2id(s.m.get(), mjOBJ_BODY, "pad_a")) +
                              mujoco_wrench(s, box, mj_name2id(s.m.get(), mjOBJ_BODY, "pad_b"));
  const Wrench<double> rest = a.external_wrench() + mujoco_wrench(s, box, pad_c);
  CHECK((hand + rest).norm() <= 1e-6 * (1 + hand.norm()));
}

TEST_CASE("mujoco adapter: no contact gives Singular and zero forces, no heap in update and solve") {
  Sim s(scene(0.2, 0.2, 0.0));
  Adapter<> a;
  REQUIRE(a.bind(s.m.get(), "box", pads, 2) == Status::Ok);
  for (int step = 0; step < 20; ++step) mj_step(s.m.get(), s.d.get());
  FeltForces<double> felt;
  {
    grip_test::NoHeapScope scope;
    CHECK(a.update(s.m.get(), s.d.get()) == Status::Ok);
    CHECK(a.solve(constrained, felt) == Status::Ok);
    CHECK(a.update(s.m.get(), s.d.get()) == Status::Ok);
    CHECK(a.solve([](const auto& g, const auto& w) { return solve_range_space(g, w); }, felt) == Status::Ok);
    CHECK(scope.allocations() == 0);
  }
  // The rig (and its target) 1 m higher: the box falls free.
  const int rig = mj_name2id(s.m.get(), mjOBJ_BODY, "rig");
  s.d->qpos[s.m->jnt_qposadr[s.m->body_jntadr[rig]] + 2] += 1.0;
  s.d->mocap_pos[2] += 1.0;
  mj_forward(s.m.get(), s.d.get());
  REQUIRE(a.update(s.m.get(), s.d.get()) == Status::Ok);
  CHECK(a.grasp().size() == 0);
  CHECK(a.solve(constrained, felt) == Status::Singular);
  for (int k = 0; k < hand_body_count; ++k) CHECK(felt.force[detail::idx(k)].norm() == 0.0);
  // Falling free: w_ext is about zero (gravity and inertia cancel).
  CHECK(a.external_wrench().norm() <= 1e-6);
}

TEST_CASE("mujoco adapter: set-up errors name the problem and the entry") {
  Sim s(scene(0.2, 0.2, 0.0));
  Adapter<> a;
  const auto problem = [&](const char* object, const BodyName* entries, int count) {
    const Status st = a.bind(s.m.get(), object, entries, count);
    CHECK((st == Status::Ok) == (a.problem() == Problem::None));
    return a.problem();
  };
  const BodyName missing[] = {{"pad_a", 4}, {"pad_x", 1}};
  CHECK(problem("box", missing, 2) == Problem::NameMissing);
  CHECK(a.entry() == 1);
  const BodyName null_name[] = {{nullptr, 4}};
  CHECK(problem("box", null_name, 1) == Problem::NameMissing);
  const BodyName twice[] = {{"pad_a", 4}, {"pad_b", 1}, {"pad_a", 7}};
  CHECK(problem("box", twice, 3) == Problem::BodyTwice);
  CHECK(a.entry() == 2);
  const BodyName range[] = {{"pad_a", 19}};
  CHECK(problem("box", range, 1) == Problem::BodyOutOfRange);
  const BodyName world[] = {{"world", 4}};
  CHECK(problem("box", world, 1) == Problem::WorldBody);
  CHECK(problem("box", pads, 0) == Problem::EmptyMap);
  CHECK(problem("box", nullptr, 2) == Problem::EmptyMap);
  CHECK(problem("boxx", pads, 2) == Problem::ObjectMissing);
  CHECK(problem(nullptr, pads, 2) == Problem::ObjectMissing);
  CHECK(problem("fixed", pads, 2) == Problem::ObjectNotFree);
  CHECK(problem("pad_a", pads, 2) == Problem::ObjectInHand);
  CHECK(a.bind(nullptr, "box", pads, 2) == Status::InvalidInput);
  CHECK(a.problem() == Problem::NullModel);
  s.m->opt.gravity[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK(problem("box", pads, 2) == Problem::ModelNotFinite);
  s.m->opt.gravity[2] = -9.81;
  s.m->opt.timestep = 0;
  CHECK(problem("box", pads, 2) == Problem::ModelNotFinite);
  s.m->opt.timestep = 0.001;
  CHECK(problem("box", pads, 2) == Problem::None);
  // Unbound or null: update refuses.
  Adapter<> unbound;
  CHECK(unbound.update(s.m.get(), s.d.get()) == Status::InvalidInput);
  CHECK(a.update(s.m.get(), nullptr) == Status::InvalidInput);
  // A state that is not finite: InvalidInput, the grasp empty.
  const int box = mj_name2id(s.m.get(), mjOBJ_BODY, "box");
  s.d->qacc[s.m->jnt_dofadr[s.m->body_jntadr[box]] + 2] = std::numeric_limits<double>::infinity();
  CHECK(a.update(s.m.get(), s.d.get()) == Status::InvalidInput);
  CHECK(a.grasp().size() == 0);
  for (const Problem p : {Problem::None, Problem::NullModel, Problem::ModelNotFinite, Problem::EmptyMap,
                          Problem::NameMissing, Problem::BodyOutOfRange, Problem::BodyTwice, Problem::WorldBody,
                          Problem::ObjectMissing, Problem::ObjectNotFree, Problem::ObjectInHand})
    CHECK(std::string(grip::mujoco::to_string(p)) != "unknown");
}

TEST_CASE("mujoco adapter: more hand contacts than the grasp holds gives OutOfRange and counts them") {
  Sim s(scene(0.2, 0.2, 0.0));
  Adapter<HardFinger, double, 3> a;
  REQUIRE(a.bind(s.m.get(), "box", pads, 2) == Status::Ok);
  mj_step(s.m.get(), s.d.get());
  int hand_contacts = 0;
  for (int i = 0; i < s.d->ncon; ++i) {
    const int b1 = s.m->geom_bodyid[s.d->contact[i].geom1], b2 = s.m->geom_bodyid[s.d->contact[i].geom2];
    hand_contacts += (a.map().grip_body(b1) >= 0 || a.map().grip_body(b2) >= 0) ? 1 : 0;
  }
  REQUIRE(hand_contacts > 3);
  CHECK(a.update(s.m.get(), s.d.get()) == Status::OutOfRange);
  CHECK(a.grasp().size() == 3);
  CHECK(a.dropped() == hand_contacts - 3);
}
