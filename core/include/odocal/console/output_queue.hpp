#pragma once
/// @file
/// The console's transmit queue: lines wait here until the byte stream accepts them.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/hal/byte_stream.hpp"

namespace odocal::console {

/// A byte FIFO of fixed capacity that never blocks: `push` takes a whole piece or nothing, and
/// `flush` hands the stream only what it accepts. Main-loop only.
class OutputQueue {
 public:
  static constexpr std::size_t capacity = 1024u;

  /// Appends `size` bytes, all or nothing. @return false (nothing queued) when they do not fit.
  bool push(const char* data, std::size_t size);
  /// Writes queued bytes to `stream` until it accepts fewer than offered. @return bytes written.
  std::size_t flush(hal::ByteStream& stream);
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t free_space() const { return capacity - size_; }

 private:
  std::array<std::uint8_t, capacity> bytes_{};
  std::size_t head_ = 0u;  ///< oldest byte
  std::size_t size_ = 0u;
};

}  // namespace odocal::console
