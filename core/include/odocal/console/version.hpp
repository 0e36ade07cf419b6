#pragma once
/// @file
/// Versions the console reports (`version`).

namespace odocal::console {

/// The project version (CMake `project(odocal VERSION ...)`); a test keeps the two equal.
/// A build may override it with -DODOCAL_VERSION_STRING="x.y.z".
#ifdef ODOCAL_VERSION_STRING
inline constexpr const char* project_version = ODOCAL_VERSION_STRING;
#else
inline constexpr const char* project_version = "0.1.0";
#endif

/// Console protocol revision: bumped when a reply format or error code changes meaning.
inline constexpr unsigned protocol_version = 1u;

}  // namespace odocal::console
