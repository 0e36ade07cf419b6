#pragma once
/// @file
/// SysTick as the control tick.

#include <atomic>
#include <cstdint>

#include "odocal/hal/tick_source.hpp"

namespace odocal::hal::stm32f4 {

/// The core's 24-bit SysTick counter, clocked by the processor clock, raising the control tick.
/// One instance per image (it owns SysTick). The images' microsecond clock is a separate 32-bit
/// timer (`MicrosecondTimer`), one register load to read, so edges can stamp themselves cheaply.
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

 private:
  std::uint32_t do_start(std::uint32_t rate_hz, TickHandler handler, void* context) override;
  void do_stop() override;
  static void on_interrupt(void* self);

  std::uint32_t core_hz_;
  std::uint8_t priority_;
  std::uint32_t period_cycles_ = 0u;
  TickHandler handler_ = nullptr;
  void* context_ = nullptr;
  std::atomic<std::uint32_t> ticks_{0u};
};

}  // namespace odocal::hal::stm32f4
