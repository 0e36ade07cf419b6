#pragma once
/// @file
/// The console stream as the application sees it: the board's UART, with Ctrl-D taken out.

#include <cstddef>
#include <cstdint>

#include "odocal/hal/byte_stream.hpp"

namespace odocal::firmware {

/// Passes bytes through unchanged, except that Ctrl-D (0x04, end of transmission) is removed
/// and remembered: in the QEMU image it ends the session (semihosting exit). The robot image
/// does not use it (board_ends_session). Main-loop only.
class SessionStream final : public hal::ByteStream {
 public:
  explicit SessionStream(hal::ByteStream& uart) : uart_(uart) {}
  /// True once a Ctrl-D arrived.
  [[nodiscard]] bool end_requested() const { return end_requested_; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    const std::size_t got = uart_.read(out, capacity);
    std::size_t kept = 0u;
    for (std::size_t i = 0u; i < got; ++i) {
      if (out[i] == end_of_transmission) {
        end_requested_ = true;
      } else {
        out[kept++] = out[i];
      }
    }
    return kept;
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return uart_.write(data, size);
  }
  std::uint32_t do_rx_dropped() const override { return uart_.rx_dropped(); }

  static constexpr std::uint8_t end_of_transmission = 0x04u;
  hal::ByteStream& uart_;
  bool end_requested_ = false;
};

}  // namespace odocal::firmware
