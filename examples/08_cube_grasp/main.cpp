// The paper's Fig. 3: the virtual hand closes on a cube and lifts it. The contacts come from
// the cube's spherical octree (the broad phase) and its exact distance field (the narrow
// phase), up to two per phalanx, so a phalanx lying across the cube's top edge presses on
// both faces. Prints the contacts and what each phalanx feels while the cube is held and
// lifted; writes cube_grasp.svg (the contacts and their normals on the cube, seen from the
// front and from the side) to the current directory or to the directory given as argv[1].
// Exits 0 when the cube is held through the lift and rises with the hand.
#include <cmath>
#include <cstdio>
#include <string>

#include <grip/pipeline/close_hand.hpp>
#include <grip/pipeline/haptic_pipeline.hpp>
#include <grip/pipeline/octree_scene.hpp>

namespace {

using S = double;
using V3 = grip::Vector3<S>;
using Cube = grip::Shape<S, 1>;
constexpr int octree_capacity = 4096;  // depth 4 of a cube needs about 1 900 cells
constexpr int per_phalanx = 2;
using Scene = grip::OctreeScene<S, octree_capacity, Cube, 8, per_phalanx>;
using Pipeline = grip::HapticPipeline<S, Scene>;
constexpr double half = 0.03, mass = 0.3;  // a 6 cm cube of 300 g

const char* const phalanx_names[grip::hand_phalanx_count] = {
    "thumb prox", "thumb dist", "index prox", "index mid", "index dist",  "long prox",  "long mid",
    "long dist",  "ring prox",  "ring mid",   "ring dist", "little prox", "little mid", "little dist"};

// The SVG: two orthographic views of the cube (front: world x right, z up; side: world y
// right, z up), the phalanx capsules in grey, each contact a dot with its normal (into the
// cube) as an arrow, coloured by finger.
void write_svg(const std::string& path, const Pipeline& p) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::printf("cannot write %s\n", path.c_str());
    return;
  }
  const double W = 900, H = 470, scale = 2500, cx[2] = {225, 675}, cy = 250;
  const V3 c = p.object().position;
  const int axis[2] = {0, 1};  // the horizontal world axis of each view
  const char* colour[5] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd"};
  auto X = [&](int v, const V3& q) { return cx[v] + scale * (q(axis[v]) - c(axis[v])); };
  auto Y = [&](const V3& q) { return cy - scale * (q.z() - c.z()); };
  std::fprintf(
      f,
      "<svg xmlns='http://www.w3.org/2000/svg' width='%.0f' height='%.0f' font-family='sans-serif' font-size='13'>\n",
      W, H);
  std::fprintf(f, "<rect width='100%%' height='100%%' fill='white'/>\n");
  std::fprintf(f,
               "<text x='20' y='24' font-size='16'>grip: a hand grasping a 6 cm cube (the paper's Fig. 3), contacts "
               "and normals</text>\n");
  for (int v = 0; v < 2; ++v) {
    std::fprintf(f, "<text x='%.0f' y='60' text-anchor='middle'>%s</text>\n", cx[v],
                 v == 0 ? "front (x right, z up)" : "side (y right, z up)");
    const double s = scale * half;
    std::fprintf(f, "<rect x='%.1f' y='%.1f' width='%.1f' height='%.1f' fill='#eef' stroke='#446'/>\n", cx[v] - s,
                 cy - s, 2 * s, 2 * s);
    for (int k = 0; k < grip::hand_phalanx_count; ++k) {
      const grip::PhalanxCapsule<S>& cap = p.posture().phalanges[static_cast<std::size_t>(k)];
      std::fprintf(f,
                   "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='#bbb' stroke-opacity='0.6' "
                   "stroke-width='%.1f' stroke-linecap='round'/>\n",
                   X(v, cap.base), Y(cap.base), X(v, cap.tip), Y(cap.tip), 2 * scale * cap.radius);
    }
    for (int i = 0; i < p.hand_contacts().count; ++i) {
      const grip::HandContact<S>& hc = p.hand_contacts()[i];
      const V3 tip = hc.point + 0.02 * hc.normal;
      const char* col = colour[static_cast<int>(hc.finger)];
      std::fprintf(f, "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='%s' stroke-width='2'/>\n", X(v, hc.point),
                   Y(hc.point), X(v, tip), Y(tip), col);
      std::fprintf(f, "<circle cx='%.1f' cy='%.1f' r='4' fill='%s'/>\n", X(v, hc.point), Y(hc.point), col);
    }
  }
  const char* names[5] = {"thumb", "index", "long", "ring", "little"};
  for (int i = 0; i < 5; ++i)
    std::fprintf(f, "<text x='%d' y='450' fill='%s'>&#9679; %s</text>\n", 20 + 90 * i, colour[i], names[i]);
  std::fprintf(f, "</svg>\n");
  std::fclose(f);
}

