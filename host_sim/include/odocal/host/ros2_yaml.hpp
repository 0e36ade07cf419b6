#pragma once
/// @file
/// YAML values as ROS 2 parameter files need them (`odocal ros2`, the ROSArduinoBridge session's
/// diff_drive_controller.yaml).

#include <array>
#include <string>

namespace odocal::host {

/// The shortest text that reads back as exactly `value`, always with a '.' so that YAML (and
/// rcl_yaml_param_parser) reads a double, never an integer: 1 -> "1.0", 1e-05 -> "1.0e-05".
[[nodiscard]] std::string yaml_double(double value);

/// "[a, b, c, d, e, f]" with YAML doubles (a covariance diagonal).
[[nodiscard]] std::string yaml_list(const double (&values)[6]);

}  // namespace odocal::host
