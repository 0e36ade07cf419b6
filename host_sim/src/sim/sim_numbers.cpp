#include "odocal/host/sim_numbers.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace odocal::host {
namespace {

std::string number_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

bool plain_decimal(const std::string& text) {
  // strtod also reads hex, "nan", "inf" and leading blanks: only digits, one sign, a point and
  // an exponent are a number here.
  if (text.empty()) {
    return false;
  }
  for (const char c : text) {
    const bool allowed =
        (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E';
    if (!allowed) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::optional<double> parse_real(const std::string& text) {
  if (!plain_decimal(text)) {
    return std::nullopt;
  }
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::uint64_t> parse_whole(const std::string& text) {
  if (text.empty() || text.size() > 20u) {
    return std::nullopt;
  }
  for (const char c : text) {
    if (c < '0' || c > '9') {
      return std::nullopt;
    }
  }
  errno = 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || errno == ERANGE) {
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(value);
}

CLI::Validator real_in(double lo, double hi, const std::string& unit, bool zero_allowed) {
  const std::string range = (zero_allowed ? "0 or " : "") + number_text(lo) + " to " +
                            number_text(hi) + (unit.empty() ? "" : " " + unit);
  return CLI::Validator(
      [lo, hi, range, zero_allowed](std::string& text) -> std::string {
        const std::optional<double> value = parse_real(text);
        if (!value) {
          return "'" + text + "' is not a number (expected " + range + ")";
        }
        if (zero_allowed && *value == 0.0) {
          return {};
        }
        if (!(*value >= lo && *value <= hi)) {
          return text + " is outside " + range;
        }
        return {};
      },
      range);
}

CLI::Validator whole_in(std::uint64_t lo, std::uint64_t hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        const std::optional<std::uint64_t> value = parse_whole(text);
        if (!value) {
          return "'" + text + "' is not a whole number (expected " + range + ")";
        }
        if (*value < lo || *value > hi) {
          return text + " is outside " + range;
        }
        return {};
      },
      range);
}

}  // namespace odocal::host
