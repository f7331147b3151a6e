// OctreeScene in the closed loop: the paper's Fig. 3, a hand grasping a cube (contacts from the
// spherical octree and the cube's exact distance field), held, lifted, released; what each
// phalanx feels against an independent solve of the same grasp; several contacts per
// phalanx; obstacles of any shape; the paper mode.
#include <doctest/doctest.h>

#include <cmath>

#include <grip/geometry/mesh_io.hpp>
#include <grip/geometry/mesh_shape.hpp>
#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/haptic_pipeline.hpp>
#include <grip/pipeline/octree_scene.hpp>
#include <grip/solve/solve_kkt.hpp>

#include "pipeline/pipeline_fixture.hpp"
#include "support/allocation_counter.hpp"
#include "support/tolerance.hpp"

namespace octree_scene_test {

using namespace grip;

namespace {

constexpr int cap = 16384;
constexpr double cube_half = 0.03, cube_mass = 0.3;

template <class S>
using CubeShape = Shape<S, 1>;

template <class S>
const CubeShape<S>& cube_shape() {
  static const CubeShape<S> shape(make_box<S>(Vector3<S>::Constant(S(cube_half))));
  return shape;
}
template <class S>
const SphericalOctree<S, cap>& cube_octree() {
  static SphericalOctree<S, cap> octree;
  static const bool built = octree.build(cube_shape<S>(), 3) == Status::Ok;
  REQUIRE(built);
  return octree;
}

// The hand closed on a 6 cm cube of 0.3 kg under the palm: the fingers over its far top edge
// and down its far face, the thumb on its near face (the cylinder fixture's geometry).
template <class S, int K = 1>
struct HeldCube {
  using Scene = OctreeScene<S, cap, CubeShape<S>, 8, K>;
  using Isometry = Eigen::Transform<S, 3, Eigen::Isometry>;
  HapticSettings<S> settings;
  Scene scene;
  RigidBody<S> object;
  WristState<S> wrist;
  JointAngles<S> closed{JointAngles<S>::Zero()};
  int touching = 0;

