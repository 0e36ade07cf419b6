#pragma once
/// @file
/// Console byte stream on a USART, interrupt-driven in both directions.

#include <atomic>
#include <cstdint>

#include "odocal/concurrency/spsc_ring.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4 {

/// Where the console USART is and how fast it runs.
struct UsartConfig {
  Block usart;            ///< register block (usart::usart1, ...)
  std::uint32_t irq;      ///< its interrupt number
  std::uint32_t pclk_hz;  ///< clock of its APB bus
  std::uint32_t baud;     ///< 115200 for the console
  std::uint8_t priority;  ///< interrupt priority (below the tick)
};

/// 8N1 USART with a receive ring and a transmit ring (127 bytes each), both filled/drained by the
/// USART interrupt. `read`/`write` are main-loop only and never block: `write` queues what fits.
///
/// Transmission is started by pending the USART interrupt after queueing: the handler writes
/// while TXE is set and keeps TXEIE on only while bytes remain. (QEMU's USART never raises the
/// TXE interrupt but always reads TXE = 1, so there one pended interrupt drains the ring.)
class UsartStream final : public hal::ByteStream {
 public:
  explicit UsartStream(const UsartConfig& config);

  /// Configures the USART (pins and clocks are the board's job) and enables its interrupt.
  /// Not ISR-safe; call once before interrupts are enabled.
  void start();

  /// Writes `text` by polling, bypassing the ring: for fault reports with interrupts disabled.
  /// Gives up on a byte after a bounded wait. Any context.
  static void emergency_write(Block usart, const char* text);

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override;
  /// Bytes dropped because the receive ring was full or the USART overran.
  std::uint32_t do_rx_dropped() const override {
    return rx_dropped_.load(std::memory_order_relaxed);
  }
  static void on_interrupt(void* self);

  UsartConfig config_;
  // Small: the console drains rx into its line editor every main-loop pass while a reply fits
  // in its output queue (~11.5 B/ms arrive at 115200 baud; it keeps no receive ring of its own,
  // so rx is where input waits: 127 B hold a whole 127-byte line, the most a host that waits for
  // each reply has in flight, docs/architecture.md) and keeps its replies in its own output queue
  // until tx has room; the main loop runs at least every tick (1 ms), so 128 B of tx (11 ms of
  // line time) keep the line busy.
  concurrency::SpscRing<128> rx_;
  concurrency::SpscRing<128> tx_;
  std::atomic<std::uint32_t> rx_dropped_{0u};
};

}  // namespace odocal::hal::stm32f4
