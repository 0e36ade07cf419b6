#pragma once
/// @file
/// A 32-bit general-purpose timer (TIM2 or TIM5) counting microseconds, free-running over 2^32:
/// the `hal::MonotonicClock` whose reading is a single register load, cheap enough to stamp every
/// encoder edge. RM0090 section 18: the prescaler divides the timer clock by PSC + 1 from the
/// next update event; with ARR = 0xFFFFFFFF the counter wraps from 2^32 - 1 to 0, which is the
/// "microseconds modulo 2^32" the interface promises.

#include <cstdint>

#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"
#include "odocal/hal/stm32f4/tim.hpp"

namespace odocal::hal::stm32f4 {

class MicrosecondTimer final : public hal::MonotonicClock {
 public:
  /// @param timer tim::tim2 or tim::tim5 (the 32-bit ones); @param enable its RCC APB1ENR bit.
  constexpr MicrosecondTimer(Block timer, Field enable) : timer_(timer), enable_(enable) {}

  /// Starts counting from 0 at 1 MHz. @param timer_clock_hz the timer's input clock (APB1 timer
  /// clock: 2 · PCLK1 when the APB1 prescaler is not 1), a whole number of MHz. Start-up only.
  void start(std::uint32_t timer_clock_hz) const {
    rcc::apb1enr.set(enable_.mask());
    tim::cr1(timer_).write(0u);
    tim::psc(timer_).write(timer_clock_hz / 1'000'000u - 1u);
    tim::arr(timer_).write(0xFFFF'FFFFu);
    tim::cnt(timer_).write(0u);
    tim::egr(timer_).write(tim::egr_ug.mask());  // loads PSC now, not at the first wrap
    tim::sr(timer_).write(0u);                   // UG set the update flag; no interrupt is enabled
    tim::cr1(timer_).write(tim::cr1_cen.mask());
  }
  /// Microseconds since `start`, modulo 2^32, of the started timer `timer`: one volatile load
  /// from a constant address (for edge interrupts); any context.
  [[nodiscard]] static std::uint32_t read(Block timer) { return tim::cnt(timer).read(); }

 private:
  std::uint32_t do_now_us() override { return read(timer_); }

  Block timer_;
  Field enable_;
};

}  // namespace odocal::hal::stm32f4
