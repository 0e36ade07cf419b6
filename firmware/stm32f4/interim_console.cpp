#include "interim_console.hpp"

#include <cstring>

#include "runtime.hpp"

namespace odocal::firmware {
namespace {

constexpr const char* prompt = "> ";
constexpr const char* version = "0.1.0";
constexpr std::size_t max_tokens = 5u;

struct Token {
  const char* text;
  std::size_t length;
  bool is(const char* word) const {
    return std::strlen(word) == length && std::memcmp(word, text, length) == 0;
  }
};

std::size_t split(char* line, std::size_t length, Token* tokens) {
  std::size_t count = 0u;
  std::size_t i = 0u;
  while (i < length) {
    while (i < length && line[i] == ' ') {
      ++i;
    }
    const std::size_t start = i;
    while (i < length && line[i] != ' ') {
      ++i;
    }
    if (i > start) {
      if (count == max_tokens) {
        return max_tokens + 1u;
      }
      tokens[count++] = Token{line + start, i - start};
    }
  }
  return count;
}

/// Strict decimal: [-]digits[.digits], nothing else.
bool parse(const Token& token, float& value) {
  std::size_t i = 0u;
  bool negative = false;
  if (i < token.length && (token.text[i] == '-' || token.text[i] == '+')) {
    negative = token.text[i] == '-';
    ++i;
  }
  float result = 0.0f;
  float scale = 1.0f;
  bool digits = false;
  bool point = false;
  for (; i < token.length; ++i) {
    const char c = token.text[i];
    if (c == '.' && !point) {
      point = true;
    } else if (c >= '0' && c <= '9') {
      digits = true;
      if (point) {
        scale *= 0.1f;
        result += scale * static_cast<float>(c - '0');
      } else {
        result = result * 10.0f + static_cast<float>(c - '0');
      }
    } else {
      return false;
    }
  }
  if (!digits || result > 1.0e6f) {
    return false;
  }
  value = negative ? -result : result;
  return true;
}

}  // namespace

InterimConsole::InterimConsole(hal::ByteStream& stream, drive::ControlLoop& loop,
                               hal::stm32f4::SysTickTimer& timer, hal::BlockStore&,
                               const BoardInfo& info, bool watchdog_reset)
    : stream_(stream), loop_(loop), timer_(timer), info_(info), watchdog_reset_(watchdog_reset) {}

void InterimConsole::put(const char* text) {
  const std::size_t n = std::strlen(text);
  std::size_t done = 0u;
  while (done < n) {  // the ring drains under interrupts; a full ring only waits for the UART
    done += stream_.write(reinterpret_cast<const std::uint8_t*>(text) + done, n - done);
  }
}

void InterimConsole::put_unsigned(std::uint32_t value) {
  char digits[11];
  std::size_t n = 0u;
  do {
    digits[n++] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u);
  char text[11];
  for (std::size_t i = 0u; i < n; ++i) {
    text[i] = digits[n - 1u - i];
  }
  text[n] = '\0';
  put(text);
}

void InterimConsole::put_number(float value, int decimals) {
  if (value < 0.0f) {
    put("-");
    value = -value;
  }
  std::uint32_t scale = 1u;
  for (int i = 0; i < decimals; ++i) {
    scale *= 10u;
  }
  const auto scaled = static_cast<std::uint32_t>(value * static_cast<float>(scale) + 0.5f);
  put_unsigned(scaled / scale);
  if (decimals > 0) {
    put(".");
    std::uint32_t fraction = scaled % scale;
    for (std::uint32_t digit = scale / 10u; digit > 0u; digit /= 10u) {
      const char c[2] = {static_cast<char>('0' + fraction / digit), '\0'};
      put(c);
      fraction %= digit;
    }
  }
}

void InterimConsole::reply(const char* text) {
  put(text);
  put("\r\n");
}

void InterimConsole::begin() {
  put("\r\nodocal-fw ");
  put(version);
  put(" board=");
  put(info_.name);
  put(" clock=");
  put(hal::stm32f4::clock_source_name(info_.clock.source));
  put(watchdog_reset_ ? " reset=watchdog" : "");
  put("\r\n");
  put(prompt);
}

bool InterimConsole::poll() {
  std::uint8_t bytes[32];
  const std::size_t n = stream_.read(bytes, sizeof(bytes));
  for (std::size_t i = 0u; i < n; ++i) {
    const std::uint8_t byte = bytes[i];
    if (byte == 0x04u) {  // Ctrl-D: end of session (QEMU exits with status 0)
      put("\r\nbye\r\n");
      loop_.stop();
      exit_program(0);
    }
    if (byte == '\r' || byte == '\n') {
      put("\r\n");
      if (overflow_) {
        reply("err 3 line too long");
      } else if (length_ > 0u) {
        handle_line();
      }
      length_ = 0u;
      overflow_ = false;
      put(prompt);
      continue;
    }
    if (length_ < sizeof(line_) - 1u) {
      line_[length_++] = static_cast<char>(byte);
      const char echo[2] = {static_cast<char>(byte), '\0'};
      put(echo);
    } else {
      overflow_ = true;
    }
  }
  return n > 0u;
}

void InterimConsole::handle_line() {
  Token tokens[max_tokens];
  const std::size_t count = split(line_, length_, tokens);
  if (count == 0u) {
    return;
  }
  const Token& command = tokens[0];
  if (command.is("version") && count == 1u) {
    put("ok version=");
    put(version);
    put(" board=");
    put(info_.name);
    reply("");
  } else if (command.is("status") && count == 1u) {
    const drive::LoopStatus s = loop_.status();
    put("ok mode=");
    put(drive::mode_name(s.mode));
    put(" path=");
    put(drive::path_name(s.path));
    put(" faults=");
    put_unsigned(s.faults);
    put(" ticks=");
    put_unsigned(s.ticks);
    put(" uptime_ms=");
    put_unsigned(timer_.now_us() / 1000u);
    put(" tick_us_avg=");
    put_number(s.tick_us_avg, 3);
    put(" tick_us_max=");
    put_number(s.tick_us_max, 3);
    put(" illegal_left=");
    put_unsigned(s.illegal_left);
    put(" illegal_right=");
    put_unsigned(s.illegal_right);
    put(" left_radps=");
    put_number(s.left_radps, 3);
    put(" right_radps=");
    put_number(s.right_radps, 3);
    put(" left_duty=");
    put_number(s.left_duty, 3);
    put(" right_duty=");
    put_number(s.right_duty, 3);
    put(" clock=");
    put(hal::stm32f4::clock_source_name(info_.clock.source));
    reply("");
  } else if (command.is("odom") && (count == 1u || (count == 2u && tokens[1].is("reset")))) {
    if (count == 2u) {
      loop_.reset_pose();
    }
    const drive::Pose pose = loop_.pose();
    put("ok x_mm=");
    put_number(pose.x_m * 1000.0f, 2);
    put(" y_mm=");
    put_number(pose.y_m * 1000.0f, 2);
    put(" theta_deg=");
    put_number(pose.theta_rad * 57.29578f, 3);
    reply("");
  } else if (command.is("drive") && (count == 3u || count == 4u)) {
    float v = 0.0f;
    float w = 0.0f;
    float ms = 0.0f;
    if (!parse(tokens[1], v) || !parse(tokens[2], w) || (count == 4u && !parse(tokens[3], ms)) ||
        ms < 0.0f) {
      reply("err 4 bad number");
    } else if (!loop_.drive(drive::Twist{v, w}, static_cast<std::uint32_t>(ms))) {
      reply("err 6 refused");
    } else {
      reply("ok");
    }
  } else if (command.is("stop") && count == 1u) {
    loop_.stop();
    reply("ok");
  } else if (command.is("run") && count == 3u) {
    float side = 0.0f;
    if (!parse(tokens[2], side) || side <= 0.0f || side > 20.0f) {
      reply("err 4 bad number");
      return;
    }
    drive::Path path{};
    if (tokens[1].is("umbmark-cw")) {
      path = drive::make_umbmark_square(true, side);
    } else if (tokens[1].is("umbmark-ccw")) {
      path = drive::make_umbmark_square(false, side);
    } else if (tokens[1].is("line")) {
      path = drive::make_line(side);
    } else {
      reply("err 2 unknown path");
      return;
    }
    reply(loop_.run(path) ? "ok" : "err 6 refused");
  } else {
    reply("err 1 unknown command");
  }
}

}  // namespace odocal::firmware
