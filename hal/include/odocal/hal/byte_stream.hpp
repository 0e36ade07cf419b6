#pragma once
/// @file
/// Byte stream (console UART, pty, stdio).

#include <cstddef>
#include <cstdint>

namespace odocal::hal {

/// A non-blocking, full-duplex byte stream.
class ByteStream {
 public:
  /// Copies up to `capacity` received bytes into `out`; returns how many. Never blocks.
  /// Main-loop only (not ISR-safe).
  std::size_t read(std::uint8_t* out, std::size_t capacity) {
    if (out == nullptr || capacity == 0u) {
      return 0u;
    }
    return do_read(out, capacity);
  }

  /// Queues up to `size` bytes for sending; returns how many were accepted (fewer when the
  /// transmit queue is full). Never blocks. Main-loop only.
  std::size_t write(const std::uint8_t* data, std::size_t size) {
    if (data == nullptr || size == 0u) {
      return 0u;
    }
    return do_write(data, size);
  }

  /// Received bytes lost before `read` could return them (a receive buffer full, a hardware
  /// overrun), since start-up; 0 where nothing is ever lost (a pipe, a pty). Main-loop only.
  [[nodiscard]] std::uint32_t rx_dropped() const { return do_rx_dropped(); }

 protected:
  ~ByteStream() = default;

 private:
  virtual std::size_t do_read(std::uint8_t* out, std::size_t capacity) = 0;
  virtual std::size_t do_write(const std::uint8_t* data, std::size_t size) = 0;
  virtual std::uint32_t do_rx_dropped() const { return 0u; }
};

}  // namespace odocal::hal
