#pragma once
/// @file
/// USART (RM0090 section 30) as typed register descriptions.

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::usart {

inline constexpr Block usart1{0x4001'1000u};  ///< APB2
inline constexpr Block usart2{0x4000'4400u};  ///< APB1
inline constexpr Block usart3{0x4000'4800u};  ///< APB1
inline constexpr Block usart6{0x4001'1400u};  ///< APB2

[[nodiscard]] constexpr Register sr(Block u) {
  return u.at(0x00);
}
inline constexpr Field sr_ore = bit(3);   ///< overrun (cleared by reading SR then DR)
inline constexpr Field sr_rxne = bit(5);  ///< a received byte waits in DR
inline constexpr Field sr_tc = bit(6);    ///< transmission complete
inline constexpr Field sr_txe = bit(7);   ///< transmit data register empty
[[nodiscard]] constexpr Register dr(Block u) {
  return u.at(0x04);
}
/// Baud rate: USARTDIV = f_pclk / (16 · baud) with OVER8 = 0, as 12.4 fixed point.
[[nodiscard]] constexpr Register brr(Block u) {
  return u.at(0x08);
}
[[nodiscard]] constexpr Register cr1(Block u) {
  return u.at(0x0C);
}
inline constexpr Field cr1_re = bit(2);
inline constexpr Field cr1_te = bit(3);
inline constexpr Field cr1_rxneie = bit(5);
inline constexpr Field cr1_txeie = bit(7);
inline constexpr Field cr1_ue = bit(13);
[[nodiscard]] constexpr Register cr2(Block u) {
  return u.at(0x10);
}
[[nodiscard]] constexpr Register cr3(Block u) {
  return u.at(0x14);
}

/// BRR value for `baud` from the peripheral clock `pclk_hz` (oversampling by 16, rounded).
[[nodiscard]] constexpr std::uint32_t brr_value(std::uint32_t pclk_hz, std::uint32_t baud) {
  return (pclk_hz + baud / 2u) / baud;  // = 16 · USARTDIV: mantissa << 4 | fraction
}

}  // namespace odocal::hal::stm32f4::usart
