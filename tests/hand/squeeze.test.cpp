// Eq. 8 and the paper's Table 1.
#include <doctest/doctest.h>

#include <grip/hand/squeeze.hpp>

using namespace grip;

TEST_CASE("Table 1: the finger totals are the sums of their phalanges, as printed") {
  constexpr auto d = cylindrical_power_grip<double>();
  // Table 1's "Total Contribution" row, read from the paper.
  CHECK(d.finger_total(Finger::Index) == doctest::Approx(0.295));
  CHECK(d.finger_total(Finger::Long) == doctest::Approx(0.325));
  CHECK(d.finger_total(Finger::Ring) == doctest::Approx(0.226));
  CHECK(d.finger_total(Finger::Little) == doctest::Approx(0.154));
  // The four fingers share the whole grip.
  CHECK(d.finger_total(Finger::Index) + d.finger_total(Finger::Long) + d.finger_total(Finger::Ring) +
            d.finger_total(Finger::Little) ==
        doctest::Approx(1.0).epsilon(1e-9));
  CHECK(d(Finger::Long, Phalanx::Distal) == doctest::Approx(0.176));
  CHECK(d(Finger::Little, Phalanx::Middle) == doctest::Approx(0.011));
  // Table 1 has no thumb row: the thumb's shares are grip's choice (grasp_type.test.cpp).
  static_assert(cylindrical_power_grip<float>()(Finger::Index, Phalanx::Proximal) == 0.115f, "constexpr table");
}

TEST_CASE("eq. 8: s = d K dr, zero when not touching") {
  CHECK(squeeze(0.159, 2000.0, 0.003) == doctest::Approx(0.954));
  CHECK(squeeze(0.159f, 2000.0f, -0.001f) == 0.0f);
  CHECK(squeeze(0.5, 100.0, 0.0) == 0.0);
  CHECK(std::isnan(squeeze(0.5, 100.0, std::numeric_limits<double>::quiet_NaN())));
}
