#pragma once
/// @file
/// General-purpose I/O ports (RM0090 section 8) as typed register descriptions.

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::gpio {

/// Port index: the letter's position (A = 0). Also the EXTI line source code of SYSCFG.
enum class Port : std::uint8_t { a = 0, b, c, d, e, f, g, h, i };

/// A pin: port and number (0..15).
struct Pin {
  Port port;
  std::uint8_t number;
};

/// Pin modes (MODER, two bits per pin).
enum class Mode : std::uint32_t { input = 0b00, output = 0b01, alternate = 0b10, analog = 0b11 };
/// Pull resistors (PUPDR, two bits per pin).
enum class Pull : std::uint32_t { none = 0b00, up = 0b01, down = 0b10 };
/// Output slew rate (OSPEEDR, two bits per pin).
enum class Speed : std::uint32_t { low = 0b00, medium = 0b01, fast = 0b10, high = 0b11 };

/// The register block of one port (ports are 0x400 apart from 0x40020000).
[[nodiscard]] constexpr Block port_block(Port port) {
  return Block{0x4002'0000u + 0x400u * static_cast<std::uintptr_t>(port)};
}

[[nodiscard]] constexpr Register moder(Port p) {
  return port_block(p).at(0x00);
}
[[nodiscard]] constexpr Register otyper(Port p) {
  return port_block(p).at(0x04);
}
[[nodiscard]] constexpr Register ospeedr(Port p) {
  return port_block(p).at(0x08);
}
[[nodiscard]] constexpr Register pupdr(Port p) {
  return port_block(p).at(0x0C);
}
[[nodiscard]] constexpr Register idr(Port p) {
  return port_block(p).at(0x10);
}
[[nodiscard]] constexpr Register odr(Port p) {
  return port_block(p).at(0x14);
}
/// Bit set/reset: writing bit n sets pin n, bit n + 16 clears it; atomic, no read-modify-write.
[[nodiscard]] constexpr Register bsrr(Port p) {
  return port_block(p).at(0x18);
}
/// Alternate function: AFRL for pins 0..7, AFRH for 8..15, four bits per pin.
[[nodiscard]] constexpr Register afr(Pin pin) {
  return port_block(pin.port).at(pin.number < 8u ? 0x20 : 0x24);
}

/// The two-bit field of `pin` in MODER, OSPEEDR, PUPDR.
[[nodiscard]] constexpr Field two_bits(std::uint8_t number) {
  return Field{static_cast<std::uint8_t>(2u * number), 2u};
}
/// The four-bit field of `pin` in its AFR register.
[[nodiscard]] constexpr Field af_field(std::uint8_t number) {
  return Field{static_cast<std::uint8_t>(4u * (number % 8u)), 4u};
}

}  // namespace odocal::hal::stm32f4::gpio
