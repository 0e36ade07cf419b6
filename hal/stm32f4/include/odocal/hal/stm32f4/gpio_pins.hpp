#pragma once
/// @file
/// GPIO pin configuration, push-pull outputs, and EXTI edge inputs.

#include <cstdint>

#include "odocal/hal/digital_input.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/stm32f4/gpio.hpp"

namespace odocal::hal::stm32f4 {

/// Enables the clock of `pin`'s port and sets its mode, pull and speed. For `Mode::alternate`,
/// `alternate_function` (0..15, RM0090 / datasheet AF table) selects the peripheral.
/// Not ISR-safe (read-modify-write of port registers); start-up only.
void configure_pin(gpio::Pin pin, gpio::Mode mode, gpio::Pull pull = gpio::Pull::none,
                   gpio::Speed speed = gpio::Speed::low, std::uint8_t alternate_function = 0u);

/// Makes `pin` an input whose both edges raise EXTI line `pin.number` (SYSCFG routing, both
/// triggers, pending bit cleared, line unmasked) and enables that line's NVIC interrupt at
/// `priority`. The board serves the interrupt itself from its vector, clearing the pending bit
/// (board_robot.cpp). Start-up only, with interrupts disabled.
void start_exti_line(gpio::Pin pin, gpio::Pull pull, std::uint8_t priority);

/// A push-pull output pin.
class GpioOutput final : public hal::DigitalOutput {
 public:
  /// @param initial the level driven from `start()` on.
  constexpr GpioOutput(gpio::Pin pin, bool initial) : pin_(pin), initial_(initial) {}
  /// Sets the initial level, then makes the pin an output. Start-up only.
  void start();

 private:
  /// Single BSRR write: ISR-safe, no read-modify-write.
  void do_set(bool level) override;
  gpio::Pin pin_;
  bool initial_;
};

}  // namespace odocal::hal::stm32f4
