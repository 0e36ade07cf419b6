#include "odocal/hal/linux_gpiod/gpio_output.hpp"

#include <gpiod.h>

#include <cerrno>

namespace odocal::hal::linux_gpiod {

GpioOutput::~GpioOutput() {
  close();
}

SetupResult GpioOutput::open(ChipSet& chips, const LinePin& pin, bool initial,
                             const char* consumer) {
  close();
  gpiod_line* line = nullptr;
  SetupResult found = chips.find(pin, &line);
  if (!found.ok()) {
    return found;
  }
  if (gpiod_line_is_requested(line)) {
    return request_failure(pin, line, EBUSY);
  }
  if (gpiod_line_request_output(line, consumer, initial ? 1 : 0) != 0) {
    return request_failure(pin, line, errno);
  }
  line_ = line;
  level_ = initial;
  return SetupResult::success();
}

void GpioOutput::close() {
  if (line_ != nullptr) {
    gpiod_line_set_value(line_, 0);
    gpiod_line_release(line_);
    line_ = nullptr;
  }
  level_ = false;
}

void GpioOutput::do_set(bool level) {
  level_ = level;
  if (line_ != nullptr) {
    // One ioctl; the only failure is a vanished device, which the next read of status shows.
    (void)gpiod_line_set_value(line_, level ? 1 : 0);
  }
}

}  // namespace odocal::hal::linux_gpiod
