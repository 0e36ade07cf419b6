#pragma once
/// @file
/// Assembles received bytes into command lines, with the editing a terminal user expects.

#include <array>
#include <cstddef>
#include <cstdint>

namespace odocal::console {

/// What a byte completed.
enum class LineEvent : std::uint8_t {
  none,       ///< the line goes on
  line,       ///< a line is ready in `line()` / `length()`
  empty,      ///< an empty (or all-space) line: not a command, no reply
  too_long,   ///< the line had more than `max_line` bytes: refused whole
  bad_byte,   ///< the line held a non-ASCII byte or a control byte: refused whole
  cancelled,  ///< Ctrl-C discarded the line: no reply
};

/// Bytes to echo for one input byte (at most 3: "\b \b").
struct Echo {
  std::array<char, 3> bytes{};
  std::uint8_t count = 0u;
};

/// Line editor. Rules (docs/console.md):
///  - CR, LF and CR LF end a line (the LF of a CR LF pair is swallowed);
///  - backspace (0x08) and DEL (0x7F) remove the last byte (echo "\b \b");
///  - TAB counts as a space; Ctrl-C (0x03) discards the line;
///  - a printable ASCII byte (0x20..0x7E) is appended; more than `max_line` of them make the
///    line too long: the rest is read and discarded up to the line end, then the line is refused;
///  - any other byte (>= 0x80, or a control byte) marks the line bad; it is refused at its end.
/// Main-loop only.
class LineEditor {
 public:
  /// Longest accepted line, bytes, not counting the terminator.
  static constexpr std::size_t max_line = 127u;

  /// Feeds one byte; `echo` receives what a terminal should show for it (the line end itself
  /// echoes nothing: the console writes its own newline).
  /// Out of line: inlined, its many exits each got a copy of the caller's echo handling.
  [[gnu::noinline]] LineEvent feed(std::uint8_t byte, Echo& echo);

  /// The completed line (valid after LineEvent::line until the next feed). Not NUL-terminated.
  [[nodiscard]] const char* line() const { return buffer_.data(); }
  [[nodiscard]] std::size_t length() const { return completed_length_; }

  /// The line being typed (not yet ended), for redrawing it after an asynchronous line.
  [[nodiscard]] const char* pending() const { return buffer_.data(); }
  [[nodiscard]] std::size_t pending_length() const { return too_long_ ? 0u : length_; }

  /// True once the input looked like a person at a terminal: a backspace/DEL. Used by
  /// EchoMode::automatic (a line ended by a bare CR, what picocom, screen and minicom send for
  /// Enter, is judged by the console, which knows what the line was: ROSArduinoBridge's client
  /// ends its lines so too).
  [[nodiscard]] bool saw_terminal() const { return saw_terminal_; }
  /// Forgets that: the input comes from a program again (a ROSArduinoBridge line).
  void forget_terminal() { saw_terminal_ = false; }

 private:
  LineEvent finish();

  std::size_t length_ = 0u;
  std::size_t completed_length_ = 0u;
  bool too_long_ = false;
  bool bad_byte_ = false;
  bool after_cr_ = false;
  bool saw_terminal_ = false;
  // No initializer: a byte is read only after it was written (the console is a static on the
  // robot, where zeroing it would be code that repeats what startup does).
  std::array<char, max_line + 1u> buffer_;
};

}  // namespace odocal::console
