#pragma once
/// @file
/// YAML values as ROS 2 parameter files need them (`odocal ros2`, the ROSArduinoBridge session's
/// diff_drive_controller.yaml).

#include <array>
#include <cstddef>
#include <string>

namespace odocal::host {

/// How diff_drive_controller estimates the velocity it publishes (odometry.cpp): at every
/// update of the controller manager (`update_rate`), each wheel's travel since the last update
/// over the update's period, averaged over the last `velocity_rolling_window_size` updates.
/// The defaults are the controller's and the controller manager's.
struct RosVelocityEstimate {
  double update_rate_hz = 100.0;  ///< controller_manager's update_rate
  std::size_t window = 10;        ///< diff_drive_controller's velocity_rolling_window_size
};

/// The shortest text that reads back as exactly `value`, always with a '.' so that YAML (and
/// rcl_yaml_param_parser) reads a double, never an integer: 1 -> "1.0", 1e-05 -> "1.0e-05".
[[nodiscard]] std::string yaml_double(double value);

/// "[a, b, c, d, e, f]" with YAML doubles (a covariance diagonal).
[[nodiscard]] std::string yaml_list(const double (&values)[6]);

}  // namespace odocal::host
