// `walls` in an image that has no wall sensors (the STM32F4 robot image, the QEMU twin of the
// default robot): the refusal alone, without the reading loop and its reply (walls_read.cpp).

#include "odocal/console/console.hpp"

namespace odocal::console {

void Console::cmd_walls() {
  send_error(ErrorCode::no_sensors, no_wall_sensors);
}

}  // namespace odocal::console
