#include "config.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include "odocal/toolkit/numbers.hpp"

namespace odocal::linux_target {
namespace {

using hal::linux_gpiod::LinePin;

std::string trim(const std::string& text) {
  return std::string(toolkit::trim(text));
}

// A whole number in [lo, hi], digits only (the host toolkit's rule for every host program).
bool parse_unsigned(const std::string& text, unsigned long lo, unsigned long hi,
                    unsigned long& value) {
  const std::optional<std::uint64_t> parsed = toolkit::parse_whole_in(text, lo, hi);
  if (!parsed) {
    return false;
  }
  value = static_cast<unsigned long>(*parsed);
  return true;
}

// "[chip:]offset"; the chip may itself contain ':' only as a path, so split at the last one.
bool parse_line(const std::string& text, const std::string& default_chip, LinePin& pin) {
  const std::size_t colon = text.rfind(':');
  const std::string chip = colon == std::string::npos ? default_chip : text.substr(0u, colon);
  const std::string offset = colon == std::string::npos ? text : text.substr(colon + 1u);
  unsigned long value = 0u;
  if (chip.empty() || !parse_unsigned(offset, 0u, 1023u, value)) {
    return false;
  }
  pin.chip = chip;
  pin.offset = static_cast<unsigned int>(value);
  return true;
}

// "pwmchipN:M" or "none".
bool parse_pwm(const std::string& text, PwmSpec& spec) {
  if (text == "none") {
    spec.sysfs = false;
    return true;
  }
  const std::string prefix = "pwmchip";
  const std::size_t colon = text.find(':');
  unsigned long chip = 0u;
  unsigned long channel = 0u;
  if (text.compare(0u, prefix.size(), prefix) != 0 || colon == std::string::npos ||
      !parse_unsigned(text.substr(prefix.size(), colon - prefix.size()), 0u, 1023u, chip) ||
      !parse_unsigned(text.substr(colon + 1u), 0u, 1023u, channel)) {
    return false;
  }
  spec.sysfs = true;
  spec.chip = static_cast<unsigned int>(chip);
  spec.channel = static_cast<unsigned int>(channel);
  return true;
}

enum class Kind { line, optional_line, pwm, number, priority, text };

struct Key {
  const char* name;
  Kind kind;
  bool required;
};

constexpr Key kKeys[] = {
    {"chip", Kind::text, false},
    {"left_a", Kind::line, true},
    {"left_b", Kind::line, true},
    {"right_a", Kind::line, true},
    {"right_b", Kind::line, true},
    {"left_dir", Kind::line, true},
    {"right_dir", Kind::line, true},
    {"enable", Kind::optional_line, false},
    {"left_pwm", Kind::pwm, true},
    {"right_pwm", Kind::pwm, true},
    {"left_pwm_gpio", Kind::optional_line, false},
    {"right_pwm_gpio", Kind::optional_line, false},
    {"pwm_hz", Kind::number, false},
    {"soft_pwm_hz", Kind::number, false},
    {"event_priority", Kind::priority, false},
    {"tick_priority", Kind::priority, false},
    {"pwm_priority", Kind::priority, false},
    {"event_holdback_us", Kind::number, false},
    {"store", Kind::text, false},
};
constexpr std::size_t kKeyCount = sizeof(kKeys) / sizeof(kKeys[0]);

/// The file's values as written, by key (index into kKeys), and the line each came from (0: not
/// given).
struct RawConfig {
  std::string values[kKeyCount];
  int lines[kKeyCount] = {};
};

/// The first pass: splits the file into `key = value` lines, refusing a malformed line, an
/// unknown or repeated key and an empty value. Nothing is interpreted yet, so `chip` is known
/// before any line is read.
bool read_raw(const std::string& text, const std::string& name, RawConfig& raw_config,
              std::string& error) {
  std::istringstream input(text);
  std::string raw;
  int number = 0;
  while (std::getline(input, raw)) {
    ++number;
    const std::string where = name + ":" + std::to_string(number) + ": ";
    const std::size_t hash = raw.find('#');
    const std::string line = trim(hash == std::string::npos ? raw : raw.substr(0u, hash));
    if (line.empty()) {
      continue;
    }
    const std::size_t equals = line.find('=');
    if (equals == std::string::npos) {
      error = where + "expected `key = value`, got \"" + line + "\"";
      return false;
    }
    const std::string key = trim(line.substr(0u, equals));
    const std::string value = trim(line.substr(equals + 1u));
    std::size_t index = kKeyCount;
    for (std::size_t k = 0; k < kKeyCount; ++k) {
      if (key == kKeys[k].name) {
        index = k;
      }
    }
    if (index == kKeyCount) {
      error = where + "unknown key \"" + key + "\" (see odocal-linux --help)";
      return false;
    }
    if (raw_config.lines[index] != 0) {
      error = where + "key \"" + key + "\" repeated (first on line " +
              std::to_string(raw_config.lines[index]) + ")";
      return false;
    }
    if (value.empty()) {
      error = where + "key \"" + key + "\" has no value";
      return false;
    }
    raw_config.values[index] = value;
    raw_config.lines[index] = number;
  }
  return true;
}

/// Parses the value of key `k` into its place in `parsed`. @return false with `expected` saying
/// what the key takes.
bool parse_value(std::size_t k, const std::string& value, const std::string& default_chip,
                 LinuxConfig& parsed, std::string& expected) {
  const Key& key = kKeys[k];
  LinePin* line_targets[] = {nullptr,           &parsed.left_a,        &parsed.left_b,
                             &parsed.right_a,   &parsed.right_b,       &parsed.left_dir,
                             &parsed.right_dir, &parsed.enable,        nullptr,
                             nullptr,           &parsed.left_pwm.gpio, &parsed.right_pwm.gpio};
  bool ok = true;
  unsigned long number_value = 0u;
  switch (key.kind) {
    case Kind::line:
    case Kind::optional_line:
      ok = parse_line(value, default_chip, *line_targets[k]);
      line_targets[k]->role = key.name;
      expected = "a line offset or chip:offset";
      break;
    case Kind::pwm:
      ok = parse_pwm(value, k == 8u ? parsed.left_pwm : parsed.right_pwm);
      expected = "pwmchipN:CHANNEL or none";
      break;
    case Kind::number:
      if (std::strcmp(key.name, "pwm_hz") == 0) {
        ok = parse_unsigned(value, 1u, 10000000u, number_value);
        parsed.pwm_hz = static_cast<std::uint32_t>(number_value);
        expected = "a whole number of Hz in 1..10000000";
      } else if (std::strcmp(key.name, "soft_pwm_hz") == 0) {
        ok = parse_unsigned(value, 1u, 5000u, number_value);
        parsed.soft_pwm_hz = static_cast<std::uint32_t>(number_value);
        expected = "a whole number of Hz in 1..5000";
      } else {
        ok = parse_unsigned(value, 0u, 100000u, number_value);
        parsed.event_holdback_us = static_cast<std::uint32_t>(number_value);
        expected = "a whole number of microseconds in 0..100000";
      }
      break;
    case Kind::priority:
      ok = parse_unsigned(value, 0u, 99u, number_value);
      expected = "a SCHED_FIFO priority 0..99 (0: normal scheduling)";
      if (std::strcmp(key.name, "event_priority") == 0) {
        parsed.event_priority = static_cast<int>(number_value);
      } else if (std::strcmp(key.name, "tick_priority") == 0) {
        parsed.tick_priority = static_cast<int>(number_value);
      } else {
        parsed.pwm_priority = static_cast<int>(number_value);
      }
      break;
    case Kind::text:
      if (std::strcmp(key.name, "store") == 0) {
        parsed.store = value;
      }
      break;
  }
  return ok;
}

/// The second pass: every key's value parsed into `parsed`, in the table's order, with the
/// required keys and a PWM for each motor present.
bool parse_values(const RawConfig& raw, const std::string& name, LinuxConfig& parsed,
                  std::string& error) {
  const std::string default_chip = raw.lines[0] != 0 ? raw.values[0] : std::string("gpiochip0");
  for (std::size_t k = 0; k < kKeyCount; ++k) {
    const Key& key = kKeys[k];
    const std::string where = name + ":" + std::to_string(raw.lines[k]) + ": ";
    if (raw.lines[k] == 0) {
      if (key.required) {
        error = name + ": missing required key \"" + key.name + "\"";
        return false;
      }
      continue;
    }
    const std::string& value = raw.values[k];
    std::string expected;
    if (!parse_value(k, value, default_chip, parsed, expected)) {
      error = where + "bad value \"" + value + "\" for \"" + key.name + "\": expected " + expected;
      return false;
    }
  }
  parsed.has_enable = raw.lines[7] != 0;
  parsed.left_pwm.has_gpio = raw.lines[10] != 0;
  parsed.right_pwm.has_gpio = raw.lines[11] != 0;
  for (PwmSpec* spec : {&parsed.left_pwm, &parsed.right_pwm}) {
    if (!spec->sysfs && !spec->has_gpio) {
      const bool left = spec == &parsed.left_pwm;
      error = name + ": " + (left ? "left_pwm" : "right_pwm") + " is none and no " +
              (left ? "left_pwm_gpio" : "right_pwm_gpio") + " is given: the motor has no PWM";
      return false;
    }
  }
  return true;
}

/// One line, one signal: refuses two roles on the same GPIO line or the same PWM channel.
bool check_lines_distinct(const LinuxConfig& parsed, const std::string& name, std::string& error) {
  const LinePin* used[] = {&parsed.left_a,
                           &parsed.left_b,
                           &parsed.right_a,
                           &parsed.right_b,
                           &parsed.left_dir,
                           &parsed.right_dir,
                           parsed.has_enable ? &parsed.enable : nullptr,
                           parsed.left_pwm.has_gpio ? &parsed.left_pwm.gpio : nullptr,
                           parsed.right_pwm.has_gpio ? &parsed.right_pwm.gpio : nullptr};
  const std::size_t used_count = sizeof(used) / sizeof(used[0]);
  for (std::size_t i = 0; i < used_count; ++i) {
    for (std::size_t j = i + 1u; j < used_count; ++j) {
      if (used[i] != nullptr && used[j] != nullptr && used[i]->chip == used[j]->chip &&
          used[i]->offset == used[j]->offset) {
        error = name + ": " + used[i]->role + " and " + used[j]->role + " both use " +
                used[i]->chip + " line " + std::to_string(used[i]->offset);
        return false;
      }
    }
  }
  if (parsed.left_pwm.sysfs && parsed.right_pwm.sysfs &&
      parsed.left_pwm.chip == parsed.right_pwm.chip &&
      parsed.left_pwm.channel == parsed.right_pwm.channel) {
    error = name + ": left_pwm and right_pwm both use pwmchip" +
            std::to_string(parsed.left_pwm.chip) + ":" + std::to_string(parsed.left_pwm.channel);
    return false;
  }
  return true;
}

}  // namespace

bool parse_config(const std::string& text, const std::string& name, LinuxConfig& config,
                  std::string& error) {
  // Two passes: `chip` is the default for every line, wherever it appears in the file.
  RawConfig raw;
  LinuxConfig parsed;
  if (!read_raw(text, name, raw, error) || !parse_values(raw, name, parsed, error) ||
      !check_lines_distinct(parsed, name, error)) {
    return false;
  }
  config = parsed;
  return true;
}

bool load_config(const std::string& path, LinuxConfig& config, std::string& error) {
  std::ifstream file(path);
  if (!file) {
    error = path + ": cannot read the configuration file (" + std::strerror(errno) + ")";
    return false;
  }
  std::ostringstream text;
  text << file.rdbuf();
  return parse_config(text.str(), path, config, error);
}

const char* config_reference() {
  return R"(Configuration file (default /etc/odocal/odocal-linux.conf): `key = value` lines, `#` comments.
A line is `OFFSET` on the default chip or `CHIP:OFFSET`; CHIP is a name (gpiochip0), a path
(/dev/gpiochip0), a label (pinctrl-bcm2711) or a number.

  chip = gpiochip0          default chip for lines given as a bare offset
  left_a = 17               left encoder channel A (required; both edges)
  left_b = 27               left encoder channel B (required)
  right_a = 22              right encoder channel A (required)
  right_b = 23              right encoder channel B (required)
  left_dir = 5              left motor direction output, high = forward (required)
  right_dir = 6             right motor direction output (required)
  enable = 26               motor driver enable output, high while running (optional)
  left_pwm = pwmchip0:0     sysfs PWM chip:channel for the left motor, or none (required)
  right_pwm = pwmchip0:1    same for the right motor (required)
  left_pwm_gpio = 12        software PWM line used when left_pwm is none or missing
                            (LOW PRECISION: timed by a thread; optional)
  right_pwm_gpio = 13       same for the right motor (optional)
  pwm_hz = 20000            sysfs PWM carrier, Hz (1..10000000)
  soft_pwm_hz = 200         software PWM carrier, Hz (1..5000)
  event_priority = 45       SCHED_FIFO priority of the encoder-event thread (0 = normal)
  tick_priority = 40        SCHED_FIFO priority of the control tick thread (0 = normal)
  pwm_priority = 30         SCHED_FIFO priority of software PWM threads (0 = normal)
  event_holdback_us = 1000  how long an edge waits for older edges of the other lines (0..100000)
  store = /var/lib/odocal/params.bin   parameter store file (written atomically)

Keep the priorities below 50: the kernel's GPIO interrupt threads run at 50 and decide each
event's edge type; the event thread above the tick thread.
)";
}

}  // namespace odocal::linux_target
