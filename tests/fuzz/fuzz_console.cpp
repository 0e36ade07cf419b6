// libFuzzer target: arbitrary bytes typed into the robot console (line editor, parser, dispatch
// into the drive loop, parameter table, store and UMBmark). Besides the sanitizers, it checks the
// protocol contract: every output line is `ok` [pairs], `err <code> <message>` or `# ...` (or one
// of ROSArduinoBridge's replies to its one-letter lines), no line exceeds the reply limit, and the
// parameters in force are always in range and accepted by the drive.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "odocal/console/console.hpp"
#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/pwm_output.hpp"
#include "odocal/sim/ram_block_store.hpp"

namespace {

// ROSArduinoBridge's replies (docs/console.md): `OK`, `Invalid Command`, or one or two whole
// numbers (`b`'s baud rate, `e`'s counts).
bool bridge_reply(const char* l, std::size_t n) {
  if ((n == 2u && std::memcmp(l, "OK", 2) == 0) ||
      (n == 15u && std::memcmp(l, "Invalid Command", 15) == 0)) {
    return true;
  }
  std::size_t i = 0u;
  for (int number = 0; number < 2 && i < n; ++number) {
    if (number == 1) {
      if (l[i] != ' ')
        return false;
      ++i;
    }
    if (i < n && l[i] == '-')
      ++i;
    const std::size_t digits = i;
    while (i < n && l[i] >= '0' && l[i] <= '9')
      ++i;
    if (i == digits)
      return false;
  }
  return n > 0u && i == n;
}

class NullPwm final : public odocal::hal::PwmOutput {
  void do_set_duty(float) override {}
};
class NullOutput final : public odocal::hal::DigitalOutput {
  void do_set(bool) override {}
};
class NullCritical final : public odocal::hal::CriticalSection {
  void do_enter() override {}
  void do_exit() override {}
};

// Hands out the fuzz input a few bytes at a time and checks every byte written back.
class CheckingStream final : public odocal::hal::ByteStream {
 public:
  CheckingStream(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  [[nodiscard]] bool drained() const { return pos_ == size_; }
  void finish() {
    if (line_length_ != 0u)
      check_line();
  }
  /// Echoed keystrokes are not protocol lines: from the first `echo on` only the sanitizers and
  /// the parameter invariants are checked.
  bool protocol_checks = true;

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    std::size_t n = size_ - pos_;
    if (n > capacity)
      n = capacity;
    if (n > 7u)
      n = 7u;  // uneven chunks exercise the ring and partial lines
    std::memcpy(out, data_ + pos_, n);
    pos_ += n;
    return n;
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    for (std::size_t i = 0; i < size; ++i) {
      const char c = static_cast<char>(data[i]);
      if (c == '\n') {
        check_line();
        line_length_ = 0u;
      } else if (c == '\b' && !protocol_checks) {
        // A terminal moves the cursor back: backspace echoes "\b \b", so a user who types and
        // erases for ever keeps one short visible line (bounded below), not an endless one.
        if (line_length_ > 0u)
          --line_length_;
      } else {
        if (line_length_ >= sizeof line_)
          __builtin_trap();  // longer than a reply after at most one line of typed echo
        line_[line_length_++] = c;
      }
    }
    return size;
  }
  void check_line() {
    if (!protocol_checks)
      return;
    const char* l = line_;
    const std::size_t n = line_length_;
    if (n >= 1u && l[0] == '#')
      return;
    if (n == 2u && std::memcmp(l, "ok", 2) == 0)
      return;
    if (n > 3u && std::memcmp(l, "ok ", 3) == 0)
      return;
    if (bridge_reply(l, n))
      return;
    if (n > 4u && std::memcmp(l, "err ", 4) == 0) {
      // err <code> <message>: a lower-case code followed by a space and a message.
      std::size_t i = 4u;
      while (i < n && ((l[i] >= 'a' && l[i] <= 'z') || l[i] == '_'))
        ++i;
      if (i > 4u && i + 1u < n && l[i] == ' ')
        return;
    }
    __builtin_trap();
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0u;
  // A reply, or (with echo) a typed line of at most max_line bytes, "^C" and a stream line
  // printed before the typed line ended.
  char line_[odocal::console::Console::max_reply + odocal::console::LineEditor::max_line + 4u] = {};
  std::size_t line_length_ = 0u;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace odocal;
  NullPwm pwm_l, pwm_r;
  NullOutput dir_l, dir_r;
  NullCritical critical;
  drive::ControlLoop loop{drive::MotorChannel{pwm_l, dir_l}, drive::MotorChannel{pwm_r, dir_r},
                          critical};
  static sim::StaticRamBlockStore<1024, 2, 4> flash;  // static: 2 KiB reset below, not reallocated
  std::memset(flash.memory(), 0xFF, 2048);
  params::ParamStore store(flash);
  CheckingStream stream(data, size);
  console::ConsoleOptions options;
  options.echo = console::EchoMode::off;
  options.crlf = false;
  console::Console console(stream, loop, store, options);
  std::uint32_t now = 0xFFFF0000u;  // wraps during the run
  (void)console.start(now);
  for (int i = 0; i < 200000 && !(stream.drained() && console.idle()); ++i) {
    now += 997u;
    console.poll(now);
    stream.protocol_checks = stream.protocol_checks && !console.echo_enabled();
    loop.tick(now);
    const params::ParamSet& in_force = console.params();
    if (!params::all_in_range(in_force) || !drive::valid(params::to_drive_config(in_force))) {
      __builtin_trap();
    }
  }
  if (!(stream.drained() && console.idle()))
    __builtin_trap();  // the console must keep up
  stream.finish();
  return 0;
}
