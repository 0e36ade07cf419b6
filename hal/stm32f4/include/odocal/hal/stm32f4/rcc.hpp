#pragma once
/// @file
/// Reset and clock control (RM0090 section 7) and the power controller's voltage scaling
/// (section 5), as typed register descriptions.

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::rcc {

inline constexpr Block block{0x4002'3800u};

inline constexpr Register cr = block.at(0x00);
inline constexpr Field cr_hsion = bit(0);
inline constexpr Field cr_hsirdy = bit(1);
inline constexpr Field cr_hseon = bit(16);
inline constexpr Field cr_hserdy = bit(17);
inline constexpr Field cr_hsebyp = bit(18);
inline constexpr Field cr_pllon = bit(24);
inline constexpr Field cr_pllrdy = bit(25);

/// Main PLL: f_vco = f_in · N / M (f_in / M should be 2 MHz), f_sys = f_vco / P, f_usb = f_vco / Q.
inline constexpr Register pllcfgr = block.at(0x04);
inline constexpr Field pllcfgr_m = {0, 6};   ///< 2..63
inline constexpr Field pllcfgr_n = {6, 9};   ///< 50..432
inline constexpr Field pllcfgr_p = {16, 2};  ///< 0 -> /2, 1 -> /4, 2 -> /6, 3 -> /8
inline constexpr Field pllcfgr_src_hse = bit(22);
inline constexpr Field pllcfgr_q = {24, 4};  ///< 2..15

inline constexpr Register cfgr = block.at(0x08);
inline constexpr Field cfgr_sw = {0, 2};      ///< system clock switch
inline constexpr Field cfgr_sws = {2, 2};     ///< system clock switch status
inline constexpr Field cfgr_hpre = {4, 4};    ///< AHB prescaler; 0 -> /1
inline constexpr Field cfgr_ppre1 = {10, 3};  ///< APB1 prescaler; 0b100 -> /2, 0b101 -> /4
inline constexpr Field cfgr_ppre2 = {13, 3};  ///< APB2 prescaler

/// Values of `cfgr_sw` / `cfgr_sws`.
enum class SystemClock : std::uint32_t { hsi = 0b00, hse = 0b01, pll = 0b10 };
/// APB prescaler codes.
inline constexpr std::uint32_t apb_div1 = 0b000;
inline constexpr std::uint32_t apb_div2 = 0b100;
inline constexpr std::uint32_t apb_div4 = 0b101;

inline constexpr Register ahb1enr = block.at(0x30);
/// AHB1 enable bit of GPIO port `port` (0 = A, 1 = B, ...).
[[nodiscard]] constexpr Field ahb1enr_gpio(std::uint8_t port) {
  return bit(port);
}

inline constexpr Register apb1enr = block.at(0x40);
inline constexpr Field apb1enr_tim2 = bit(0);
inline constexpr Field apb1enr_tim3 = bit(1);
inline constexpr Field apb1enr_tim4 = bit(2);
inline constexpr Field apb1enr_tim5 = bit(3);
inline constexpr Field apb1enr_usart2 = bit(17);
inline constexpr Field apb1enr_usart3 = bit(18);
inline constexpr Field apb1enr_pwr = bit(28);

inline constexpr Register apb2enr = block.at(0x44);
inline constexpr Field apb2enr_usart1 = bit(4);
inline constexpr Field apb2enr_usart6 = bit(5);
inline constexpr Field apb2enr_adc1 = bit(8);
inline constexpr Field apb2enr_syscfg = bit(14);

/// Clock control and status: LSI (the watchdog's clock) and the reset-cause flags.
inline constexpr Register csr = block.at(0x74);
inline constexpr Field csr_lsion = bit(0);
inline constexpr Field csr_rmvf = bit(24);  ///< write 1 to clear the reset flags
inline constexpr Field csr_pinrstf = bit(26);
inline constexpr Field csr_porrstf = bit(27);
inline constexpr Field csr_sftrstf = bit(28);
inline constexpr Field csr_iwdgrstf = bit(29);

}  // namespace odocal::hal::stm32f4::rcc

namespace odocal::hal::stm32f4::pwr {

inline constexpr Register cr = Register{0x4000'7000u};
/// Regulator voltage scale: 1 = scale 1, needed for 168 MHz.
inline constexpr Field cr_vos = bit(14);

}  // namespace odocal::hal::stm32f4::pwr
