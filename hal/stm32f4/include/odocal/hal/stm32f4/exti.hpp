#pragma once
/// @file
/// External interrupt controller (RM0090 section 12) and the SYSCFG line routing (section 9).

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::exti {

inline constexpr Block block{0x4001'3C00u};
inline constexpr Register imr = block.at(0x00);   ///< interrupt mask: 1 = enabled
inline constexpr Register rtsr = block.at(0x08);  ///< rising-edge trigger
inline constexpr Register ftsr = block.at(0x0C);  ///< falling-edge trigger
inline constexpr Register swier = block.at(0x10);
/// Pending: bit n set by an edge on line n; cleared by writing 1 (writing 0 does nothing).
inline constexpr Register pr = block.at(0x14);

}  // namespace odocal::hal::stm32f4::exti

namespace odocal::hal::stm32f4::syscfg {

inline constexpr Block block{0x4001'3800u};
/// EXTICR1..4: which port drives EXTI line n; four bits per line, four lines per register.
[[nodiscard]] constexpr Register exticr(std::uint8_t line) {
  return block.at(0x08u + 4u * (line / 4u));
}
[[nodiscard]] constexpr Field exticr_field(std::uint8_t line) {
  return Field{static_cast<std::uint8_t>(4u * (line % 4u)), 4u};
}

}  // namespace odocal::hal::stm32f4::syscfg
