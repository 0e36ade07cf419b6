#pragma once
/// @file
/// The robot a QEMU image simulates inside the MCU (board_qemu.cpp): one file per twin, the image
/// chosen by which is linked. qemu_twin_robot.cpp: the default robot on an open floor, no wall
/// sensors (odocal-fw-qemu); qemu_twin_mouse.cpp: the usual mouse in the practice maze with its
/// four wall sensors (odocal-fw-qemu-mouse).

#include <array>

#include "odocal/console/console.hpp"
#include "odocal/hal/wall_sensor.hpp"
#include "odocal/sim/plant.hpp"
#include "odocal/sim/robot_model.hpp"

namespace odocal::firmware {

/// The board's name in the console's start-up line (`board=`).
extern const char* const twin_name;

/// Whether the twin carries wall sensors (twin_wall_sensors gives one at least).
extern const bool twin_has_wall_sensors;

/// The plant's robot: its true geometry, motors, encoders and floor.
[[nodiscard]] sim::RobotModel twin_robot_model();

/// The twin's wall sensors in the console's order (ConsoleOptions::wall_sensors), reading the maze
/// around `plant`'s true pose; nullptr where there is none. Start-up, once, before interrupts.
[[nodiscard]] std::array<hal::WallSensor*, console::wall_sensor_slots> twin_wall_sensors(
    const sim::Plant& plant);

}  // namespace odocal::firmware
