#pragma once
/// @file
/// The console's transmit queue: lines wait here until the byte stream accepts them.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/hal/byte_stream.hpp"

namespace odocal::console {

/// A byte FIFO of fixed capacity that never blocks: `push` takes a whole piece or nothing, and
/// `flush` hands the stream only what it accepts. The queued bytes always start at the front, so
/// the free space is one piece at `tail()`: a line is written there in place (no copy of it on
/// the stack) and queued by `commit`. Main-loop only.
class OutputQueue {
 public:
  /// A whole reply (max_reply, 560 B) plus room for stream lines while a command waits.
  static constexpr std::size_t capacity = 768u;

  /// Appends `size` bytes, all or nothing. @return false (nothing queued) when they do not fit.
  bool push(const char* data, std::size_t size);
  /// Writes queued bytes to `stream` (what it accepts) and moves the rest to the front.
  /// @return bytes written.
  std::size_t flush(hal::ByteStream& stream);
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t free_space() const { return capacity - size_; }
  /// The free space (`free_space()` bytes), where the next bytes will be queued.
  [[nodiscard]] char* tail() { return bytes_.data() + size_; }
  /// Queues the first `size` bytes written at `tail()` (at most `free_space()`).
  void commit(std::size_t size) { size_ += size < free_space() ? size : free_space(); }
  /// Drops what was queued after the first `size` bytes (not yet flushed: main loop, same pass).
  void truncate(std::size_t size) { size_ = size < size_ ? size : size_; }

 private:
  std::size_t size_ = 0u;
  std::array<char, capacity> bytes_;  // no initializer: only queued (written) bytes are read
};

}  // namespace odocal::console
