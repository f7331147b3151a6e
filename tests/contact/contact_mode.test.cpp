// contact/contact_mode.hpp: the modes' names, as the documentation spells them.
#include <doctest/doctest.h>

#include <string>

#include <grip/contact/contact_mode.hpp>

TEST_CASE("contact modes have the names of eq. 4-5's three cases") {
  CHECK(std::string(grip::to_string(grip::ContactMode::Sticking)) == "sticking");
  CHECK(std::string(grip::to_string(grip::ContactMode::Sliding)) == "sliding");
  CHECK(std::string(grip::to_string(grip::ContactMode::Separating)) == "separating");
  // A value outside the enumeration (from a corrupted byte, say) gets a name too, not a crash.
  CHECK(std::string(grip::to_string(static_cast<grip::ContactMode>(7))) == "unknown");
}
