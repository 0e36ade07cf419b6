#pragma once
/// @file
/// The usual micromouse of the project's maze work (issue 48): what a robot file that says nothing
/// of the robot's size is under `odocal session --truth walls`, and what the QEMU mouse twin
/// (odocal-fw-qemu-mouse) simulates. Its nominal size is what its owner tells the firmware; its
/// true size is each a little off, as a built robot's is.

#include "odocal/sim/robot_model.hpp"

namespace odocal::sim {

/// The usual mouse's nominal wheel diameter and wheelbase, mm (what the firmware is told).
inline constexpr double usual_mouse_wheel_diameter_mm = 32.0;
inline constexpr double usual_mouse_wheelbase_mm = 76.0;
/// Its true wheel diameters and wheelbase, mm: the right wheel 0.34 % larger than the left, the
/// wheelbase 1.4 % wider than nominal.
inline constexpr double usual_mouse_true_left_diameter_mm = 31.95;
inline constexpr double usual_mouse_true_right_diameter_mm = 32.06;
inline constexpr double usual_mouse_true_wheelbase_mm = 77.1;
/// The spread of a robot's wall-sensor gains: each uniform in 1 ± 20 % (emitters and receivers of
/// one batch differ about that much).
inline constexpr double usual_wall_sensor_gain_spread = 0.20;

/// The plant's model of the usual mouse: the default motors, encoders and floor, the mouse's true
/// geometry.
[[nodiscard]] inline RobotModel usual_mouse_model() {
  RobotModel model;
  model.left_diameter_m = usual_mouse_true_left_diameter_mm * 1e-3;
  model.right_diameter_m = usual_mouse_true_right_diameter_mm * 1e-3;
  model.wheelbase_m = usual_mouse_true_wheelbase_mm * 1e-3;
  return model;
}

}  // namespace odocal::sim
