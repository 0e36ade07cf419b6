#include "odocal/host/motion.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "odocal/console/commands.hpp"
#include "odocal/console/text.hpp"

namespace odocal::host {
namespace {

// The motion the robot reads from `line`; `as_given` when it would refuse the line (a length out of
// its range, say): sent as it is, the robot refuses it and the session says so.
Motion read(const char* line, const Motion& as_given) {
  return Motion::of_command(line).value_or(as_given);
}

std::optional<float> argument(const console::Token& token, float lo, float hi, bool whole) {
  float value = 0.0f;
  if (console::read_number_arg(token, lo, hi, whole, value) != console::NumberArg::ok) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

// The factories write the line from the numbers given (rounded once, from the double) and take
// the motion the robot reads from it.
Motion Motion::square(bool clockwise, double side_m) {
  char text[64];
  std::snprintf(text, sizeof text, "run umbmark-%s %.3f", clockwise ? "cw" : "ccw", side_m);
  Motion m;
  m.kind = clockwise ? Kind::square_cw : Kind::square_ccw;
  m.length_m = static_cast<float>(side_m);
  return read(text, m);
}

Motion Motion::line(double length_m) {
  char text[64];
  std::snprintf(text, sizeof text, "run line %.3f", length_m);
  Motion m;
  m.kind = Kind::line;
  m.length_m = static_cast<float>(length_m);
  return read(text, m);
}

Motion Motion::unseen() {
  return Motion{};
}

Motion Motion::timed(double v_mps, double w_radps, double ms) {
  char text[96];
  std::snprintf(text, sizeof text, "drive %.4f %.4f %ld", v_mps, w_radps, std::lround(ms));
  Motion m;
  m.kind = Kind::timed;
  m.v_mps = static_cast<float>(v_mps);
  m.w_radps = static_cast<float>(w_radps);
  m.ms = ms > 0.0 && ms < 4.0e9 ? static_cast<std::uint32_t>(std::lround(ms)) : 0u;
  return read(text, m);
}

Motion Motion::selftest(Wheels wheels) {
  Motion m;
  m.kind = Kind::selftest;
  m.wheels = wheels;
  return m;
}

// `value` with at least `decimals` decimals, and as many more as the robot needs to read back the
// very same float (a motion read from a line with more digits than the usual keeps them: the
// line that started it and the one written for it start the same motion).
std::string number_text(float value, int decimals) {
  char text[48];
  for (int d = decimals; d <= 9; ++d) {
    std::snprintf(text, sizeof text, "%.*f", d, static_cast<double>(value));
    const console::Token token{text, std::strlen(text)};
    float read = 0.0f;
    if (console::read_number_arg(token, -1.0e6f, 1.0e6f, false, read) == console::NumberArg::ok &&
        read == value) {
      break;
    }
  }
  return text;
}

std::string Motion::command() const {
  switch (kind) {
    case Kind::square_cw:
    case Kind::square_ccw:
      return std::string("run umbmark-") + (kind == Kind::square_cw ? "cw " : "ccw ") +
             number_text(length_m, 3);
    case Kind::line:
      return "run line " + number_text(length_m, 3);
    case Kind::unseen:
      return "run unseen";
    case Kind::timed:
      return "drive " + number_text(v_mps, 4) + " " + number_text(w_radps, 4) + " " +
             std::to_string(ms);
    case Kind::selftest:
      break;
  }
  return wheels == Wheels::left    ? "selftest left"
         : wheels == Wheels::right ? "selftest right"
                                   : "selftest";
}

std::optional<Motion> Motion::of_command(const std::string& line) {
  std::array<console::Token, 6> words{};
  const std::size_t count = console::split(line.data(), line.size(), words.data(), words.size());
  const console::FormLookup lookup = console::find_form(words.data(), count);
  if (lookup.result != console::FormLookup::Result::found) {
    return std::nullopt;
  }
  Motion m;
  switch (lookup.form->handler) {
    case console::Handler::run_umbmark_cw:
    case console::Handler::run_umbmark_ccw:
    case console::Handler::run_line: {
      const std::optional<float> length =
          argument(words[2], console::run_length_min_m, console::run_length_max_m, false);
      if (!length) {
        return std::nullopt;
      }
      m.kind = lookup.form->handler == console::Handler::run_line         ? Kind::line
               : lookup.form->handler == console::Handler::run_umbmark_cw ? Kind::square_cw
                                                                          : Kind::square_ccw;
      m.length_m = *length;
      return m;
    }
    case console::Handler::run_unseen:
      return m;
    case console::Handler::drive: {
      if (count != 4u) {
        return std::nullopt;  // a drive without its duration runs until stopped: not a run
      }
      const auto v =
          argument(words[1], -console::drive_v_limit_mps, console::drive_v_limit_mps, false);
      const auto w =
          argument(words[2], -console::drive_w_limit_radps, console::drive_w_limit_radps, false);
      const auto ms = argument(words[3], 0.0f, console::drive_ms_max, true);
      if (!v || !w || !ms) {
        return std::nullopt;
      }
      m.kind = Kind::timed;
      m.v_mps = *v;
      m.w_radps = *w;
      m.ms = static_cast<std::uint32_t>(*ms);
      return m;
    }
    case console::Handler::selftest:
      m.kind = Kind::selftest;
      if (count == 2u) {
        if (!words[1].is("left") && !words[1].is("right")) {
          return std::nullopt;
        }
        m.wheels = words[1].is("left") ? Wheels::left : Wheels::right;
      }
      return m;
    default:
      return std::nullopt;
  }
}

std::optional<drive::Path> Motion::path() const {
  switch (kind) {
    case Kind::square_cw:
    case Kind::square_ccw:
      return drive::make_umbmark_square(kind == Kind::square_cw, length_m);
    case Kind::line:
      return drive::make_line(length_m);
    case Kind::unseen:
      return drive::make_unseen_path();
    case Kind::timed: {
      drive::Path path;
      const double t_s = ms / 1000.0;
      static_cast<void>(path.push(
          drive::Segment{static_cast<float>(v_mps * t_s), static_cast<float>(w_radps * t_s)}));
      return path;
    }
    case Kind::selftest:
      break;
  }
  return std::nullopt;
}

}  // namespace odocal::host
