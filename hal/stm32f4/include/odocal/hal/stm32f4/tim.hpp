#pragma once
/// @file
/// General-purpose timers TIM2..TIM5 (RM0090 section 18) as typed register descriptions.
/// TIM2 and TIM5 are 32-bit, TIM3 and TIM4 16-bit; all sit on APB1 (timer clock = 2 · PCLK1
/// when the APB1 prescaler is not 1).

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::tim {

inline constexpr Block tim2{0x4000'0000u};
inline constexpr Block tim3{0x4000'0400u};
inline constexpr Block tim4{0x4000'0800u};
inline constexpr Block tim5{0x4000'0C00u};

[[nodiscard]] constexpr Register cr1(Block t) {
  return t.at(0x00);
}
inline constexpr Field cr1_cen = bit(0);   ///< counter enable
inline constexpr Field cr1_arpe = bit(7);  ///< ARR preload
[[nodiscard]] constexpr Register dier(Block t) {
  return t.at(0x0C);
}
inline constexpr Field dier_uie = bit(0);  ///< update interrupt enable
[[nodiscard]] constexpr Register sr(Block t) {
  return t.at(0x10);
}
inline constexpr Field sr_uif = bit(0);  ///< update flag; cleared by writing 0
[[nodiscard]] constexpr Register egr(Block t) {
  return t.at(0x14);
}
inline constexpr Field egr_ug = bit(0);  ///< update generation: loads PSC/ARR preloads
/// Capture/compare mode 1 (channels 1 and 2) and 2 (channels 3 and 4).
[[nodiscard]] constexpr Register ccmr(Block t, std::uint8_t channel) {
  return t.at(channel <= 2u ? 0x18 : 0x1C);
}
/// Output-compare mode field of `channel` (1..4) in its CCMR register.
[[nodiscard]] constexpr Field ccmr_ocm(std::uint8_t channel) {
  return Field{static_cast<std::uint8_t>(channel % 2u == 1u ? 4u : 12u), 3u};
}
/// Output-compare preload enable of `channel`.
[[nodiscard]] constexpr Field ccmr_ocpe(std::uint8_t channel) {
  return bit(static_cast<std::uint8_t>(channel % 2u == 1u ? 3u : 11u));
}
/// PWM mode 1: output active while CNT < CCR.
inline constexpr std::uint32_t ocm_pwm1 = 0b110;
[[nodiscard]] constexpr Register ccer(Block t) {
  return t.at(0x20);
}
/// Output enable of `channel` (1..4).
[[nodiscard]] constexpr Field ccer_cce(std::uint8_t channel) {
  return bit(static_cast<std::uint8_t>(4u * (channel - 1u)));
}
[[nodiscard]] constexpr Register cnt(Block t) {
  return t.at(0x24);
}
[[nodiscard]] constexpr Register psc(Block t) {
  return t.at(0x28);
}
[[nodiscard]] constexpr Register arr(Block t) {
  return t.at(0x2C);
}
/// Compare value of `channel` (1..4).
[[nodiscard]] constexpr Register ccr(Block t, std::uint8_t channel) {
  return t.at(0x34u + 4u * (channel - 1u));
}

}  // namespace odocal::hal::stm32f4::tim
