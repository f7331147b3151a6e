#pragma once
/// \file
/// grip's version: the one place it is written. CMake reads it from here (project(VERSION)),
/// and so do the package files it generates (gripConfigVersion.cmake, grip.pc).

/// Major version: changes that break the API.
#define GRIP_VERSION_MAJOR 0
/// Minor version: additions; before 1.0 also changes that break the API (see CHANGELOG.md).
#define GRIP_VERSION_MINOR 2
/// Patch version: fixes only.
#define GRIP_VERSION_PATCH 0

/// The version as one integer, major * 10000 + minor * 100 + patch (0.2.0 is 200), for
/// `#if GRIP_VERSION >= 200`.
#define GRIP_VERSION (GRIP_VERSION_MAJOR * 10000 + GRIP_VERSION_MINOR * 100 + GRIP_VERSION_PATCH)

/// The version as a string literal, "major.minor.patch".
#define GRIP_VERSION_STRING "0.2.0"

namespace grip {

/// The version of the headers a translation unit was compiled with, as plain values.
struct Version {
  int major;  ///< GRIP_VERSION_MAJOR
  int minor;  ///< GRIP_VERSION_MINOR
  int patch;  ///< GRIP_VERSION_PATCH
};

/// The version of these headers.
constexpr Version version() { return Version{GRIP_VERSION_MAJOR, GRIP_VERSION_MINOR, GRIP_VERSION_PATCH}; }

}  // namespace grip
