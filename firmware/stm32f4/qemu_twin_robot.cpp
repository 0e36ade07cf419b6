// The QEMU twin of the default robot (odocal-fw-qemu): the simulator's default geometry on an open
// floor, no wall sensors (its `walls` answers `err no_sensors`, as the robot image's does).

#include "qemu_twin.hpp"

namespace odocal::firmware {

const bool twin_has_wall_sensors = false;
const char* const twin_name = "qemu";

sim::RobotModel twin_robot_model() {
  return sim::RobotModel{};
}

std::array<hal::WallSensor*, console::wall_sensor_slots> twin_wall_sensors(
    const sim::Plant& /*plant*/) {
  return {};
}

}  // namespace odocal::firmware
