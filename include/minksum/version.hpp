// minksum's version (CMakeLists.txt reads it from here: one place).
#pragma once

#define MINKSUM_VERSION_MAJOR 0  ///< incompatible API changes
#define MINKSUM_VERSION_MINOR 2  ///< added functionality, compatible
#define MINKSUM_VERSION_PATCH 0  ///< fixes
/// The version as one number: 10000 major + 100 minor + patch.
#define MINKSUM_VERSION (MINKSUM_VERSION_MAJOR * 10000 + MINKSUM_VERSION_MINOR * 100 + MINKSUM_VERSION_PATCH)
/// The version as a string literal, "major.minor.patch".
#define MINKSUM_VERSION_STRING "0.2.0"
