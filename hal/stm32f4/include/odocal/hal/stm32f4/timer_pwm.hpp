#pragma once
/// @file
/// PWM output on a general-purpose timer channel.

#include <cstdint>

#include "odocal/hal/pwm_output.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4 {

/// One timer shared by the PWM channels of a board, edge-aligned, PWM mode 1.
struct PwmTimerConfig {
  Block timer;               ///< tim::tim3, ...
  std::uint32_t timer_hz;    ///< timer input clock (84 MHz for APB1 timers at 168 MHz)
  std::uint32_t carrier_hz;  ///< PWM frequency (20 kHz: above hearing)
};

/// Steps of duty resolution: timer_hz / carrier_hz (4200 for 84 MHz / 20 kHz, i.e. 0.024 %).
[[nodiscard]] constexpr std::uint32_t pwm_steps(const PwmTimerConfig& config) {
  return config.timer_hz / config.carrier_hz;
}

/// Starts the counter of `config.timer` at the carrier frequency (prescaler 1). Channels must be
/// set up first with `TimerPwm::start`. Start-up only.
void start_pwm_timer(const PwmTimerConfig& config);

/// One channel (1..4) of a PWM timer. Duty changes take effect at the next period (preload).
class TimerPwm final : public hal::PwmOutput {
 public:
  TimerPwm(const PwmTimerConfig& config, std::uint8_t channel)
      : config_(config), channel_(channel) {}
  /// Enables the channel's output compare at duty 0. Start-up only.
  void start();

 private:
  /// One register write: ISR-safe.
  void do_set_duty(float duty) override;
  PwmTimerConfig config_;
  std::uint8_t channel_;
};

/// Sets channel `channel` of `timer` to duty 0 at once. For fault handlers: no object needed.
void force_pwm_zero(Block timer, std::uint8_t channel);

}  // namespace odocal::hal::stm32f4
