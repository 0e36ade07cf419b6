#pragma once
/// @file
/// System clock set-up: 168 MHz from the crystal through the main PLL, with timeouts and a
/// fallback to the internal 16 MHz oscillator (RM0090 sections 7.2 and 3.5.1).

#include <cstdint>

namespace odocal::hal::stm32f4 {

/// What a board asks of the clock tree.
struct ClockPlan {
  std::uint32_t hse_hz = 8'000'000u;       ///< crystal frequency; a multiple of 2 MHz, 4..26 MHz
  std::uint32_t sysclk_hz = 168'000'000u;  ///< target SYSCLK = HCLK
  std::uint32_t ready_timeout_polls = 200'000u;  ///< polls of a ready bit before giving up
};

/// Which oscillator ended up driving the core.
enum class ClockSource : std::uint8_t {
  hse_pll,  ///< the crystal through the PLL (the normal case)
  hsi_pll,  ///< the crystal did not start: HSI (±1 %) through the PLL, same frequencies
  hsi,      ///< the PLL did not lock either: 16 MHz HSI, peripherals at 16 MHz
};

/// The result of `configure_clock`.
struct ClockReport {
  ClockSource source = ClockSource::hsi;
  std::uint32_t sysclk_hz = 16'000'000u;  ///< core clock (SysTick, DWT)
  std::uint32_t pclk1_hz = 16'000'000u;   ///< APB1 (USART2/3, TIM2..5 at twice this if divided)
  std::uint32_t pclk2_hz = 16'000'000u;   ///< APB2 (USART1/6)
};

/// Name of a clock source as `status` prints it ("hse", "hsi-pll", "hsi").
[[nodiscard]] const char* clock_source_name(ClockSource source);

/// Brings the clock tree to `plan`: voltage scale 1, HSE on (with timeout), PLL (VCO input 2 MHz,
/// VCO 336 MHz, P = 2, Q = 7 for 48 MHz USB), flash 5 wait states with prefetch and caches,
/// AHB /1, APB1 /4 (42 MHz), APB2 /2 (84 MHz). Never waits forever: a missing crystal falls back to
/// HSI through the PLL, a PLL that does not lock leaves the core on HSI. Call once at start-up,
/// interrupts disabled. Supports `sysclk_hz` = 168 MHz only (the constants above).
[[nodiscard]] ClockReport configure_clock(const ClockPlan& plan);

}  // namespace odocal::hal::stm32f4
