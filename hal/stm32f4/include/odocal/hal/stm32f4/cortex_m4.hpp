#pragma once
/// @file
/// Cortex-M4 core peripherals used here (ARMv7-M architecture reference, the Cortex-M4 generic
/// user guide): system control block, NVIC, SysTick, DWT cycle counter, FPU access.

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::scb {

/// Interrupt control and state: SysTick pending, active vector.
inline constexpr Register icsr = Register{0xE000'ED04u};
inline constexpr Field icsr_vectactive = {0, 9};
inline constexpr Field icsr_pendstclr = bit(25);
inline constexpr Field icsr_pendstset = bit(26);  ///< reads 1 while SysTick is pending
inline constexpr Register vtor = Register{0xE000'ED08u};
/// Application interrupt and reset control: writes need the key in the upper half.
inline constexpr Register aircr = Register{0xE000'ED0Cu};
inline constexpr std::uint32_t aircr_key = 0x05FAu << 16;
inline constexpr Field aircr_sysresetreq = bit(2);
inline constexpr Register ccr = Register{0xE000'ED14u};
inline constexpr Field ccr_div_0_trp = bit(4);  ///< integer divide by zero faults
/// System handler priorities: SHPR3 holds SysTick (bits 31..24) and PendSV (23..16).
inline constexpr Register shpr3 = Register{0xE000'ED20u};
inline constexpr Field shpr3_systick = {24, 8};
/// System handler control: enables the configurable faults (else they escalate to HardFault).
inline constexpr Register shcsr = Register{0xE000'ED24u};
inline constexpr Field shcsr_memfaultena = bit(16);
inline constexpr Field shcsr_busfaultena = bit(17);
inline constexpr Field shcsr_usgfaultena = bit(18);
inline constexpr Register cfsr = Register{0xE000'ED28u};  ///< configurable fault status
inline constexpr Register hfsr = Register{0xE000'ED2Cu};  ///< hard fault status
inline constexpr Register mmfar = Register{0xE000'ED34u};
inline constexpr Register bfar = Register{0xE000'ED38u};
/// Coprocessor access: CP10 and CP11 (the FPU), two bits each; 0b11 = full access.
inline constexpr Register cpacr = Register{0xE000'ED88u};
inline constexpr Field cpacr_cp10 = {20, 2};
inline constexpr Field cpacr_cp11 = {22, 2};

}  // namespace odocal::hal::stm32f4::scb

namespace odocal::hal::stm32f4::nvic {

/// Set-enable, clear-enable, set-pending registers: one bit per IRQ, 32 per register.
[[nodiscard]] constexpr Register iser(std::uint32_t irq) {
  return Register{0xE000'E100u + 4u * (irq / 32u)};
}
[[nodiscard]] constexpr Register icer(std::uint32_t irq) {
  return Register{0xE000'E180u + 4u * (irq / 32u)};
}
[[nodiscard]] constexpr Register ispr(std::uint32_t irq) {
  return Register{0xE000'E200u + 4u * (irq / 32u)};
}
[[nodiscard]] constexpr std::uint32_t irq_bit(std::uint32_t irq) {
  return 1u << (irq % 32u);
}
/// Priority bytes, four per word; the STM32F4 implements the upper four bits of each.
[[nodiscard]] constexpr Register ipr(std::uint32_t irq) {
  return Register{0xE000'E400u + 4u * (irq / 4u)};
}
[[nodiscard]] constexpr Field ipr_field(std::uint32_t irq) {
  return Field{static_cast<std::uint8_t>(8u * (irq % 4u)), 8u};
}

}  // namespace odocal::hal::stm32f4::nvic

namespace odocal::hal::stm32f4::systick {

inline constexpr Register ctrl = Register{0xE000'E010u};
inline constexpr Field ctrl_enable = bit(0);
inline constexpr Field ctrl_tickint = bit(1);
inline constexpr Field ctrl_clksource_core = bit(2);  ///< 1: processor clock, 0: HCLK / 8
/// Reload value: the counter runs LOAD..0, so the period is LOAD + 1 clocks (24 bits).
inline constexpr Register load = Register{0xE000'E014u};
inline constexpr Register val = Register{0xE000'E018u};
inline constexpr std::uint32_t max_reload = 0x00FF'FFFFu;

}  // namespace odocal::hal::stm32f4::systick

namespace odocal::hal::stm32f4::dwt {

/// Debug exception and monitor control: TRCENA powers the DWT.
inline constexpr Register demcr = Register{0xE000'EDFCu};
inline constexpr Field demcr_trcena = bit(24);
inline constexpr Register ctrl = Register{0xE000'1000u};
inline constexpr Field ctrl_cyccntena = bit(0);
inline constexpr Register cyccnt = Register{0xE000'1004u};

}  // namespace odocal::hal::stm32f4::dwt
