// `odocal session`'s flags checked against each other: --procedure and --runs, and --protocol
// ros-arduino-bridge with the nominal geometry such a session needs (docs/ros.md).

#include "session_flags.hpp"

#include <utility>

#include <CLI/CLI.hpp>

#include "odocal/host/csv.hpp"
#include "odocal/host/robot_file.hpp"
#include "odocal/toolkit/cli_checks.hpp"

namespace odocal::host {

Procedure procedure_of(const std::string& name, const std::string& where, const std::string& key) {
  const std::optional<Procedure> procedure = procedure_named(name);
  if (!procedure) {
    throw InputError(where, 0, key, "no procedure '" + name + "' (" + procedure_names() + ")");
  }
  return *procedure;
}

std::vector<std::string> procedure_words() {
  std::vector<std::string> names;
  for (const ProcedureInfo& p : procedures) {
    names.emplace_back(p.name);
  }
  return names;
}

/// --runs within the procedure's bounds (`procedures`, session.hpp).
void check_runs(Procedure procedure, std::uint64_t runs) {
  const ProcedureInfo& p = info_of(procedure);
  if (runs < p.runs_lo || runs > p.runs_hi) {
    throw InputError("--runs", 0, "",
                     "must be a whole number from " + std::to_string(p.runs_lo) + " to " +
                         std::to_string(p.runs_hi) + " for --procedure " + p.name + ", got " +
                         std::to_string(runs));
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

namespace {
constexpr const char* kRosRateFlag = "--ros-update-rate-hz";
constexpr const char* kRosWindowFlag = "--ros-velocity-window";
}  // namespace

void add_ros_flags(CLI::App& cmd, RosFlags& flags) {
  const RosVelocityEstimate defaults;
  cmd.add_option(kRosRateFlag, flags.update_rate_hz,
                 "the controller manager's update_rate, Hz (default " +
                     std::to_string(static_cast<int>(defaults.update_rate_hz)) +
                     "): diff_drive_controller estimates its velocity at every update, for the "
                     "twist covariance of diff_drive_controller.yaml (docs/ros.md)")
      ->check(toolkit::range_check(0.1, 10000.0, "Hz"));
  cmd.add_option(
         kRosWindowFlag, flags.window,
         "diff_drive_controller's velocity_rolling_window_size: updates averaged (default " +
             std::to_string(defaults.window) + ")")
      ->check(toolkit::whole_check(1u, 100000u));
}

RosVelocityEstimate ros_estimate(const RosFlags& flags) {
  RosVelocityEstimate estimate;
  estimate.update_rate_hz = flags.update_rate_hz.value_or(estimate.update_rate_hz);
  estimate.window = static_cast<std::size_t>(flags.window.value_or(estimate.window));
  return estimate;
}

void record_ros_flags(const RosFlags& flags, nlohmann::json& recorded) {
  const RosVelocityEstimate estimate = ros_estimate(flags);
  recorded["ros_update_rate_hz"] = estimate.update_rate_hz;
  recorded["ros_velocity_window"] = estimate.window;
}

void resume_ros_flags(const nlohmann::json& options, const std::string& file, const CLI::App& cmd,
                      RosFlags& flags) {
  // Sessions from before these flags ran with the controller's defaults.
  const RosVelocityEstimate given = ros_estimate(flags);
  RosVelocityEstimate recorded;
  if (options.contains("ros_update_rate_hz") && options["ros_update_rate_hz"].is_number()) {
    recorded.update_rate_hz = options["ros_update_rate_hz"].get<double>();
  }
  if (options.contains("ros_velocity_window") &&
      options["ros_velocity_window"].is_number_unsigned()) {
    recorded.window = options["ros_velocity_window"].get<std::size_t>();
  }
  const auto refuse = [&](const char* flag, const std::string& was, const std::string& now) {
    throw InputError(flag, 0, "",
                     "conflicts with the interrupted session in " + file + " (it ran with " + was +
                         ", given " + now + "); leave it out to resume");
  };
  if (cmd.count(kRosRateFlag) != 0u && given.update_rate_hz != recorded.update_rate_hz) {
    refuse(kRosRateFlag, std::to_string(recorded.update_rate_hz),
           std::to_string(given.update_rate_hz));
  }
  if (cmd.count(kRosWindowFlag) != 0u && given.window != recorded.window) {
    refuse(kRosWindowFlag, std::to_string(recorded.window), std::to_string(given.window));
  }
  flags.update_rate_hz = recorded.update_rate_hz;
  flags.window = recorded.window;
}

std::uint64_t count_in(const nlohmann::json& options, const char* key, const std::string& file) {
  const nlohmann::json& v = options.at(key);
  if (v.is_number_unsigned()) {
    return v.get<std::uint64_t>();
  }
  const double d = v.is_number() ? v.get<double>() : -1.0;
  if (v.is_number_float() && d >= 0.0 && d == std::floor(d) && d < 18446744073709551616.0) {
    return static_cast<std::uint64_t>(d);
  }
  throw InputError(file, 0, std::string("options.") + key,
                   "not a whole number from 0 within 64 bits");
}

nlohmann::json interrupted_session(const std::string& file) {
  nlohmann::json session = nlohmann::json::parse(read_text_file(file), nullptr, false);
  if (!session.is_object() || !session.contains("options") || !session["options"].is_object()) {
    throw InputError(file, 0, "", "not a session.json written by odocal session");
  }
  if (session.contains("complete") && !session["complete"].is_boolean()) {
    throw InputError(file, 0, "complete", "not true or false");
  }
  if (session.value("complete", false)) {
    throw InputError(file, 0, "complete", "this session is complete: nothing to resume");
  }
  return session;
}

}  // namespace odocal::host
