// A session's result as diff_drive_controller parameters (DESIGN "ROS robots"; docs/ros.md):
// OUT/diff_drive_controller.yaml, a snippet for the owner's controller configuration. For a
// ROSArduinoBridge robot (nothing is written to it) the multipliers carry the calibration; for an
// odocal robot, whose `e` counts already carry its wheels in force, they are 1.

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "model_in_force.hpp"
#include "odocal/host/bridge_console.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/ros2_yaml.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

/// The covariances' conditions: the twist at 0.2 m/s (as `odocal ros2` by default), the pose
/// after 1 m straight; the controller's velocity estimate from the session's flags.
constexpr double kCovarianceSpeedMps = 0.2;
constexpr double kCovariancePoseDistanceM = 1.0;

/// The fit's `noise` object in a procedure's result (`fit`: the result's own; `auto`: its fit's).
const nlohmann::json* noise_of(const nlohmann::json& result) {
  const nlohmann::json* holder = &result;
  if (result.contains("fit") && result["fit"].is_object()) {
    holder = &result["fit"];
  }
  if (!holder->contains("noise") || !(*holder)["noise"].is_object()) {
    return nullptr;
  }
  const nlohmann::json& noise = (*holder)["noise"];
  if (!noise.contains("k_l") || !noise.contains("k_r") || !noise["k_l"].is_number() ||
      !noise["k_r"].is_number()) {
    return nullptr;
  }
  return &noise;
}

/// The covariance lines of the YAML (and `ros`'s diagonals) from the result's noise, with their
/// comment in `text`; "" when the result has no noise estimate.
std::string covariance_lines(const Context& c, const nlohmann::json& result, double wheelbase_mm,
                             std::string& text, nlohmann::json& ros) {
  const nlohmann::json* noise = noise_of(result);
  if (noise == nullptr) {
    text += "# no covariances: the result has no noise estimate\n";
    return "";
  }
  WheelNoise k{(*noise)["k_l"].get<double>(), (*noise)["k_r"].get<double>()};
  // A wheel whose drift the runs do not resolve above 0 gets its interval's upper end: a zero
  // covariance would tell ROS (robot_localization, a planner) that its odometry never drifts.
  std::string bounded;
  for (const char* key : {"k_l", "k_r"}) {
    double& value = key[2] == 'l' ? k.k_l : k.k_r;
    const nlohmann::json ci =
        noise->contains("ci") ? (*noise)["ci"].value(key, nlohmann::json()) : nlohmann::json();
    if (value <= 0.0 && ci.is_array() && ci.size() == 2u && ci[1].is_number()) {
      value = ci[1].get<double>();
      bounded += std::string(bounded.empty() ? "" : ", ") + key;
    }
  }
  if (!bounded.empty()) {
    text += "# " + bounded +
            ": not resolved above 0 by these runs; the upper end of its 95 % interval is used "
            "(a conservative covariance)\n";
  }
  const RosVelocityEstimate& estimate = c.options.ros_velocity;
  const Ros2Covariance cov =
      ros2_covariance(k, wheelbase_mm, kCovarianceSpeedMps, estimate, kCovariancePoseDistanceM);
  text += ros2_covariance_note(k, kCovariancePoseDistanceM, kCovarianceSpeedMps, estimate);
  ros["pose_covariance_diagonal"] = cov.pose;
  ros["twist_covariance_diagonal"] = cov.twist;
  ros["ros_update_rate_hz"] = estimate.update_rate_hz;
  ros["ros_velocity_window"] = estimate.window;
  return fmt::format("    pose_covariance_diagonal: {}\n    twist_covariance_diagonal: {}\n",
                     yaml_list(cov.pose), yaml_list(cov.twist));
}

}  // namespace

RosGeometry ros_geometry_for_bridge(const Factors& f, const BridgeNominal& nominal) {
  // The geometry the host drove with at the end: the fitted one (F_lat, F_lon folded in).
  const drive::model::Geometry<double> g = geometry_in_force(f, nominal.wheel_diameter_mm);
  return RosGeometry{nominal.wheelbase_mm / 1000.0, nominal.wheel_diameter_mm / 2000.0,
                     g.wheelbase / nominal.wheelbase_mm,
                     g.left_diameter / nominal.wheel_diameter_mm,
                     g.right_diameter / nominal.wheel_diameter_mm};
}

