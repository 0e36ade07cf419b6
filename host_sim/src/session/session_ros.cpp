// A ROSArduinoBridge robot's calibration as diff_drive_controller parameters (DESIGN "ROS
// robots"; docs/ros.md): nothing is written to such a robot, the result goes to
// OUT/diff_drive_controller.yaml for the owner's controller configuration.

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

}  // namespace

void write_ros_yaml(Context& c, Outcome& outcome) {
  const BridgeNominal& nominal = c.options.bridge->nominal();
  const Factors f = c.factors();
  // The geometry the host drove with at the end: the fitted one (F_lat, F_lon folded in).
  const drive::model::Geometry<double> g = geometry_in_force(f, nominal.wheel_diameter_mm);
  const double left = g.left_diameter / nominal.wheel_diameter_mm;
  const double right = g.right_diameter / nominal.wheel_diameter_mm;
  const double separation = g.wheelbase / nominal.wheelbase_mm;
  std::string text = fmt::format(
      "# ROS 2 diff_drive_controller parameters from odocal session {} ({} runs, date {})\n"
      "# robot: {}; told wheel diameter {} mm, wheelbase {} mm, {} counts "
      "per wheel turn\n"
      "# calibrated: left wheel {:.4f} mm, right wheel {:.4f} mm, wheelbase {:.4f} mm (turns in "
      "place)\n",
      to_string(c.options.procedure), c.runs.size(), c.date(), c.options.bridge->name(),
      nominal.wheel_diameter_mm, nominal.wheelbase_mm, nominal.counts_per_rev, g.left_diameter,
      g.right_diameter, g.wheelbase);
  if (g.wheelbase_arc != 0.0 && std::fabs(g.wheelbase_arc - g.wheelbase) > 1e-9) {
    text += fmt::format(
        "# the robot turns about another wheelbase on arcs ({:.4f} mm): diff_drive_controller "
        "has one wheel separation, the one for turns in place is written\n",
        g.wheelbase_arc);
  }
  nlohmann::json ros = {{"file", "diff_drive_controller.yaml"},
                        {"wheel_separation", nominal.wheelbase_mm / 1000.0},
                        {"wheel_radius", nominal.wheel_diameter_mm / 2000.0},
                        {"wheel_separation_multiplier", separation},
                        {"left_wheel_radius_multiplier", left},
                        {"right_wheel_radius_multiplier", right}};
  std::string covariance;
  if (const nlohmann::json* noise = noise_of(outcome.result)) {
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
              ": not resolved above 0 by these runs; the upper end of its 95 % interval is "
              "used (a conservative covariance)\n";
    }
    const RosVelocityEstimate& estimate = c.options.ros_velocity;
    const Ros2Covariance cov =
        ros2_covariance(k, g.wheelbase, kCovarianceSpeedMps, estimate, kCovariancePoseDistanceM);
    text += ros2_covariance_note(k, kCovariancePoseDistanceM, kCovarianceSpeedMps, estimate);
    ros["ros_update_rate_hz"] = estimate.update_rate_hz;
    ros["ros_velocity_window"] = estimate.window;
    covariance =
        fmt::format("    pose_covariance_diagonal: {}\n    twist_covariance_diagonal: {}\n",
                    yaml_list(cov.pose), yaml_list(cov.twist));
    ros["pose_covariance_diagonal"] = cov.pose;
    ros["twist_covariance_diagonal"] = cov.twist;
  } else {
    text += "# no covariances: the result has no noise estimate\n";
  }
  text += fmt::format(
      "diff_drive_controller:\n  ros__parameters:\n    wheel_separation: {}\n    wheel_radius: "
      "{}\n    wheel_separation_multiplier: {}\n    left_wheel_radius_multiplier: {}\n    "
      "right_wheel_radius_multiplier: {}\n",
      yaml_double(nominal.wheelbase_mm / 1000.0), yaml_double(nominal.wheel_diameter_mm / 2000.0),
      yaml_double(separation), yaml_double(left), yaml_double(right));
  text += covariance;
  c.write_file("diff_drive_controller.yaml", text);
  outcome.result["ros"] = ros;
  c.log << "Wrote " << c.options.out_dir
        << "/diff_drive_controller.yaml (nothing was written to the robot): paste its "
           "ros__parameters into the robot's diff_drive_controller configuration (docs/ros.md).\n";
}

}  // namespace odocal::host::session