  HeldCube() {
    settings.hand.thumb_cmc.y() = S(-0.005);
    settings.hand.base[0].y() = S(-0.005);
    settings.contribution(Finger::Thumb, Phalanx::Proximal) = S(0.5);
    settings.contribution(Finger::Thumb, Phalanx::Distal) = S(0.7);
    settings.stiffness.fill(S(1.5e4));
    settings.device_limit.fill(S(100));
    scene.octree = &cube_octree<S>();
    scene.field = &cube_shape<S>();
    REQUIRE(add_box_points(scene.surface, Vector3<S>::Constant(S(cube_half))) == Status::Ok);
    object.mass = S(cube_mass);
    object.principal_inertia = solid_box_inertia<S>(S(cube_mass), Vector3<S>::Constant(S(cube_half)));
    object.position = Vector3<S>(S(0.1), S(0.2), S(0.5));
    const S l = settings.hand.hand_length;
    const Vector3<S> offset(S(0.374) * l + S(0.025), S(0), -(S(cube_half) + S(0.045) * l - S(0.002)));
    wrist.pose = Isometry::Identity();
    wrist.pose.translation() = object.position - offset;
    // The same closing for every test of a scalar and K: computed once.
    static const ClosedHand<S> c = close_hand_in_scene<S>(scene, settings.hand, wrist.pose, object, S(0.002), S(0.03));
    REQUIRE(c.status == Status::Ok);
    closed = c.angles;
    touching = c.touching;
  }
  HapticPipeline<S, Scene> pipeline() const { return HapticPipeline<S, Scene>(settings, scene, object); }
};

// The tolerance of a frame's forces, from round-off (support/tolerance.hpp): k = 1 unit of
// u * grasp_condition * force scale, the first-order error of a backward-stable solve with its
// constant taken as 1; observed at most 0.03 of it in both scalar types and both scenes (float:
// about 1.4e-4 N on the held cylinder's 0.4 kg, where a fixed 2e-3 N stood before). A moment's
// tolerance is the force tolerance times the object's reach (the largest |r_i|).
template <class S, class P>
double force_tol(const P& p, const grip::HapticFrame<S>& f) {
  return grip_test::frame_force_tolerance(p, f, 1);
}

// Round-off of n free-fall steps of 1 ms from x_a, v_a (support/tolerance.hpp), counted as in
// integrator.test.cpp with V = |v_a| + g t and X = |x_a| + V t bounding |v| and |x|: the
// velocity 2 roundings of V per step, g's and dt's 4 and the reference's 2 (tol_v); the
// position 1 of X + dt V per step, the reference's 6, and the velocity's error carried over t.
template <class S>
double fall_tol(int n, const grip::Vector3<S>& xa, const grip::Vector3<S>& va) {
  const double t = n * 1e-3, V = double(va.norm()) + 9.81 * t, X = double(xa.norm()) + V * t;
  const double tol_v = grip_test::roundoff<S>(2 * n + 6, 1, V);
  return grip_test::roundoff<S>(n + 6, 1, X + 1e-3 * V) + t * tol_v;
}

// A contact's point x - phi n lies on the surface to round-off: its world coordinates (16
// roundings of M, as in collision.test.cpp), local = point - position (1) and the field's
// distance (8): k = 25 of M = |point| + |position| (support/tolerance.hpp).
template <class S>
double surface_tol(const grip::Vector3<S>& point, const grip::Vector3<S>& position) {
  return grip_test::roundoff<S>(25, 1, double(point.norm() + position.norm()));
}
}  // namespace

TEST_CASE_TEMPLATE("a cube grasped (Fig. 3): each phalanx feels what an independent solve gives", S, double, float) {
  HeldCube<S> h;
  REQUIRE(h.touching >= 8);
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  REQUIRE(f.separating == 0);
  CHECK(f.sliding == 0);
  // Statics: the hand feels +m g in all, moments balanced about the centre of mass.
  CHECK(double((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), S(-cube_mass * 9.81))).norm()) <=
        force_tol(p, f));
  CHECK(double(grip_test::finger_moment(f, p).norm()) <= force_tol(p, f) * grip_test::contact_reach(p));
  // Per phalanx, against solve_kkt on the same contacts.
  const auto feel = grip_test::independent_feedback<S>(p, h.settings);
  int felt = 0;
  for (int k = 0; k < hand_phalanx_count; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    CHECK(double((f.phalanges[sk].force - feel[sk]).norm()) <= force_tol(p, f));
    felt += f.phalanges[sk].in_contact ? 1 : 0;
  }
  CHECK(felt == f.contacts);
  // Every contact lies on the cube's surface, its normal into the cube.
  for (int i = 0; i < p.hand_contacts().count; ++i) {
    const HandContact<S>& c = p.hand_contacts()[i];
    const Vector3<S> local = c.point - p.object().position;
    CHECK(double(std::abs(cube_shape<S>().distance(local))) <= surface_tol(c.point, p.object().position));
    CHECK(c.normal.dot(local) < S(0));
  }
}

