#include "odocal/console/line_editor.hpp"

namespace odocal::console {

LineEvent LineEditor::finish() {
  LineEvent event = LineEvent::line;
  if (too_long_) {
    event = LineEvent::too_long;
  } else if (bad_byte_) {
    event = LineEvent::bad_byte;
  } else {
    std::size_t i = 0;
    while (i < length_ && buffer_[i] == ' ') {
      ++i;
    }
    if (i == length_) {
      event = LineEvent::empty;
    }
  }
  completed_length_ = event == LineEvent::line ? length_ : 0u;
  buffer_[completed_length_] = '\0';
  length_ = 0u;
  too_long_ = false;
  bad_byte_ = false;
  return event;
}

LineEvent LineEditor::feed(std::uint8_t byte, Echo& echo) {
  echo.count = 0u;
  const bool after_cr = after_cr_;
  after_cr_ = byte == '\r';
  if (after_cr && byte == '\n') {
    return LineEvent::none;  // second half of CR LF
  }
  if (byte == '\r' || byte == '\n') {
    return finish();
  }
  if (byte == 0x08u || byte == 0x7Fu) {
    saw_terminal_ = true;
    if (length_ > 0u && !too_long_) {
      --length_;
      echo.bytes = {'\b', ' ', '\b'};
      echo.count = 3u;
    }
    return LineEvent::none;
  }
  if (byte == 0x03u) {
    length_ = 0u;
    too_long_ = false;
    bad_byte_ = false;
    return LineEvent::cancelled;
  }
  if (byte == '\t') {
    byte = ' ';
  }
  if (byte < 0x20u || byte > 0x7Eu) {
    bad_byte_ = true;
    return LineEvent::none;
  }
  if (length_ >= max_line) {
    too_long_ = true;
    return LineEvent::none;
  }
  buffer_[length_++] = static_cast<char>(byte);
  echo.bytes[0] = static_cast<char>(byte);
  echo.count = 1u;
  return LineEvent::none;
}

}  // namespace odocal::console
