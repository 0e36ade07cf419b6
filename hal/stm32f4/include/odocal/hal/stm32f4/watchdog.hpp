#pragma once
/// @file
/// Independent watchdog and DWT cycle counter.

#include <cstdint>

namespace odocal::hal::stm32f4 {

/// The independent watchdog (IWDG). Once started it cannot be stopped; it resets the MCU unless
/// `feed()` is called within the timeout. It runs from the LSI (nominal 32 kHz, 17..47 kHz over
/// temperature and parts), so the real timeout is 0.68..1.9 times the nominal one.
class Watchdog {
 public:
  /// Starts the watchdog with a nominal timeout, ms (clamped to 1..32768). Not ISR-safe.
  static void start(std::uint32_t timeout_ms);
  /// Reloads the counter. One register write: ISR-safe.
  static void feed();
  /// True when the last reset was caused by the watchdog (RCC_CSR); clears the reset flags.
  [[nodiscard]] static bool caused_last_reset();
};

/// The DWT cycle counter (core clock cycles, wraps every 25.6 s at 168 MHz). Real on hardware;
/// QEMU does not model the DWT and reads 0.
class CycleCounter {
 public:
  /// Powers the trace block and starts the counter. Not ISR-safe.
  static void start();
  /// Current count. ISR-safe.
  [[nodiscard]] static std::uint32_t now();
};

}  // namespace odocal::hal::stm32f4