void print_feel(const char* title, const grip::HapticFrame<S>& frame) {
  std::printf("%s: %s, %d contacts, %d sliding; what each phalanx feels (N):\n", title,
              frame.held ? "held" : "NOT held", frame.contacts, frame.sliding);
  for (int k = 0; k < grip::hand_phalanx_count; ++k) {
    const grip::PhalanxFeedback<S>& fb = frame.phalanges[static_cast<std::size_t>(k)];
    if (fb.in_contact)
      std::printf("  %-12s (%+6.2f %+6.2f %+6.2f)  |F| %5.2f\n", phalanx_names[k], fb.force.x(), fb.force.y(),
                  fb.force.z(), fb.force.norm());
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Set-up, once: the cube's distance field and octree (static storage: the octree is large).
  static const Cube cube(grip::make_box<S>(V3::Constant(half)));
  static grip::SphericalOctree<S, octree_capacity> octree;
  if (octree.build(cube, 4) != grip::Status::Ok) return 1;

  grip::HapticSettings<S> settings;
  settings.hand.thumb_cmc.y() = -0.005;  // the thumb opposes the long finger
  settings.hand.base[0].y() = -0.005;
  settings.contribution(grip::Finger::Thumb, grip::Phalanx::Proximal) = 0.5;  // a firm thumb
  settings.contribution(grip::Finger::Thumb, grip::Phalanx::Distal) = 0.7;
  settings.stiffness.fill(1.5e4);
  settings.device_limit.fill(30);
  Scene scene;
  scene.octree = &octree;
  scene.field = &cube;
  if (grip::add_box_points(scene.surface, V3::Constant(half)) != grip::Status::Ok) return 1;

  grip::RigidBody<S> body;  // the cube, on no table, in front of the hand
  body.mass = mass;
  body.principal_inertia = grip::solid_box_inertia<S>(mass, V3::Constant(half));
  body.position = V3(0.1, 0.2, 0.5);
  grip::WristState<S> wrist;  // palm over the cube's top face, fingers over its far edge
  const S l = settings.hand.hand_length;
  wrist.pose.translation() = body.position - V3(0.374 * l + 0.025, 0, -(half + 0.045 * l - 0.002));

  // The glove's joint angles: here the hand closes until each digit presses 2 mm in.
  const grip::ClosedHand<S> closed = grip::close_hand_in_scene<S>(scene, settings.hand, wrist.pose, body, 0.002);
  if (closed.status != grip::Status::Ok) return 1;

  Pipeline pipeline(settings, scene, body);
  grip::HapticFrame<S> frame;
  if (pipeline.step(wrist, closed.angles, frame) != grip::Status::Ok) return 1;
  std::printf("contacts (world, m; normal into the cube):\n");
  for (int i = 0; i < pipeline.hand_contacts().count; ++i) {
    const grip::HandContact<S>& c = pipeline.hand_contacts()[i];
    const V3 r = c.point - pipeline.object().position;
    std::printf("  %-12s depth %.2f mm  at (%+.3f %+.3f %+.3f) from the centre  normal (%+.2f %+.2f %+.2f)\n",
                phalanx_names[grip::phalanx_index(c.finger, c.phalanx)], 1e3 * c.depth, r.x(), r.y(), r.z(),
                c.normal.x(), c.normal.y(), c.normal.z());
  }
  print_feel("at rest", frame);
  bool held = frame.held;

  // Lift: the hand accelerates upwards at 4 m/s^2 for 0.15 s, then moves on at 0.6 m/s.
  const double z0 = pipeline.object().position.z(), wrist_z0 = wrist.pose.translation().z();
  for (int i = 0; i < 300; ++i) {
    wrist.linear_acceleration.z() = i < 150 ? 4.0 : 0.0;
    wrist.linear_velocity.z() += wrist.linear_acceleration.z() * settings.dt;
    wrist.pose.translation() += wrist.linear_velocity * settings.dt;
    if (pipeline.step(wrist, closed.angles, frame) != grip::Status::Ok) return 1;
    held = held && frame.held;
    if (i == 100) print_feel("lifting at 4 m/s^2", frame);
  }
  const double rise = pipeline.object().position.z() - z0, hand_rise = wrist.pose.translation().z() - wrist_z0;
  std::printf("after 0.3 s: the cube rose %.1f mm with the hand (%.1f mm), %s throughout\n", 1e3 * rise,
              1e3 * hand_rise, held ? "held" : "NOT held");

  const std::string dir = argc > 1 ? std::string(argv[1]) + "/" : std::string();
  write_svg(dir + "cube_grasp.svg", pipeline);
  std::printf("wrote %scube_grasp.svg\n", dir.c_str());
  return held && std::abs(rise - hand_rise) < 1e-6 && rise > 0.13 ? 0 : 2;
}
