// `odocal session`'s flags checked against each other: --procedure and --runs, and --protocol
// ros-arduino-bridge with the nominal geometry such a session needs (docs/ros.md).

#include "session_flags.hpp"

#include <utility>

#include "odocal/host/csv.hpp"
#include "odocal/host/robot_file.hpp"

namespace odocal::host {

Procedure procedure_of(const std::string& name) {
  if (name == "umbmark") {
    return Procedure::umbmark;
  }
  if (name == "lateral") {
    return Procedure::lateral;
  }
  if (name == "fit") {
    return Procedure::fit;
  }
  if (name == "extended") {
    return Procedure::extended;
  }
  if (name == "selftest") {
    return Procedure::selftest;
  }
  if (name == "auto") {
    return Procedure::automatic;
  }
  return Procedure::verify;
}

/// --runs bounds per procedure: UMBmark runs per direction (the robot keeps 16 per direction,
/// the solver needs 2); lateral straight trials (the bootstrap needs 5 rows with the arcs);
/// fit runs; verify runs per scenario.
void check_runs(Procedure procedure, std::uint64_t runs) {
  std::uint64_t lo = 1;
  std::uint64_t hi = 32;
  switch (procedure) {
    case Procedure::umbmark:
      lo = 2;
      hi = 16;
      break;
    case Procedure::lateral:
      lo = 2;
      hi = 28;
      break;
    case Procedure::fit:
      lo = 3;
      hi = 30;
      break;
    case Procedure::verify:
    case Procedure::selftest:
    case Procedure::automatic:
      lo = 1;
      hi = 16;
      break;
    case Procedure::extended:
      lo = 2;  // the figure's intervals need 2 runs per direction and floor
      hi = 16;
      break;
  }
  if (runs < lo || runs > hi) {
    throw InputError("--runs", 0, "",
                     "must be a whole number from " + std::to_string(lo) + " to " +
                         std::to_string(hi) + " for --procedure " + to_string(procedure) +
                         ", got " + std::to_string(runs));
  }
}

/// --protocol and the nominal geometry it needs: a ROSArduinoBridge robot knows nothing of its
/// geometry, so the owner gives it (with --sim the robot file's nominal keys stand in).
void check_bridge_flags(const BridgeFlags& f, Procedure procedure) {
  const bool bridge = f.protocol == kBridgeProtocol;
  const std::pair<const char*, const std::optional<double>*> geometry[] = {
      {"--wheel-diameter-mm", &f.wheel_diameter_mm},
      {"--wheelbase-mm", &f.wheelbase_mm},
      {"--counts-per-rev", &f.counts_per_rev}};
  for (const auto& [flag, value] : geometry) {
    if (!bridge && value->has_value()) {
      throw InputError(flag, 0, "",
                       "only with --protocol ros-arduino-bridge (an odocal robot knows its own "
                       "geometry: `set` it on the console)");
    }
    if (bridge && f.sim_robot.empty() && !value->has_value()) {
      throw InputError(flag, 0, "",
                       "required with --protocol ros-arduino-bridge and --port: the robot's "
                       "nominal geometry (ROSArduinoBridge does not know it)");
    }
  }
  if (!bridge) {
    return;
  }
  if (procedure != Procedure::automatic && procedure != Procedure::fit &&
      procedure != Procedure::verify && procedure != Procedure::selftest) {
    throw InputError("--procedure", 0, "",
                     std::string("--protocol ros-arduino-bridge: auto, fit, verify or selftest "
                                 "(they measure the geometry diff_drive_controller takes); ") +
                         to_string(procedure) + " is for odocal firmware");
  }
  if (!f.store.empty()) {
    throw InputError("--store", 0, "",
                     "a ROSArduinoBridge robot keeps no parameters: leave --store out");
  }
}

/// The nominal geometry of a ROSArduinoBridge robot: the flags, with --sim the robot file's
/// nominal keys where a flag is not given.
BridgeNominal bridge_nominal(const BridgeFlags& f) {
  RobotSpec spec = default_robot();
  std::string error;
  if (!f.sim_robot.empty() && !load_robot_file(f.sim_robot, spec, error)) {
    throw InputError(f.sim_robot, 0, "", error);
  }
  BridgeNominal n;
  n.wheel_diameter_mm = f.wheel_diameter_mm.value_or(spec.nominal.wheel_diameter_mm);
  n.wheelbase_mm = f.wheelbase_mm.value_or(spec.nominal.wheelbase_mm);
  n.counts_per_rev = f.counts_per_rev.value_or(spec.nominal.counts_per_rev);
  return n;
}

}  // namespace odocal::host
