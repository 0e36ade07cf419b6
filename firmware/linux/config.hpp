#pragma once
/// @file
/// The configuration file of odocal-linux: which GPIO lines and PWM channels the robot uses.

#include <cstdint>
#include <string>

#include "odocal/hal/linux_gpiod/gpio_chips.hpp"

namespace odocal::linux_target {

/// Where one motor's PWM comes from.
struct PwmSpec {
  bool sysfs = false;              ///< a sysfs channel is named (else only the GPIO fallback)
  unsigned int chip = 0u;          ///< pwmchip<chip>
  unsigned int channel = 0u;       ///< pwm<channel>
  bool has_gpio = false;           ///< a software-PWM line is named
  hal::linux_gpiod::LinePin gpio;  ///< the software-PWM (low-precision) line
};

/// Everything the file can say. Defaults are what `--help` prints.
struct LinuxConfig {
  hal::linux_gpiod::LinePin left_a, left_b, right_a, right_b;
  hal::linux_gpiod::LinePin left_dir, right_dir;
  bool has_enable = false;
  hal::linux_gpiod::LinePin enable;
  PwmSpec left_pwm, right_pwm;
  std::uint32_t pwm_hz = 20000u;
  std::uint32_t soft_pwm_hz = 200u;
  int event_priority = 45;
  int tick_priority = 40;
  int pwm_priority = 30;
  std::uint32_t event_holdback_us = 1000u;
  std::string store = "/var/lib/odocal/params.bin";
};

/// Parses the text of a configuration file. `name` is used in messages ("FILE:LINE: ...").
/// @return true on success; false with `error` naming the file, line and key otherwise.
/// Unknown keys, repeated keys, malformed values, missing required keys and one line used for
/// two signals are all errors.
bool parse_config(const std::string& text, const std::string& name, LinuxConfig& config,
                  std::string& error);

/// Reads and parses `path`. @return false with `error` set (missing file included).
bool load_config(const std::string& path, LinuxConfig& config, std::string& error);

/// The reference of every key, as printed by `odocal-linux --help`.
const char* config_reference();

}  // namespace odocal::linux_target
