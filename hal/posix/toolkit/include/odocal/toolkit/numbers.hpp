#pragma once
/// @file
/// Strict reading of numbers written by people and by the robot: the whole text must be one
/// plain decimal number. No blanks around it, no hex, no "nan" or "inf", no trailing junk, no
/// silent wrap of an integer. Every host program (odocal, odocal-sim, odocal-linux) reads its
/// numbers here, so a value refused by one is refused by all.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace odocal::toolkit {

/// What a text holds, read as a real.
enum class NumberText {
  ok,            ///< a finite double (an underflow such as 1e-310 rounds to a subnormal or 0)
  not_a_number,  ///< empty, blanks, junk, "nan", "inf", hex
  out_of_range,  ///< decimal, but beyond the largest double ("1e400")
};

/// Reads `text` as a plain decimal real: digits, an optional sign ("+1" and "-1" are numbers),
/// one point, an exponent ("2.5e3"). `value` is set only on `ok`.
[[nodiscard]] NumberText read_number(std::string_view text, double& value);

/// The finite real `text` holds (read_number's `ok`), or nullopt.
[[nodiscard]] std::optional<double> parse_real(std::string_view text);

/// A non-negative integer written in digits only ("42"): nullopt for a sign, a fraction, an
/// exponent, hex, junk or a value above 2^64 - 1 (so "-1" never wraps to 2^64 - 1).
[[nodiscard]] std::optional<std::uint64_t> parse_whole(std::string_view text);

/// parse_whole, and nullopt unless low <= value <= high.
[[nodiscard]] std::optional<std::uint64_t> parse_whole_in(std::string_view text, std::uint64_t low,
                                                          std::uint64_t high);

/// An integer with an optional leading '-' ("-120", "7"): nullopt for '+', a fraction, an
/// exponent, junk or a value outside the 64-bit signed range.
[[nodiscard]] std::optional<std::int64_t> parse_integer(std::string_view text);

/// `text` without leading and trailing spaces, tabs and carriage returns.
[[nodiscard]] std::string_view trim(std::string_view text);

/// A bound as a person writes it: up to 15 significant digits, no trailing zeros
/// (1000000, 0.5, 1e-05), as printf's "%.15g".
[[nodiscard]] std::string bound_text(double value);

}  // namespace odocal::toolkit
