// The grasp types' contribution tables: the shares' convention, the statics of the pinches,
// and the cylindrical power grip against the paper's Table 1 typed from the paper.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <initializer_list>

#include <grip/hand/grasp_type.hpp>

using namespace grip;

namespace {

constexpr GraspType all_types[] = {GraspType::CylindricalPower, GraspType::SphericalPower, GraspType::TipPinch,
                                   GraspType::Tripod, GraspType::LateralPinch};

/// The sum of the twelve finger shares, index to little, added here one by one.
template <class S>
double four_fingers(const ContributionTable<S>& t) {
  double sum = 0;
  for (int f = 1; f < 5; ++f)
    for (int p = 0; p < 3; ++p) sum += double(t.share[f][p]);
  return sum;
}

}  // namespace

TEST_CASE("grasp types: shares >= 0, the four fingers sum to 1, the thumb has no middle phalanx") {
  static_assert(sizeof(all_types) / sizeof(all_types[0]) == grasp_type_count, "every grasp type listed");
  for (GraspType g : all_types) {
    CAPTURE(to_string(g));
    const auto t = contribution_table<double>(g);
    for (int f = 0; f < 5; ++f)
      for (int p = 0; p < 3; ++p) CHECK(t.share[f][p] >= 0.0);
    CHECK(t.palm >= 0.0);
    CHECK(t(Finger::Thumb, Phalanx::Middle) == 0.0);
    // The convention of docs/hand.md: shares are fractions of the four fingers' summed force,
    // rounded to three decimals (at most 0.002 off over twelve shares).
    CHECK(std::abs(four_fingers(t) - 1.0) <= 0.002);
    CHECK(t.four_finger_total() == doctest::Approx(four_fingers(t)).epsilon(1e-12));
    CHECK(t.total() == doctest::Approx(four_fingers(t) + t.share[0][0] + t.share[0][2] + t.palm).epsilon(1e-12));
    // A grasp needs something to oppose the fingers.
    CHECK(t.finger_total(Finger::Thumb) + t.palm > 0.5);
  }
}

TEST_CASE("cylindrical power: the paper's Table 1 for the fingers, grip's thumb and palm") {
  // Table 1, typed from the paper: index, long, ring, little; proximal, middle, distal.
  const double table1[4][3] = {
      {0.115, 0.021, 0.159}, {0.126, 0.023, 0.176}, {0.088, 0.016, 0.122}, {0.060, 0.011, 0.083}};
  const auto t = contribution_table<double>(GraspType::CylindricalPower);
  for (int f = 1; f < 5; ++f)
    for (int p = 0; p < 3; ++p) CHECK(t.share[f][p] == doctest::Approx(table1[f - 1][p]).epsilon(1e-12));
  // grip's choice (docs/hand.md): thumb proximal 0.15, distal 0.25, palm 0.40.
  CHECK(t(Finger::Thumb, Phalanx::Proximal) == doctest::Approx(0.15).epsilon(1e-12));
  CHECK(t(Finger::Thumb, Phalanx::Distal) == doctest::Approx(0.25).epsilon(1e-12));
  CHECK(t.palm == doctest::Approx(0.40).epsilon(1e-12));
  CHECK(t.total() == doctest::Approx(1.8).epsilon(1e-12));
  // cylindrical_power_grip() is the same table.
  const auto c = cylindrical_power_grip<double>();
  CHECK(std::memcmp(&c, &t, sizeof t) == 0);
}

TEST_CASE("pinches: the pads that oppose each other carry equal shares, the rest nothing") {
  const auto tip = contribution_table<double>(GraspType::TipPinch);
  CHECK(tip(Finger::Thumb, Phalanx::Distal) == 1.0);
  CHECK(tip(Finger::Index, Phalanx::Distal) == tip(Finger::Thumb, Phalanx::Distal));
  CHECK(tip.total() == 2.0);  // nothing but the two pads

  // Tripod: the thumb balances the two finger pads, which split their force evenly.
  const auto tri = contribution_table<double>(GraspType::Tripod);
  CHECK(tri(Finger::Index, Phalanx::Distal) == tri(Finger::Long, Phalanx::Distal));
  CHECK(tri(Finger::Thumb, Phalanx::Distal) ==
        tri(Finger::Index, Phalanx::Distal) + tri(Finger::Long, Phalanx::Distal));
  CHECK(tri.total() == 2.0);

  // Lateral (key) pinch: the thumb's pad against the index's middle phalanx.
  const auto key = contribution_table<double>(GraspType::LateralPinch);
  CHECK(key(Finger::Index, Phalanx::Middle) == 1.0);
  CHECK(key(Finger::Thumb, Phalanx::Distal) == key(Finger::Index, Phalanx::Middle));
  CHECK(key.total() == 2.0);

  for (const auto& t : {tip, tri, key}) {
    CHECK(t.palm == 0.0);
    CHECK(t.finger_total(Finger::Ring) == 0.0);
    CHECK(t.finger_total(Finger::Little) == 0.0);
  }
}

