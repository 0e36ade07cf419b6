#include "odocal/hal/linux_gpiod/gpio_chips.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

namespace odocal::hal::linux_gpiod {

std::string describe(const LinePin& pin) {
  std::string text = pin.chip + " line " + std::to_string(pin.offset);
  if (!pin.role.empty()) {
    text += " (" + pin.role + ")";
  }
  return text;
}

SetupResult request_failure(const LinePin& pin, gpiod_line* line, int error_number) {
  if (error_number == EBUSY) {
    const char* consumer = line != nullptr ? gpiod_line_consumer(line) : nullptr;
    return SetupResult::failure(SetupCode::busy,
                                describe(pin) + " is in use" +
                                    (consumer != nullptr && consumer[0] != '\0'
                                         ? std::string(" by \"") + consumer + "\""
                                         : std::string(" by another driver or process")));
  }
  return SetupResult::failure(code_of_errno(error_number), "cannot request " + describe(pin) +
                                                               ": " + std::strerror(error_number));
}

ChipSet::~ChipSet() {
  for (Entry& entry : chips_) {
    if (entry.chip != nullptr) {
      gpiod_chip_close(entry.chip);  // releases every line requested on it
      entry.chip = nullptr;
    }
  }
}

SetupResult ChipSet::open(const std::string& chip, gpiod_chip** handle) {
  for (Entry& entry : chips_) {
    if (entry.chip != nullptr && entry.name == chip) {
      *handle = entry.chip;
      return SetupResult::success();
    }
  }
  Entry* slot = nullptr;
  for (Entry& entry : chips_) {
    if (entry.chip == nullptr) {
      slot = &entry;
      break;
    }
  }
  if (slot == nullptr) {
    return SetupResult::failure(SetupCode::bad_argument,
                                "more than " + std::to_string(max_chips) + " GPIO chips named");
  }
  errno = 0;
  gpiod_chip* opened = gpiod_chip_open_lookup(chip.c_str());
  if (opened == nullptr) {
    const int error_number = errno != 0 ? errno : ENOENT;
    if (error_number == EACCES || error_number == EPERM) {
      return SetupResult::failure(SetupCode::permission_denied,
                                  "GPIO chip \"" + chip +
                                      "\": permission denied (run as root or join the group "
                                      "that owns /dev/gpiochip*, usually \"gpio\")");
    }
    return SetupResult::failure(code_of_errno(error_number),
                                "GPIO chip \"" + chip + "\" not found (" +
                                    std::strerror(error_number) +
                                    "); list the chips with `gpiodetect`");
  }
  slot->name = chip;
  slot->chip = opened;
  *handle = opened;
  return SetupResult::success();
}

SetupResult ChipSet::find(const LinePin& pin, gpiod_line** line) {
  gpiod_chip* chip = nullptr;
  SetupResult opened = open(pin.chip, &chip);
  if (!opened.ok()) {
    if (!pin.role.empty()) {
      opened.message = pin.role + ": " + opened.message;
    }
    return opened;
  }
  const unsigned int lines = gpiod_chip_num_lines(chip);
  if (pin.offset >= lines) {
    return SetupResult::failure(SetupCode::not_found, describe(pin) + ": the chip has only " +
                                                          std::to_string(lines) + " lines (0.." +
                                                          std::to_string(lines - 1u) + ")");
  }
  gpiod_line* found = gpiod_chip_get_line(chip, pin.offset);
  if (found == nullptr) {
    return request_failure(pin, nullptr, errno);
  }
  *line = found;
  return SetupResult::success();
}

}  // namespace odocal::hal::linux_gpiod
