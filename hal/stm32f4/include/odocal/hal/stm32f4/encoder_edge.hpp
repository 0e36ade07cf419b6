#pragma once
/// @file
/// One quadrature encoder's edge, served from its EXTI vector: the register sequence of the
/// robot's edge path, written once against a register bus so the host tests run it on fakes.

#include <cstdint>

#include "odocal/hal/stm32f4/exti.hpp"
#include "odocal/hal/stm32f4/gpio.hpp"
#include "odocal/hal/stm32f4/tim.hpp"

namespace odocal::hal::stm32f4 {

/// Serves an edge of an encoder whose channels A and B are pins `a_line` and `b_line` of `port`
/// (EXTI line n is pin n of the port SYSCFG routes to it): clears both lines' pending bits first
/// (write 1 to clear, no other line touched; an edge from here on pends the vector again), then
/// samples A and B with one IDR read, stamps them with one read of `timer`'s counter (a
/// microsecond timer, see `MicrosecondTimer`), and hands levels and stamp to `sink.on_edge`.
///
/// `Bus` gives 32-bit register access, `read32(address)` and `write32(address, value)`:
/// `MemoryBus` on the MCU (volatile loads and stores, inlined), a fake in the host tests.
/// `Sink` is anything with `on_edge(bool a, bool b, std::uint32_t t_us)`: the robot passes the
/// core's decoder itself, so the whole edge path inlines into the vector without a call.
/// Edge-interrupt context; no other context may serve the same lines.
template <std::uint8_t a_line, std::uint8_t b_line, typename Bus, typename Sink>
inline void serve_encoder_edge(Bus& bus, gpio::Port port, Block timer, Sink& sink) {
  static_assert(a_line < 16u && b_line < 16u && a_line != b_line, "two distinct pins, 0..15");
  bus.write32(exti::pr.address, (1u << a_line) | (1u << b_line));
  const std::uint32_t levels = bus.read32(gpio::idr(port).address);
  sink.on_edge(((levels >> a_line) & 1u) != 0u, ((levels >> b_line) & 1u) != 0u,
               bus.read32(tim::cnt(timer).address));
}

}  // namespace odocal::hal::stm32f4
