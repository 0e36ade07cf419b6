#pragma once
/// @file
/// SysTick as the control tick, and (SysTickClock) as a microsecond clock.

#include <atomic>
#include <cstdint>

#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/tick_source.hpp"

namespace odocal::hal::stm32f4 {

/// The core's 24-bit SysTick counter, clocked by the processor clock, raising the control tick.
/// The microsecond clock is the count of whole periods (advanced in the interrupt) plus the
/// counter's position in the current period, so it is exact to one core cycle and needs no
/// second timer. One instance per image (it owns SysTick). `SysTickClock` offers that clock as a
/// `hal::MonotonicClock` (QEMU's clock; the robot reads TIM5 instead and links none of it).
class SysTickTimer final : public hal::TickSource {
 public:
  /// @param core_hz processor clock, Hz (168 MHz on both boards); @param priority of the tick.
  SysTickTimer(std::uint32_t core_hz, std::uint8_t priority);

  /// Core cycles since the current period began. ISR-safe. Used to time the tick itself: read at
  /// the end of the tick handler, it is the latency plus the duration of the tick.
  [[nodiscard]] std::uint32_t cycles_into_period() const;
  /// Core cycles per tick period (0 before `start`).
  [[nodiscard]] std::uint32_t period_cycles() const { return period_cycles_; }
  [[nodiscard]] std::uint32_t core_hz() const { return core_hz_; }
  /// Ticks raised since start, modulo 2^32. ISR-safe.
  [[nodiscard]] std::uint32_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
  /// Microseconds since the first start, modulo 2^32, exact to one core cycle. Any context.
  [[nodiscard]] std::uint32_t microseconds() const;

 private:
  std::uint32_t do_start(std::uint32_t rate_hz, TickHandler handler, void* context) override;
  void do_stop() override;
  static void on_interrupt(void* self);

  std::uint32_t core_hz_;
  std::uint32_t cycles_per_us_;
  std::uint8_t priority_;
  std::uint32_t period_cycles_ = 0u;
  TickHandler handler_ = nullptr;
  void* context_ = nullptr;
  std::atomic<std::uint32_t> base_us_{0u};          ///< µs at the start of the current period
  std::atomic<std::uint32_t> base_rem_cycles_{0u};  ///< cycles beyond base_us_ (< cycles_per_us)
  std::atomic<std::uint32_t> ticks_{0u};
};

/// A SysTickTimer's microseconds as the application's clock.
class SysTickClock final : public hal::MonotonicClock {
 public:
  explicit SysTickClock(const SysTickTimer& timer) : timer_(timer) {}

 private:
  std::uint32_t do_now_us() override { return timer_.microseconds(); }
  const SysTickTimer& timer_;
};

}  // namespace odocal::hal::stm32f4