TEST_CASE("spherical power: finger shares as in the circular grip, split like Table 1") {
  const auto s = contribution_table<double>(GraspType::SphericalPower);
  // Kinoshita et al. (1996): the index carries the least, ring and little the most.
  CHECK(s.finger_total(Finger::Index) < s.finger_total(Finger::Long));
  CHECK(s.finger_total(Finger::Long) < s.finger_total(Finger::Ring));
  // Five-digit shares 0.38, 0.11, 0.13, 0.19, 0.19 over the fingers' 0.62 (docs/hand.md).
  CHECK(s.finger_total(Finger::Thumb) == doctest::Approx(0.38 / 0.62).epsilon(1e-3));
  CHECK(s.finger_total(Finger::Ring) == doctest::Approx(0.19 / 0.62).epsilon(2e-3));
  // Pylatiuk et al. (2006): thumb, ring and little carry more than 71 % of the five digits.
  const double five = s.four_finger_total() + s.finger_total(Finger::Thumb);
  CHECK((s.finger_total(Finger::Thumb) + s.finger_total(Finger::Ring) + s.finger_total(Finger::Little)) / five > 0.71);
  // Within each finger, Table 1's split: the distal phalanx most, the middle least.
  const auto c = cylindrical_power_grip<double>();
  for (int f = 1; f < 5; ++f) {
    const Finger fi = static_cast<Finger>(f);
    for (int p = 0; p < 3; ++p)
      CHECK(s.share[f][p] / s.finger_total(fi) == doctest::Approx(c.share[f][p] / c.finger_total(fi)).epsilon(0.05));
  }
}

TEST_CASE("grasp types: each has a table of its own and a name") {
  for (int i = 0; i < grasp_type_count; ++i)
    for (int j = i + 1; j < grasp_type_count; ++j) {
      const auto a = contribution_table<double>(all_types[i]);
      const auto b = contribution_table<double>(all_types[j]);
      CAPTURE(to_string(all_types[i]));
      CAPTURE(to_string(all_types[j]));
      CHECK(std::memcmp(&a, &b, sizeof a) != 0);
      CHECK(std::strcmp(to_string(all_types[i]), to_string(all_types[j])) != 0);
    }
  CHECK(std::strcmp(to_string(GraspType::CylindricalPower), "cylindrical power") == 0);
  CHECK(std::strcmp(to_string(GraspType::SphericalPower), "spherical power") == 0);
  CHECK(std::strcmp(to_string(GraspType::TipPinch), "tip pinch") == 0);
  CHECK(std::strcmp(to_string(GraspType::Tripod), "tripod") == 0);
  CHECK(std::strcmp(to_string(GraspType::LateralPinch), "lateral pinch") == 0);
  CHECK(std::strcmp(to_string(static_cast<GraspType>(99)), "unknown") == 0);
  // An unknown value falls back to the cylindrical power grip.
  const auto fallback = contribution_table<double>(static_cast<GraspType>(99));
  const auto c = cylindrical_power_grip<double>();
  CHECK(std::memcmp(&fallback, &c, sizeof c) == 0);
}

TEST_CASE("grasp types: constexpr, in float too, and settable through operator()") {
  static_assert(contribution_table<float>(GraspType::TipPinch)(Finger::Index, Phalanx::Distal) == 1.0f, "constexpr");
  static_assert(contribution_table<float>(GraspType::SphericalPower).palm == 0.4f, "constexpr");
  static_assert(cylindrical_power_grip<float>().palm == 0.4f, "constexpr");
  auto t = contribution_table<float>(GraspType::Tripod);
  t(Finger::Thumb, Phalanx::Distal) = 0.8f;
  CHECK(t.share[0][2] == 0.8f);
  CHECK(t.finger_total(Finger::Thumb) == 0.8f);
}
