#pragma once
// Test rig: a console wired to a real ControlLoop (fake motor outputs), a RAM flash store and a
// scripted byte stream with fixed buffers (so a test can assert that polling allocates nothing).

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "fakes.hpp"
#include "odocal/console/console.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/sim/ram_block_store.hpp"

namespace odocal::test {

/// A byte stream fed from a fixed input buffer that records output in a fixed buffer.
class ScriptStream final : public hal::ByteStream {
 public:
  std::array<std::uint8_t, 16384> input{};
  std::size_t input_size = 0;
  std::size_t input_pos = 0;
  std::array<char, 1 << 17> output{};
  std::size_t output_size = 0;
  std::size_t read_limit = 1 << 20;   ///< bytes handed out per read call
  std::size_t write_limit = 1 << 20;  ///< bytes accepted per write call (0: a stalled link)
  std::uint32_t dropped = 0;          ///< what rx_dropped() says (bytes a UART would have lost)

  void type(const std::string& text) {
    if (text.size() > input.size() - input_size) {
      ADD_FAILURE() << "ScriptStream: more typed than its " << input.size() << " bytes";
      return;
    }
    std::copy(text.begin(), text.end(), input.begin() + static_cast<std::ptrdiff_t>(input_size));
    input_size += text.size();
  }
  [[nodiscard]] bool drained() const { return input_pos == input_size; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    std::size_t n = input_size - input_pos;
    if (n > capacity)
      n = capacity;
    if (n > read_limit)
      n = read_limit;
    std::memcpy(out, input.data() + input_pos, n);
    input_pos += n;
    return n;
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    std::size_t n = size < write_limit ? size : write_limit;
    if (n > output.size() - output_size)
      n = output.size() - output_size;
    std::memcpy(output.data() + output_size, data, n);
    output_size += n;
    return n;
  }
  std::uint32_t do_rx_dropped() const override { return dropped; }
};

using RigFlash = sim::StaticRamBlockStore<1024, 4, 4>;

/// Everything a console needs, on the host.
struct Rig {
  explicit Rig(console::ConsoleOptions options = quiet(), RigFlash* shared_flash = nullptr)
      : flash(shared_flash != nullptr ? *shared_flash : own_flash),
        store(flash),
        console(stream, loop, store, options) {}

  static console::ConsoleOptions quiet() {
    console::ConsoleOptions options;
    options.echo = console::EchoMode::off;
    options.crlf = false;
    options.banner = false;
    return options;
  }

  /// Polls until the console has answered everything typed (bounded).
  void settle() {
    for (int i = 0; i < 100000 && !(stream.drained() && console.idle()); ++i) {
      now_us += 100;
      console.poll(now_us);
    }
  }

  /// Types `line` + "\n", lets the console answer, returns the lines it printed.
  std::vector<std::string> send(const std::string& line) {
    const std::size_t mark = stream.output_size;
    stream.type(line + "\n");
    settle();
    return split_lines(mark);
  }

  /// The single reply line of a command (asserting there is exactly one non-# line).
  std::string reply(const std::string& line) {
    const auto lines = send(line);
    std::string result;
    int replies = 0;
    for (const auto& l : lines) {
      if (l.empty() || l[0] != '#') {
        result = l;
        ++replies;
      }
    }
    EXPECT_EQ(replies, 1) << "command: " << line;
    return result;
  }

  std::vector<std::string> split_lines(std::size_t from) const {
    std::vector<std::string> lines;
    std::string current;
    for (std::size_t i = from; i < stream.output_size; ++i) {
      const char c = stream.output[i];
      if (c == '\n') {
        if (!current.empty() && current.back() == '\r')
          current.pop_back();
        lines.push_back(current);
        current.clear();
      } else {
        current.push_back(c);
      }
    }
    if (!current.empty())
      lines.push_back(current);
    return lines;
  }

  /// Runs `n` control ticks of 1 ms.
  void tick(int n) {
    for (int i = 0; i < n; ++i) {
      now_us += 1000;
      loop.tick(now_us);
    }
  }

  FakePwm pwm_left, pwm_right;
  FakeOutput dir_left, dir_right;
  FakeCritical critical;
  drive::ControlLoop loop{drive::MotorChannel{pwm_left, dir_left},
                          drive::MotorChannel{pwm_right, dir_right}, critical};
  RigFlash own_flash;
  RigFlash& flash;
  params::ParamStore store;
  ScriptStream stream;
  console::Console console;
  std::uint32_t now_us = 1000;
};

/// Value of `key=` in a reply line ("" when absent).
inline std::string value_of(const std::string& line, const std::string& key) {
  const std::string needle = " " + key + "=";
  std::size_t at = line.find(needle);
  if (at == std::string::npos) {
    if (line.rfind(key + "=", 0) == 0) {
      at = 0;
    } else {
      return "";
    }
  } else {
    at += 1;
  }
  at += key.size() + 1;
  const std::size_t end = line.find(' ', at);
  return line.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

/// The error code of an `err` line ("" when it is not one).
inline std::string error_code(const std::string& line) {
  if (line.rfind("err ", 0) != 0)
    return "";
  const std::size_t end = line.find(' ', 4);
  return line.substr(4, end == std::string::npos ? std::string::npos : end - 4);
}

/// A number printed in a reply (asserting it is all number).
inline double number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  EXPECT_TRUE(!text.empty() && *end == '\0') << "not a number: '" << text << "'";
  return v;
}

/// Printed with 6 decimals: within 0.5e-6 of the stored float.
inline constexpr double kPrinted = 0.5e-6 + 1e-9;

/// Every reply line is `ok` + key=value pairs or `err <code> <message>`.
inline const std::regex kOkLine(R"(ok( [a-z_0-9]+=[^ =]+)*)");
inline const std::regex kErrLine(R"(err [a-z_]+ \S.*)");

/// A started console rig.
inline std::unique_ptr<Rig> make_rig(console::ConsoleOptions options = Rig::quiet(),
                                     RigFlash* flash = nullptr) {
  auto rig = std::make_unique<Rig>(options, flash);
  (void)rig->console.start(rig->now_us);
  return rig;
}

/// A refused command changes nothing: the parameters, provenance, unsaved flag and the drive
/// configuration are the same after it.
inline void expect_refused_without_change(Rig& rig, const std::string& command,
                                          const std::string& code) {
  const params::ParamSet before = rig.console.params();
  const bool unsaved_before = rig.console.unsaved();
  const drive::DriveConfig config_before = rig.loop.config();
  const std::string line = rig.reply(command);
  EXPECT_EQ(error_code(line), code) << command << " -> " << line;
  EXPECT_TRUE(std::regex_match(line, kErrLine)) << line;
  EXPECT_TRUE(params::same(before, rig.console.params())) << command;
  EXPECT_EQ(unsaved_before, rig.console.unsaved()) << command;
  const drive::DriveConfig after = rig.loop.config();
  EXPECT_EQ(std::memcmp(&config_before, &after, sizeof after), 0) << command;
}

}  // namespace odocal::test
