#pragma once
/// @file
/// A GPIO line driven as an output (motor direction, driver enable, software PWM).

#include <atomic>

#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/linux_gpiod/gpio_chips.hpp"

namespace odocal::hal::linux_gpiod {

/// An output line requested through libgpiod v1. Until `open` succeeds, `set` does nothing.
class GpioOutput final : public hal::DigitalOutput {
 public:
  GpioOutput() = default;
  ~GpioOutput();
  GpioOutput(const GpioOutput&) = delete;
  GpioOutput& operator=(const GpioOutput&) = delete;

  /// Requests `pin` as an output driven to `initial`, under the consumer name `consumer`.
  /// Set-up only. Fails when the chip or line is missing or the line is in use.
  SetupResult open(ChipSet& chips, const LinePin& pin, bool initial, const char* consumer);

  /// Drives the line low and releases it. Safe to call twice.
  void close();

  /// The last level written.
  bool level() const { return level_.load(std::memory_order_relaxed); }

 private:
  void do_set(bool level) override;

  gpiod_line* line_ = nullptr;
  std::atomic<bool> level_{false};
};

}  // namespace odocal::hal::linux_gpiod
