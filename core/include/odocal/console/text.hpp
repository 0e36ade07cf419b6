#pragma once
/// @file
/// Number parsing and formatting for the console, without the printf/strtod family (the robot's
/// image links none of it). Pure functions; ISR-safe but meant for the main loop.

#include <cstddef>
#include <cstdint>

namespace odocal::console {

/// A view of bytes inside a line (not NUL-terminated).
struct Token {
  const char* text = nullptr;
  std::size_t length = 0u;

  /// True when the token is exactly `word` (NUL-terminated).
  [[nodiscard]] bool is(const char* word) const;
};

/// Parses a whole token as a decimal number, strictly: an optional sign, digits with at most one
/// decimal point (at least one digit in all), and an optional exponent `e`/`E` with an optional
/// sign and at least one digit. Nothing else: no spaces, no trailing junk, no hex, no `inf`/`nan`.
/// @return false (value untouched) when the text is not such a number or the result is not
/// finite (e.g. `1e999`).
[[nodiscard]] bool parse_number(const Token& token, double& value);

/// Parses a whole token as an unsigned decimal integer in [0, 2^32 - 1] (digits only).
[[nodiscard]] bool parse_unsigned(const Token& token, std::uint32_t& value);

/// Writes `value` with exactly `decimals` (0..9) digits after the point, rounded half away from
/// zero ("-1.500000"; "nan", "inf", "-inf" for non-finite values; magnitudes of 1e12 and more in
/// exponent form "1.234567e+15"). Never writes a "-" before an all-zero result.
/// @return characters written (no terminator), 0 when `capacity` is too small (nothing usable).
std::size_t format_fixed(double value, int decimals, char* out, std::size_t capacity);

/// Writes an unsigned decimal integer; @return characters written, 0 when it does not fit.
std::size_t format_unsigned(std::uint64_t value, char* out, std::size_t capacity);

/// Splits `line` at spaces into at most `capacity` tokens.
/// @return the number of tokens, or capacity + 1 when there are more than `capacity`.
std::size_t split(const char* line, std::size_t length, Token* tokens, std::size_t capacity);

}  // namespace odocal::console
