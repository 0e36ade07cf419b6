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

/// A decimal number as typed: ±mantissa · 10^exp10, with at most 9 significant digits kept.
struct Decimal {
  std::uint32_t mantissa = 0u;
  int exp10 = 0;
  bool negative = false;
  bool inexact = false;  ///< nonzero digits beyond the 9 kept (the value is a little larger)
  bool fraction_dropped = false;  ///< some of those were after the point
};

/// True when the typed decimal is a whole number (its digits after the point, all of them, are 0).
[[nodiscard]] bool is_whole(const Decimal& value);
/// Parses a whole token with the grammar of `parse_number`, keeping the decimal digits.
[[nodiscard]] bool parse_decimal(const Token& token, Decimal& value);
/// The float nearest `value` or one unit of its last bit away (see parse_number).
[[nodiscard]] float to_float(const Decimal& value);
/// Compares a typed decimal with `bound` as it prints with `decimals` (0..9) digits after the
/// point (`params` prints 6): −1, 0 or 1 for less, equal, greater. Exact: no float rounding of
/// the typed value, so 2.0000001 is above a bound printed 2.000000 although both are the float 2.
/// For a finite bound with |bound| · 10^decimals below 2^62 (every bound printed in fixed form,
/// below 1e12, at 6 decimals or fewer).
[[nodiscard]] int compare(const Decimal& value, float bound, int decimals);

/// Parses a whole token as a decimal number, strictly: an optional sign, digits with at most one
/// decimal point (at least one digit in all), and an optional exponent `e`/`E` with an optional
/// sign and at least one digit. Nothing else: no spaces, no trailing junk, no hex, no `inf`/`nan`.
/// The result is the nearest float or within one unit of its last bit (at most 9 significant digits
/// are used); a value finite as written but beyond float's range reads as ±FLT_MAX (so that range
/// checks call it out of range), one below float's smallest as 0.
/// @return false (value untouched) when the text is not such a number or its magnitude is beyond
/// 1e308 (e.g. `1e999`).
[[nodiscard]] bool parse_number(const Token& token, float& value);

/// What `read_number_arg` made of a command's numeric argument.
enum class NumberArg : std::uint8_t { ok, not_number, out_of_range, not_whole };
/// A command's numeric argument as the robot takes it: a decimal (parse_decimal's grammar) inside
/// [lo, hi] as the bounds print with 6 decimals (exact: `0.001` is a minimum of 0.001 although its
/// float is not), whole as typed when `whole`; `value` (only on ok) its float, clamped to the
/// bounds. The robot's refusals name the result (Console::number_arg); a host reading a command
/// line takes it the same way.
[[nodiscard]] NumberArg read_number_arg(const Token& token, float lo, float hi, bool whole,
                                        float& value);

/// Parses a whole token as an unsigned decimal integer in [0, 2^32 - 1] (digits only).
[[nodiscard]] bool parse_unsigned(const Token& token, std::uint32_t& value);

/// Writes `value` with exactly `decimals` (0..9) digits after the point, rounded half away from
/// zero ("-1.500000"; "nan", "inf", "-inf" for non-finite values; magnitudes of 1e12 and more in
/// exponent form "1.234567e+15"). Never writes a "-" before an all-zero result. Below 1e12 the
/// digits are exact: the float's binary value correctly rounded, in integer arithmetic.
/// @return characters written (no terminator), 0 when `capacity` is too small (nothing usable).
std::size_t format_fixed(float value, int decimals, char* out, std::size_t capacity);

/// Writes an unsigned decimal integer; @return characters written, 0 when it does not fit.
std::size_t format_unsigned(std::uint64_t value, char* out, std::size_t capacity);

/// CRC-16/CCITT-FALSE (polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR) of
/// `length` bytes: the check of a `# ticks` line streamed with `stream ticks <hz> crc`, over the
/// line's bytes before " crc=". Its check value, of "123456789", is 0x29B1.
[[nodiscard]] constexpr std::uint16_t crc16(const char* bytes, std::size_t length) {
  std::uint32_t crc = 0xFFFFu;
  for (std::size_t i = 0u; i < length; ++i) {
    crc ^= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i])) << 8u;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000u) != 0u ? (crc << 1u) ^ 0x1021u : crc << 1u;
    }
  }
  return static_cast<std::uint16_t>(crc);
}

/// Splits `line` at spaces into at most `capacity` tokens.
/// @return the number of tokens, or capacity + 1 when there are more than `capacity`.
std::size_t split(const char* line, std::size_t length, Token* tokens, std::size_t capacity);

}  // namespace odocal::console
