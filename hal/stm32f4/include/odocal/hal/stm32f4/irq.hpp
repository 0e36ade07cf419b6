#pragma once
/// @file
/// STM32F405/407 interrupt numbers (RM0090 table 61) used by odocal, and the priorities it gives
/// them. Lower value = more urgent; the STM32F4 keeps the upper four bits of a priority byte.

#include <cstdint>

namespace odocal::hal::stm32f4::irq {

/// Number of device interrupts with a vector (table entries after the 16 system ones): 0 through
/// EXTI15_10, the last one the HAL attaches. The part has 82; a shorter table saves 164 B of flash
/// and `enable_irq` refuses the ones beyond it, so their vectors are never fetched.
inline constexpr std::uint32_t count = 41u;

inline constexpr std::uint32_t exti0 = 6u;
inline constexpr std::uint32_t exti1 = 7u;
inline constexpr std::uint32_t exti2 = 8u;
inline constexpr std::uint32_t exti3 = 9u;
inline constexpr std::uint32_t exti4 = 10u;
inline constexpr std::uint32_t exti9_5 = 23u;
inline constexpr std::uint32_t tim2 = 28u;
inline constexpr std::uint32_t tim3 = 29u;
inline constexpr std::uint32_t tim4 = 30u;
inline constexpr std::uint32_t usart1 = 37u;
inline constexpr std::uint32_t usart2 = 38u;
inline constexpr std::uint32_t usart3 = 39u;
inline constexpr std::uint32_t exti15_10 = 40u;
static_assert(exti15_10 < count, "every interrupt named here has a vector");

/// Encoder edges (or, in the emulator, the plant that makes them): most urgent.
inline constexpr std::uint8_t priority_edges = 0x00u;
/// The control tick: above the console, below the edges.
inline constexpr std::uint8_t priority_tick = 0x40u;
/// Console UART.
inline constexpr std::uint8_t priority_console = 0x80u;

}  // namespace odocal::hal::stm32f4::irq
