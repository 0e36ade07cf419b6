#pragma once
/// @file
/// Independent watchdog (RM0090 section 21): clocked by the ~32 kHz LSI, resets the MCU when its
/// 12-bit down-counter reaches 0 before a reload.

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::iwdg {

inline constexpr Block block{0x4000'3000u};
inline constexpr Register kr = block.at(0x00);
inline constexpr Register pr = block.at(0x04);   ///< prescaler: /4 << code
inline constexpr Register rlr = block.at(0x08);  ///< reload value, 0..4095
inline constexpr Register sr = block.at(0x0C);   ///< PVU, RVU: update in progress

inline constexpr std::uint32_t key_reload = 0xAAAAu;
inline constexpr std::uint32_t key_unlock = 0x5555u;  ///< enables writes to PR and RLR
inline constexpr std::uint32_t key_start = 0xCCCCu;

}  // namespace odocal::hal::stm32f4::iwdg
