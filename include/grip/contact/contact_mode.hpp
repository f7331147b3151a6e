#pragma once
/// \file
/// The mode of one contact under given forces: sticking, sliding or separating (eq. 4-5).

namespace grip {

/// What one contact does under the forces given to the monitor.
enum class ContactMode {
  Sticking,    ///< f_n > 0 and the force is inside its friction cone: the contact holds
  Sliding,     ///< f_n > 0 but the force is outside its cone: the finger slips on the object
  Separating,  ///< f_n = f.a <= 0: the finger would have to pull, so it leaves the object
};

/// A short English name of the mode ("sticking", "sliding", "separating").
constexpr const char* to_string(ContactMode m) {
  switch (m) {
    case ContactMode::Sticking: return "sticking";
    case ContactMode::Sliding: return "sliding";
    case ContactMode::Separating: return "separating";
  }
  return "unknown";
}

}  // namespace grip