TEST_CASE_TEMPLATE("a cube lifted, held still, then released: m (a - g), then free fall", S, double, float) {
  HeldCube<S> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  // Lift: the wrist accelerates upwards at 3 m/s^2 for 0.1 s; the fingers push m (a + 9.81).
  WristState<S> w = h.wrist;
  for (int i = 0; i < 100; ++i) {
    w.linear_acceleration.z() = S(3);
    w.linear_velocity.z() += S(3e-3);
    w.pose.translation() += w.linear_velocity * S(1e-3);
    REQUIRE(p.step(w, h.closed, f) == Status::Ok);
    REQUIRE(f.held);
    CHECK(double(std::abs(-grip_test::total_feedback(f).z() - S(cube_mass * (3 + 9.81)))) <= force_tol(p, f));
  }
  const Vector3<S> lifted = p.object().position;
  CHECK(lifted.z() > h.object.position.z() + S(0.014));  // 3 * 0.1^2 / 2 = 15 mm up, with the hand
  // Hold still: the weight again.
  w.linear_acceleration.setZero();
  w.linear_velocity.setZero();
  for (int i = 0; i < 20; ++i) {
    REQUIRE(p.step(w, h.closed, f) == Status::Ok);
    REQUIRE(f.held);
  }
  CHECK(double((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), S(-cube_mass * 9.81))).norm()) <=
        force_tol(p, f));
  // Release: open the hand, move it aside; the cube falls with g.
  const JointAngles<S> open = JointAngles<S>::Zero();
  REQUIRE(p.step(w, open, f) == Status::Ok);
  REQUIRE_FALSE(f.held);
  w.pose.translation().y() += S(0.5);
  REQUIRE(p.step(w, open, f) == Status::Ok);
  REQUIRE(f.contacts == 0);
  const Vector3<S> xa = p.object().position, va = p.object().linear_velocity;
  for (int i = 0; i < 100; ++i) REQUIRE(p.step(w, open, f) == Status::Ok);
  const S t = S(0.1);
  CHECK(double((p.object().position - (xa + va * t + S(0.5) * Vector3<S>(S(0), S(0), S(-9.81)) * t * t)).norm()) <=
        fall_tol(100, xa, va));
}

TEST_CASE_TEMPLATE("a cube on a tilted slab: obstacles of any shape push through the box points", S, double, float) {
  HeldCube<S> h;
  // A slab turned 0.3 rad about x whose top face passes 2 mm above the cube's lowest corners.
  const Matrix3<S> R = Eigen::AngleAxis<S>(S(0.3), Vector3<S>::UnitX()).toRotationMatrix();
  const Vector3<S> up = R.col(2);
  // The cube's lowest point along -up: the corner minimising up . (c + corner).
  S lowest = S(1e9);
  for (int i = 0; i < h.scene.surface.count; ++i)
    lowest = std::min(lowest, up.dot(h.object.position + h.scene.surface.items[static_cast<std::size_t>(i)]));
  const Vector3<S> center = h.object.position + (lowest + S(0.002) - up.dot(h.object.position) - S(0.05)) * up;
  REQUIRE(h.scene.obstacles.add(Shape<S>(make_box<S>(Vector3<S>(S(0.3), S(0.3), S(0.05)), center, R))) == Status::Ok);
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.obstacles >= 1);
  // The slab pushes along its normal (into the cube): a positive multiple of `up`.
  const Vector3<S> push = f.external.obstacles.template head<3>();
  CHECK(push.dot(up) > S(0));
  // Each point's force is k depth times the slab's normal, R's column (exact products with 0
  // and 1), so push is along up but for the products' and the sum's roundings: obstacles + 4
  // of |push|, and the test's own projection's 4 (support/tolerance.hpp).
  CHECK(double((push - push.dot(up) * up).norm()) <= grip_test::roundoff<S>(f.obstacles + 8, 1, double(push.norm())));
}

TEST_CASE_TEMPLATE("several contacts per phalanx in the loop: statics hold, forces summed per phalanx", S, double,
                   float) {
  HeldCube<S, 3> h;
  auto p = h.pipeline();
  HapticFrame<S> f;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(f.held);
  CHECK(double((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), S(-cube_mass * 9.81))).norm()) <=
        force_tol(p, f));
  const auto feel = grip_test::independent_feedback<S>(p, h.settings);
  for (int k = 0; k < hand_phalanx_count; ++k)
    CHECK(double((f.phalanges[static_cast<std::size_t>(k)].force - feel[static_cast<std::size_t>(k)]).norm()) <=
          force_tol(p, f));
  int several = 0;
  for (int k = 0; k < hand_phalanx_count; ++k)
    several += p.hand_contacts().count_of(phalanx_finger(k), phalanx_kind(k)) > 1 ? 1 : 0;
  CHECK(several >= 1);  // a phalanx across the cube's top edge touches two faces
}