RosGeometry ros_geometry_for_odocal(const Factors& f, double wheel_diameter_mm) {
  // `e` reports each wheel's counts times its diameter in force over the nominal one, and `m`
  // reads wheel speeds about the wheelbase in force (core/src/console/commands_bridge.cpp): the
  // nominal wheel and that wheelbase, no multiplier.
  const drive::model::Geometry<double> g = geometry_in_force(f, wheel_diameter_mm);
  return RosGeometry{g.wheelbase / 1000.0, wheel_diameter_mm / 2000.0, 1.0, 1.0, 1.0};
}

void write_ros_yaml(Context& c, Outcome& outcome, bool saved) {
  const Factors f = c.factors();
  const BridgeConsole* bridge = c.options.bridge;
  const double wheel_diameter_mm =
      bridge != nullptr ? bridge->nominal().wheel_diameter_mm : c.get(ParamId::wheel_diameter_mm);
  const drive::model::Geometry<double> g = geometry_in_force(f, wheel_diameter_mm);
  const RosGeometry ros_geometry = bridge != nullptr
                                       ? ros_geometry_for_bridge(f, bridge->nominal())
                                       : ros_geometry_for_odocal(f, wheel_diameter_mm);
  std::string text = fmt::format(
      "# ROS 2 diff_drive_controller parameters from odocal session {} ({} runs, date {})\n"
      "# A snippet: merge these keys into the diff_drive_controller section of the robot's\n"
      "# controller configuration, keeping its own controller name (docs/ros.md has a whole one)\n",
      to_string(c.options.procedure), c.runs.size(), c.date());
  if (bridge != nullptr) {
    const BridgeNominal& nominal = bridge->nominal();
    text += fmt::format(
        "# robot: {}; told wheel diameter {} mm, wheelbase {} mm, {} counts per wheel turn\n"
        "# calibrated: left wheel {:.4f} mm, right wheel {:.4f} mm, wheelbase {:.4f} mm (turns "
        "in place)\n",
        bridge->name(), nominal.wheel_diameter_mm, nominal.wheelbase_mm, nominal.counts_per_rev,
        g.left_diameter, g.right_diameter, g.wheelbase);
  } else {
    text += fmt::format(
        "# robot: odocal firmware, {}; its factors in force: left wheel {:.4f} mm, right wheel "
        "{:.4f} mm, wheelbase {:.4f} mm (turns in place)\n"
        "# its `e` counts carry the wheels in force, so the multipliers are 1.0 and the wheel "
        "separation is the wheelbase in force\n",
        outcome.applied && !saved ? "NOT saved on the robot (a restart loses them)"
                                  : "as saved on the robot",
        g.left_diameter, g.right_diameter, g.wheelbase);
  }
  if (g.wheelbase_arc != 0.0 && std::fabs(g.wheelbase_arc - g.wheelbase) > 1e-9) {
    text += fmt::format(
        "# the robot turns about another wheelbase on arcs ({:.4f} mm): diff_drive_controller "
        "has one wheel separation, the one for turns in place is written\n",
        g.wheelbase_arc);
  }
  nlohmann::json ros = {{"file", "diff_drive_controller.yaml"},
                        {"wheel_separation", ros_geometry.wheel_separation_m},
                        {"wheel_radius", ros_geometry.wheel_radius_m},
                        {"wheel_separation_multiplier", ros_geometry.separation_multiplier},
                        {"left_wheel_radius_multiplier", ros_geometry.left_multiplier},
                        {"right_wheel_radius_multiplier", ros_geometry.right_multiplier}};
  const std::string covariance = covariance_lines(c, outcome.result, g.wheelbase, text, ros);
  text += fmt::format(
      "diff_drive_controller:\n  ros__parameters:\n    wheel_separation: {}\n    wheel_radius: "
      "{}\n    wheel_separation_multiplier: {}\n    left_wheel_radius_multiplier: {}\n    "
      "right_wheel_radius_multiplier: {}\n",
      yaml_double(ros_geometry.wheel_separation_m), yaml_double(ros_geometry.wheel_radius_m),
      yaml_double(ros_geometry.separation_multiplier), yaml_double(ros_geometry.left_multiplier),
      yaml_double(ros_geometry.right_multiplier));
  text += covariance;
  c.write_file("diff_drive_controller.yaml", text);
  outcome.result["ros"] = ros;
  c.log << "Wrote " << c.options.out_dir << "/diff_drive_controller.yaml"
        << (bridge != nullptr ? " (nothing was written to the robot)" : "")
        << ": merge its ros__parameters into the robot's diff_drive_controller configuration "
           "(docs/ros.md).\n";
}

}  // namespace odocal::host::session
