// `walls` where the robot has wall sensors (ConsoleOptions::wall_sensors): one reading of the
// reflected light per sensor present. Linked by the host programs, the Linux board, the mouse image
// and the QEMU mouse twin; walls_none.cpp stands in for it in the images without sensors
// (core/CMakeLists.txt).

#include "odocal/console/console.hpp"
#include "odocal/name_list.hpp"

namespace odocal::console {
namespace {

// The wall sensors' keys in ConsoleOptions::wall_sensors' order.
constexpr char kWallSensorKeys[] = "left_front\0left_diagonal\0right_diagonal\0right_front";
static_assert(nul_count(kWallSensorKeys) == wall_sensor_slots, "one key per wall sensor");

}  // namespace

void Console::cmd_walls() {
  const auto& sensors = options_.wall_sensors;
  bool any = false;
  for (const hal::WallSensor* sensor : sensors) {
    any = any || sensor != nullptr;
  }
  if (!any) {
    send_error(ErrorCode::no_sensors, no_wall_sensors);
    return;
  }
  ReplyLine reply(out_);
  append(reply, "ok");
  for (unsigned i = 0u; i < wall_sensor_slots; ++i) {
    if (sensors[i] != nullptr) {
      append(reply, " %s=%u", name_at(kWallSensorKeys, i), sensors[i]->read_lit_counts());
    }
  }
  send(reply);
}

}  // namespace odocal::console