TEST_CASE_TEMPLATE("the paper mode in the loop: exact on faces, no heap per frame", S, double, float) {
  HeldCube<S> h;
  static SphericalOctree<S, cap> deep;  // the paper mode needs small leaves (docs/collision.md)
  REQUIRE(deep.build(cube_shape<S>(), 5) == Status::Ok);
  OctreeScene<S, cap> paper;
  paper.octree = &deep;
  HapticPipeline<S, OctreeScene<S, cap>> p(h.settings, paper, h.object);
  auto q = h.pipeline();
  HapticFrame<S> f, g;
  REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
  REQUIRE(q.step(h.wrist, h.closed, g) == Status::Ok);
  // Phalanges lying on the top face (normal -z in the exact mode): the leaf planes are
  // exact there, so both modes agree. (Near the edges they do not: collision.hpp.)
  int on_face = 0;
  for (int i = 0; i < q.hand_contacts().count; ++i) {
    const HandContact<S>& e = q.hand_contacts()[i];
    // On the top face the exact mode's normal is -z but for a unit normal's round-off, 8 u
    // (collision.test.cpp): the filter admits that and no edge or corner normal.
    if (double((e.normal + Vector3<S>::UnitZ()).norm()) > grip_test::roundoff<S>(8, 1, 1)) continue;
    const HandContact<S>* c = p.hand_contacts().find(e.finger, e.phalanx);
    REQUIRE(c != nullptr);
    // Both modes are exact on a face: each depth within 16 u M of the truth (collision.test.cpp),
    // M = |point| + |position|; each normal within 8 u.
    CHECK(double(std::abs(c->depth - e.depth)) <=
          2 * grip_test::roundoff<S>(16, 1, double(e.point.norm() + p.object().position.norm())));
    CHECK(double((c->normal - e.normal).norm()) <= 2 * grip_test::roundoff<S>(8, 1, 1));
    ++on_face;
  }
  CHECK(on_face >= 3);
  grip_test::NoHeapScope scope;
  for (int i = 0; i < 10; ++i) {
    REQUIRE(p.step(h.wrist, h.closed, f) == Status::Ok);
    REQUIRE(q.step(h.wrist, h.closed, g) == Status::Ok);
  }
  CHECK(scope.allocations() == 0);
}

namespace {
template <class S>
using Blob = TriangleMesh<S, 4096, 8192>;
template <class S>
using BlobShape = MeshShape<S, 4096, 8192>;

// The bunny-like blob of tests/data/meshes (5 120 triangles, about 78 mm across), its field and
// its octree at the depth docs/collision.md recommends for the exact narrow phase.
template <class S>
struct BlobObject {
  Blob<S> mesh;
  BlobShape<S> shape;
  SphericalOctree<S, cap> octree;
  bool ok = false;
  BlobObject() {
    static char buffer[1 << 18];
    ok = read_mesh_file(GRIP_TEST_DATA_DIR "/meshes/blob.obj", buffer, sizeof buffer, mesh).status == Status::Ok &&
         shape.build(mesh) == Status::Ok && octree.build(winding_signed(shape), 3) == Status::Ok;
  }
};
template <class S>
BlobObject<S>& blob() {
  static BlobObject<S>* b = new BlobObject<S>();  // large: once per scalar, kept to the end
  return *b;
}
}  // namespace

