#include "odocal/toolkit/numbers.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace odocal::toolkit {

NumberText read_number(std::string_view text, double& value) {
  // Only plain decimal notation: strtod alone would also take blanks, "nan", "inf" and hex.
  if (text.empty() || text.find_first_not_of("0123456789+-.eE") != std::string_view::npos) {
    return NumberText::not_a_number;
  }
  // strtod rather than from_chars: it takes a leading '+', and tells an overflow (HUGE_VAL) from
  // an underflow, which is a number. The host programs never change the "C" locale.
  const std::string copy(text);
  errno = 0;
  char* end = nullptr;
  const double parsed = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size()) {
    return NumberText::not_a_number;
  }
  if (!std::isfinite(parsed)) {
    return NumberText::out_of_range;
  }
  // ERANGE with a finite result is an underflow: 1e-310 is a subnormal double, 1e-400 rounds to
  // zero. Both are numbers (far below any measurement's resolution), taken as they round.
  value = parsed;
  return NumberText::ok;
}

std::optional<double> parse_real(std::string_view text) {
  double value = 0.0;
  if (read_number(text, value) != NumberText::ok) {
    return std::nullopt;
  }
  return value;
}

namespace {

template <typename Integer>
std::optional<Integer> parse_integral(std::string_view text) {
  // from_chars takes no blanks and no '+'; for an unsigned type no '-' either.
  if (text.empty()) {
    return std::nullopt;
  }
  Integer value = 0;
  const char* const last = text.data() + text.size();
  const auto [end, error] = std::from_chars(text.data(), last, value, 10);
  if (error != std::errc() || end != last) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

std::optional<std::uint64_t> parse_whole(std::string_view text) {
  return parse_integral<std::uint64_t>(text);
}

std::optional<std::uint64_t> parse_whole_in(std::string_view text, std::uint64_t low,
                                            std::uint64_t high) {
  const std::optional<std::uint64_t> value = parse_whole(text);
  if (!value || *value < low || *value > high) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::int64_t> parse_integer(std::string_view text) {
  return parse_integral<std::int64_t>(text);
}

std::string_view trim(std::string_view text) {
  constexpr std::string_view blanks = " \t\r";
  const std::size_t first = text.find_first_not_of(blanks);
  if (first == std::string_view::npos) {
    return {};
  }
  return text.substr(first, text.find_last_not_of(blanks) - first + 1u);
}

std::string bound_text(double value) {
  char text[32];
  const auto result =
      std::to_chars(text, text + sizeof text, value, std::chars_format::general, 15);
  return std::string(text, result.ptr);
}

}  // namespace odocal::toolkit
