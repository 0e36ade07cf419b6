#pragma once
/// @file
/// One console output line under construction, in fixed storage, and the error codes of
/// `err <code> <message>` replies (docs/console.md).

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "odocal/console/output_queue.hpp"
#include "odocal/console/text.hpp"

namespace odocal::console {

/// Error codes of `err <code> <message>` (docs/console.md). Each has one meaning.
enum class ErrorCode : std::uint8_t {
  line_too_long,      ///< more than 127 bytes before the line end
  non_ascii,          ///< a byte >= 0x80 or a control byte in the line
  unknown_command,    ///< first word is no command
  unknown_parameter,  ///< get/set of a name not in the table
  wrong_arity,        ///< too few or too many words for the command
  bad_argument,       ///< a keyword argument not among the allowed ones
  bad_number,         ///< not a strict finite decimal number (or not whole where required)
  out_of_range,       ///< a number outside the closed range of its parameter or argument
  busy,               ///< refused while a path runs / while the robot moves (docs)
  fault,              ///< the drive refuses motion until `stop` acknowledges its faults
  rejected,           ///< the drive refused the combination of values (cross-field rule)
  store_error,        ///< the block store failed
  store_empty,        ///< `load` found no saved parameters
  store_version,      ///< `load` found a record newer than this firmware
  umbmark_full,       ///< no room for another UMBmark run in that direction
  umbmark_failed,     ///< the UMBmark solver refused the runs (message says why)
  not_solved,         ///< `umbmark apply` / `lateral apply` without a successful solve
  no_trial,           ///< no such trial is kept (or the last one does not fit the command)
  lateral_full,       ///< no room for another lateral trial
  lateral_failed,     ///< the lateral solver refused the trials (message says why)
  store_corrupt,      ///< `load` found records, every one of them damaged
  no_sensors,         ///< `walls` on a robot without wall sensors
  count,              ///< not a code: how many there are (error_code_name names each)
};

/// The code as printed ("line_too_long", ...); "unknown" for ErrorCode::count and beyond.
[[nodiscard]] const char* error_code_name(ErrorCode code);

/// Longest output line, bytes (status with a target's own pairs).
inline constexpr std::size_t max_reply = 560u;
static_assert(OutputQueue::capacity >= max_reply + 8u + 128u,
              "the output queue holds a whole reply, its echo and line end, and stream lines");

/// Writes one output line: text and ` key=value` pairs appended in order into storage lent by a
/// `ReplyLine`; whatever does not fit is cut off. No heap. Not copyable (it points into its
/// line's storage).
class Reply {
 public:
  Reply(const Reply&) = delete;
  Reply& operator=(const Reply&) = delete;

  Reply& text(const char* s) { return bytes(s, std::strlen(s)); }
  Reply& bytes(const char* s, std::size_t n);
  /// " k=" (the value follows).
  Reply& key(const char* k) { return text(" ").text(k).text("="); }
  Reply& number(float value, int decimals);
  Reply& pair(const char* k, float value, int decimals) { return key(k).number(value, decimals); }
  /// A whole number, in decimal digits.
  Reply& unsigned_number(std::uint64_t value);
  Reply& pair_u(const char* k, std::uint64_t value) { return key(k).unsigned_number(value); }
  Reply& pair_i(const char* k, std::int64_t value);
  Reply& pair_s(const char* k, const char* value) { return key(k).text(value); }
  /// Lets `fill(out, capacity)` write into the free space; keeps the printable ASCII prefix.
  template <typename Fill>
  Reply& append_with(Fill fill) {
    char* out = buffer_ + length_;
    std::size_t n = fill(out, capacity_ - length_);
    if (n > capacity_ - length_) {
      n = capacity_ - length_;
    }
    std::size_t printable = 0u;
    while (printable < n && out[printable] >= 0x20 && out[printable] < 0x7f) {
      ++printable;
    }
    length_ += printable;
    return *this;
  }
  [[nodiscard]] const char* data() const { return buffer_; }
  [[nodiscard]] std::size_t size() const { return length_; }

 protected:
  Reply(char* buffer, std::size_t capacity) : buffer_(buffer), capacity_(capacity) {}
  ~Reply() = default;

 private:
  char* buffer_;
  std::size_t capacity_;
  std::size_t length_ = 0u;
};

/// A line written in place into the free space of an output queue (at most `max_reply` bytes,
/// leaving room for the line end): nothing is queued until the console sends it. One at a time
/// per queue (they would share the space); nothing else may be pushed while it is being written.
class ReplyLine : public Reply {
 public:
  explicit ReplyLine(OutputQueue& queue)
      : Reply(queue.tail(), queue.free_space() < max_reply + 2u
                                ? (queue.free_space() < 2u ? 0u : queue.free_space() - 2u)
                                : max_reply) {}
};

/// A ReplyLine that starts with "err <code> " (the message follows).
class ErrLine final : public ReplyLine {
 public:
  ErrLine(OutputQueue& queue, ErrorCode code);
};

/// A ReplyLine that starts with "ok" (the pairs follow).
class OkLine final : public ReplyLine {
 public:
  explicit OkLine(OutputQueue& queue);
};

}  // namespace odocal::console