// Double only: at -O0 closing the hand on the mesh takes seconds; the mesh's float path is
// checked by collision_bounds.test.cpp (the mug) and mesh_shape.test.cpp.
TEST_CASE_TEMPLATE("a mesh object in the loop: held, lifted and released, each phalanx against an independent solve", S,
                   double) {
  BlobObject<S>& b = blob<S>();
  REQUIRE(b.ok);
  using Scene = OctreeScene<S, cap, BlobShape<S>, 4>;  // 4 samples per phalanx: half the queries
  HapticSettings<S> settings;
  settings.hand.thumb_cmc.y() = S(-0.005);
  settings.hand.base[0].y() = S(-0.005);
  settings.contribution(Finger::Thumb, Phalanx::Proximal) = S(0.5);
  settings.contribution(Finger::Thumb, Phalanx::Distal) = S(0.7);
  settings.stiffness.fill(S(1.5e4));
  settings.device_limit.fill(S(100));
  Scene scene;
  scene.octree = &b.octree;
  scene.field = &b.shape;
  for (int v = 0; v < b.mesh.vertex_count() && scene.surface.count < 32; v += b.mesh.vertex_count() / 32)
    REQUIRE(scene.surface.add(b.mesh.vertex(v)) == Status::Ok);
  Vector3<S> lo, hi;
  REQUIRE(b.shape.bounding_box(lo, hi));
  RigidBody<S> object;
  object.mass = S(0.2);
  object.principal_inertia = solid_box_inertia<S>(S(0.2), Vector3<S>((hi - lo) / S(2)));
  object.position = Vector3<S>(S(0.1), S(0.2), S(0.5));
  WristState<S> wrist;
  const S l = settings.hand.hand_length;
  wrist.pose.translation() = object.position - Vector3<S>(S(0.374) * l + S(0.02), S(0),
                                                          -(S(0.5) * (hi.z() - lo.z()) + S(0.045) * l - S(0.002)));
  const ClosedHand<S> closed = close_hand_in_scene<S>(scene, settings.hand, wrist.pose, object, S(0.002), S(0.05));
  REQUIRE(closed.status == Status::Ok);
  REQUIRE(closed.touching >= 6);
  HapticPipeline<S, Scene> p(settings, scene, object);
  HapticFrame<S> f;
  REQUIRE(p.step(wrist, closed.angles, f) == Status::Ok);
  REQUIRE(f.held);
  REQUIRE(f.separating == 0);
  const S weight = S(0.2 * 9.81);
  CHECK(double((grip_test::total_feedback(f) - Vector3<S>(S(0), S(0), -weight)).norm()) <= force_tol(p, f));
  CHECK(double(grip_test::finger_moment(f, p).norm()) <= force_tol(p, f) * grip_test::contact_reach(p));
  const auto feel = grip_test::independent_feedback<S>(p, settings);
  for (int k = 0; k < hand_phalanx_count; ++k)
    CHECK(double((f.phalanges[static_cast<std::size_t>(k)].force - feel[static_cast<std::size_t>(k)]).norm()) <=
          force_tol(p, f));
  for (int i = 0; i < p.hand_contacts().count; ++i) {  // on the mesh's surface
    const Vector3<S> local = p.hand_contacts()[i].point - p.object().position;
    CHECK(double(std::abs(b.shape.distance(local))) <= surface_tol(p.hand_contacts()[i].point, p.object().position));
  }
  // Lift at 2 m/s^2 for 20 ms, then release: free fall.
  for (int i = 0; i < 20; ++i) {
    wrist.linear_acceleration.z() = S(2);
    wrist.linear_velocity.z() += S(2e-3);
    wrist.pose.translation() += wrist.linear_velocity * S(1e-3);
    REQUIRE(p.step(wrist, closed.angles, f) == Status::Ok);
    REQUIRE(f.held);
    CHECK(double(std::abs(-grip_test::total_feedback(f).z() - S(0.2) * S(2 + 9.81))) <= force_tol(p, f));
  }
  const JointAngles<S> open = JointAngles<S>::Zero();
  wrist.linear_acceleration.setZero();
  wrist.linear_velocity.setZero();
  REQUIRE(p.step(wrist, open, f) == Status::Ok);
  REQUIRE_FALSE(f.held);
  wrist.pose.translation().y() += S(0.5);
  REQUIRE(p.step(wrist, open, f) == Status::Ok);
  REQUIRE(f.contacts == 0);
  const Vector3<S> xa = p.object().position, va = p.object().linear_velocity;
  for (int i = 0; i < 20; ++i) REQUIRE(p.step(wrist, open, f) == Status::Ok);
  const S t = S(0.02);
  CHECK(double((p.object().position - (xa + va * t + S(0.5) * Vector3<S>(S(0), S(0), S(-9.81)) * t * t)).norm()) <=
        fall_tol(20, xa, va));
}

}  // namespace octree_scene_test
