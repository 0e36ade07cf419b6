#pragma once
/// @file
/// A byte stream that appends the Linux target's own figures to the console's `status` reply.

#include <cstddef>
#include <cstdint>
#include <string>

#include "odocal/hal/byte_stream.hpp"

namespace odocal::linux_target {

/// Writes ` key=value` pairs (with a leading space) into `out`, at most `capacity` bytes;
/// returns how many. Main loop.
using StatusPairs = std::size_t (*)(void* context, char* out, std::size_t capacity);

/// Passes everything through to `inner`, except that the reply line of `status` (it starts with
/// `ok mode=` and carries `ticks=`) gets the pairs of `pairs` appended before its line end.
/// Bytes that cannot start such a line go through at once (echo stays immediate). Holds at most
/// `max_queued` bytes the inner stream has not taken yet; beyond that `write` accepts fewer
/// bytes, as a full UART queue would. Main-loop only.
class StatusStream final : public hal::ByteStream {
 public:
  static constexpr std::size_t max_queued = 8192u;

  StatusStream(hal::ByteStream& inner, StatusPairs pairs, void* context)
      : inner_(inner), pairs_(pairs), context_(context) {}

  /// Writes what is queued to the inner stream; call from the main loop.
  void flush();

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override;
  void finish_line();

  hal::ByteStream& inner_;
  StatusPairs pairs_;
  void* context_;
  std::string line_;    // the start of a line that may be the status reply
  std::string queued_;  // ready for the inner stream
};

}  // namespace odocal::linux_target
