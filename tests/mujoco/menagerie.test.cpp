// MuJoCo Menagerie's Shadow and Allegro hands (not the project's: read from ../shared/models
// next to the repository, else the test prints "[grip skipped]" and CTest reports it skipped)
// load and step in the MuJoCo grip is built against, and the adapter follows them while their
// fingers close on the scene's object: every named body is found, every state read, every
// solve ends with a decided status. The body maps are the Python package's (grip/mujoco.py).
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <grip/mujoco/adapter.hpp>
#include <grip/solve/solve_constrained.hpp>

#include "mujoco/mujoco_support.hpp"

using namespace grip;

namespace {

struct MenagerieHand {
  const char* file;                    // below ../shared/models
  std::vector<mujoco::BodyName> map;   // MuJoCo body name -> grip body
  std::vector<std::string> actuators;  // the ones that close the hand
};

// Shadow Hand (right: rh_*): each finger's knuckle and proximal link as grip's proximal
// phalanx, middle and distal as theirs; the little finger's metacarpal (18); the palm (16);
// the thumb's base, proximal link and hub as its metacarpal (14), middle and distal as its
// phalanges (0, 1).
MenagerieHand shadow_right() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const char* f : {"ff", "mf", "rf", "lf"})
      for (const char* link : {"knuckle", "proximal", "middle", "distal"}) n.push_back(std::string("rh_") + f + link);
    for (const char* link : {"lfmetacarpal", "palm", "thbase", "thproximal", "thhub", "thmiddle", "thdistal"})
      n.push_back(std::string("rh_") + link);
    return n;
  }();
  MenagerieHand h{"shadow_hand/scene_right.xml", {}, {}};
  const int finger_bodies[4][3] = {{2, 3, 4}, {5, 6, 7}, {8, 9, 10}, {11, 12, 13}};
  for (int f = 0; f < 4; ++f)
    for (int link = 0; link < 4; ++link)
      h.map.push_back(
          {names[static_cast<std::size_t>(4 * f + link)].c_str(), finger_bodies[f][link == 0 ? 0 : link - 1]});
  const int rest[7] = {18, 16, 14, 14, 14, 0, 1};
  for (int k = 0; k < 7; ++k) h.map.push_back({names[static_cast<std::size_t>(16 + k)].c_str(), rest[k]});
  for (const char* f : {"FF", "MF", "RF", "LF"})
    for (const char* j : {"3", "0"}) h.actuators.push_back(std::string("rh_A_") + f + "J" + j);
  for (const char* j : {"5", "4", "1"}) h.actuators.push_back(std::string("rh_A_THJ") + j);
  return h;
}

// Allegro Hand (right): index (ff), long (mf) and ring (rf) fingers, base and proximal link
// as grip's proximal phalanx, medial as the middle, distal and tip as the distal; the thumb's
// base and proximal link as its metacarpal (14), medial and distal (with its tip) as its
// phalanges (0, 1); the palm (16).
MenagerieHand allegro_right() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const char* f : {"ff", "mf", "rf", "th"})
      for (const char* link : {"_base", "_proximal", "_medial", "_distal", "_tip"}) n.push_back(std::string(f) + link);
    return n;
  }();
  MenagerieHand h{"wonik_allegro/scene_right.xml", {{"palm", 16}}, {}};
  const int bodies[4][5] = {{2, 2, 3, 4, 4}, {5, 5, 6, 7, 7}, {8, 8, 9, 10, 10}, {14, 14, 0, 1, 1}};
  for (int f = 0; f < 4; ++f)
    for (int link = 0; link < 5; ++link)
      h.map.push_back({names[static_cast<std::size_t>(5 * f + link)].c_str(), bodies[f][link]});
  for (const char* f : {"ff", "mf", "rf"})
    for (const char* j : {"1", "2", "3"}) h.actuators.push_back(std::string(f) + "a" + j);
  for (const char* j : {"0", "2", "3"}) h.actuators.push_back(std::string("tha") + j);
  return h;
}

const std::filesystem::path models =
    std::filesystem::path(GRIP_TEST_DATA_DIR) / ".." / ".." / ".." / "shared" / "models";

}  // namespace

TEST_CASE("mujoco menagerie: the Shadow and Allegro hands close on their object, the adapter follows") {
  for (const MenagerieHand& hand : {shadow_right(), allegro_right()}) {
    CAPTURE(hand.file);
    const std::filesystem::path path = models / hand.file;
    if (!std::filesystem::is_regular_file(path)) {
      std::printf("[grip skipped] %s is absent (MuJoCo Menagerie's models, next to the repository)\n",
                  path.string().c_str());
      continue;
    }
    char error[1000] = "";
    grip_test::ModelPtr m(mj_loadXML(path.string().c_str(), nullptr, error, sizeof error));
    REQUIRE_MESSAGE(m, error);
    grip_test::DataPtr d(mj_makeData(m.get()));
    mujoco::Adapter<HardFinger, double, 64> a;
    REQUIRE(a.bind(m.get(), "object", hand.map.data(), static_cast<int>(hand.map.size())) == Status::Ok);
    std::vector<int> ids;
    for (const std::string& n : hand.actuators) {
      ids.push_back(mj_name2id(m.get(), mjOBJ_ACTUATOR, n.c_str()));
      REQUIRE(ids.back() >= 0);
    }
    int contacts = 0, decided = 0;
    FeltForces<double> felt;
    const int steps = 400;
    for (int step = 0; step < steps; ++step) {
      const double ramp = std::min(1.0, step / (steps / 2.0));
      for (int id : ids) d->ctrl[id] = ramp * m->actuator_ctrlrange[2 * id + 1];
      mj_step(m.get(), d.get());
      if (step % 10 != 9) continue;
      REQUIRE(a.update(m.get(), d.get()) == Status::Ok);
      const Status st = a.solve([](const auto& g, const auto& w) { return solve_constrained(g, w); }, felt);
      CHECK((st == Status::Ok || st == Status::Singular || st == Status::Infeasible));
      decided += st == Status::Ok || st == Status::Infeasible ? 1 : 0;
      contacts += a.grasp().size();
      for (int k = 0; k < hand_body_count; ++k) CHECK(felt.force[static_cast<std::size_t>(k)].allFinite());
    }
    CHECK(contacts > 0);  // the object lies on the hand
    CHECK(decided > 0);
  }
}
