#include "odocal/console/text.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "odocal/math/numeric.hpp"

namespace odocal::console {
namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// 10^n for n >= 0 in float: exact up to 10^10 (5^10 < 2^24), then one rounding per step (inf
/// from 10^39 on).
float power_of_ten(int n) {
  float result = 1.0f;
  for (; n >= 10; n -= 10) {
    result *= 1e10f;
  }
  float small = 1.0f;  // 10^(n mod 10), exact (5^9 < 2^24): the one rounding stays the last step
  for (; n > 0; --n) {
    small *= 10.0f;
  }
  return result * small;
}

/// Writes backwards, ending before `end`: the decimal digits of `value` followed by `zeros` 0s
/// (zeros <= point), with a point before the last `point` digits when point > 0 and at least one
/// digit before that point. @return the first character. The Cortex-M4 has no 64-bit divide
/// (libgcc's costs ~0.7 KB): digits by the drive's long division in 16-bit steps, which the robot
/// links anyway.
char* put_digits(char* end, std::uint64_t value, int zeros, int point) {
  int i = 0;
  do {
    if (i == point && i != 0) {
      *--end = '.';
    }
    std::uint32_t digit = 0u;
    if (i >= zeros) {
      const std::uint64_t quotient = math::divide_u64(value, 10u);
      digit = static_cast<std::uint32_t>(value) - static_cast<std::uint32_t>(quotient) * 10u;
      value = quotient;
    }
    *--end = static_cast<char>('0' + digit);
    ++i;
  } while (value != 0u || i <= point);
  return end;
}

/// Where times_power_of_ten saturates: above the units of any bound compare takes (|bound| ·
/// 10^decimals below 2^62, e.g. every bound printed in fixed form at 6 decimals), with room to
/// double in an int64.
constexpr std::uint64_t kSaturated = (1ull << 62u) - 1u;

/// min(x · 10^n, kSaturated) for x <= kSaturated (n <= 0: x).
// Not inlined: called four times.
[[gnu::noinline]] std::uint64_t times_power_of_ten(std::uint64_t x, int n) {
  for (; n > 0; --n) {
    if (x > kSaturated / 10u) {
      return kSaturated;
    }
    x *= 10u;
  }
  return x;
}

/// The exact magnitude of a float below 2^40 in units of 10^-decimals (0..9), correctly rounded
/// (half up) on its binary value: magnitude = m · 2^-k with a 24-bit integer m, so the units are
/// (m · 10^decimals + 2^(k-1)) >> k, below 2^54 for k > 0. A whole float (k <= 0) may not fit
/// once scaled: it comes back unscaled with `zeros` = decimals (units = result · 10^zeros).
std::uint64_t fixed_units(std::uint32_t bits, int decimals, int& zeros) {
  // A denormal (biased exponent 0) gets k = 150 and a wrong m: it is below 2^-126, and anything
  // below 2^-40 rounds to 0 at 9 decimals or fewer.
  const std::uint32_t m = (bits & 0x7FFFFFu) | 0x800000u;
  const int k = 150 - static_cast<int>((bits >> 23u) & 0xFFu);  // fraction bits
  zeros = 0;
  if (k <= 0) {
    zeros = decimals;
    return static_cast<std::uint64_t>(m) << static_cast<unsigned>(-k);  // < 2^40: fits
  }
  if (k >= 64) {
    return 0u;
  }
  // m < 2^24 and 10^decimals <= 10^9 < 2^30: the product fits in 54 bits (never saturated).
  // Rounded half up in two shifts: (x + 2^(k-1)) >> k = ((x >> (k-1)) + 1) >> 1.
  return ((times_power_of_ten(m, decimals) >> static_cast<unsigned>(k - 1)) + 1u) >> 1u;
}

/// Copies [begin, end) to `out` when it fits; @return its length, else 0 (nothing written).
std::size_t copy_out(const char* begin, const char* end, char* out, std::size_t capacity) {
  const auto n = static_cast<std::size_t>(end - begin);
  if (out == nullptr || n > capacity) {
    return 0u;
  }
  std::memcpy(out, begin, n);
  return n;
}

}  // namespace

bool Token::is(const char* word) const {
  const std::size_t n = std::strlen(word);
  return n == length && std::memcmp(text, word, n) == 0;
}

bool parse_decimal(const Token& token, Decimal& value) {
  const char* p = token.text;
  const char* end = token.text + token.length;
  if (p == nullptr || p == end) {
    return false;
  }
  bool negative = false;
  if (*p == '+' || *p == '-') {
    negative = *p == '-';
    ++p;
  }
  // At most 9 significant digits are kept (the rest truncated): a float has 24 bits (7.2
  // digits), so what is dropped is below 1e-9 relative, far under half a unit of its last bit.
  std::uint32_t mantissa = 0u;
  int exponent10 = 0;  // value = mantissa * 10^exponent10
  const char* const digits = p;
  bool point = false;
  bool inexact = false;
  bool fraction_dropped = false;
  for (; p != end; ++p) {
    const auto digit = static_cast<std::uint32_t>(*p - '0');
    if (digit <= 9u) {
      if (mantissa < 100000000u) {
        mantissa = mantissa * 10u + digit;
        exponent10 -= point ? 1 : 0;
      } else {
        if (digit != 0u) {
          inexact = true;
          fraction_dropped = fraction_dropped || point;
        }
        exponent10 += point ? 0 : 1;  // a dropped integer digit still scales the value
      }
    } else if (*p == '.' && !point) {
      point = true;
    } else {
      break;
    }
  }
  if (p - digits == (point ? 1 : 0)) {
    return false;  // no digit
  }
  if (p != end) {
    if ((*p | 0x20) != 'e') {  // 'e' or 'E'
      return false;
    }
    ++p;
    bool exponent_negative = false;
    if (p != end && (*p == '+' || *p == '-')) {
      exponent_negative = *p == '-';
      ++p;
    }
    if (p == end) {
      return false;
    }
    int written = 0;
    for (; p != end; ++p) {
      const int digit = *p - '0';
      if (digit < 0 || digit > 9) {
        return false;
      }
      if (written < 10000) {  // saturate: anything this large over- or underflows anyway
        written = written * 10 + digit;
      }
    }
    exponent10 += exponent_negative ? -written : written;
  }
  // Beyond 1e308 (mantissa · 10^exponent10 >= 10^309): not a finite number in any usual reading
  // (a double overflows too).
  if (times_power_of_ten(1u, 309 - exponent10) <= mantissa) {
    return false;
  }
  if (mantissa == 0u) {
    exponent10 = 0;
  }
  value = Decimal{mantissa, exponent10, negative, inexact, fraction_dropped};
  return true;
}

bool is_whole(const Decimal& value) {
  if (value.fraction_dropped) {
    return false;  // a nonzero digit after the point beyond the 9 kept
  }
  // Whole when the last -exp10 digits of the mantissa are all 0.
  std::uint32_t mantissa = value.mantissa;
  for (int n = value.exp10; n < 0; ++n) {
    if (mantissa % 10u != 0u) {
      return false;
    }
    mantissa /= 10u;
  }
  return true;
}

float to_float(const Decimal& decimal) {
  int exponent10 = decimal.exp10;
  auto result = static_cast<float>(decimal.mantissa);
  if (decimal.mantissa != 0u) {  // 0 · inf would be nan
    if (exponent10 < -38) {      // 10^-exponent10 is beyond float: in two divisions
      result /= power_of_ten(38);
      exponent10 += 38;
    }
    if (exponent10 >= 0) {
      // 10^39 and above are inf in float, so is any product of 10^39 or more: a value finite as
      // written but beyond float reads as the largest float, so that range checks name it as out
      // of range rather than as not a number.
      result *= power_of_ten(exponent10);
      if (!std::isfinite(result)) {
        result = std::numeric_limits<float>::max();
      }
    } else {
      // Below float's smallest denormal (under 10^-46): the quotient rounds to 0.
      result /= power_of_ten(-exponent10);
    }
  }
  return decimal.negative ? -result : result;
}

bool parse_number(const Token& token, float& value) {
  Decimal decimal;
  if (!parse_decimal(token, decimal)) {
    return false;
  }
  value = to_float(decimal);
  return true;
}

int compare(const Decimal& value, float bound, int decimals) {
  // The bound as printed: B units of 10^-decimals (exact digits, correctly rounded).
  std::uint32_t bits = 0u;
  std::memcpy(&bits, &bound, sizeof bits);
  int zeros = 0;
  std::uint64_t units = fixed_units(bits, decimals, zeros);
  units = times_power_of_ten(units, zeros);
  // The typed magnitude is mantissa · 10^k units, a little more when inexact: compared with B
  // exactly by scaling whichever side has the power of ten, both doubled so that the dropped
  // digits count as half a unit (x + a fraction lies between x and x + 1). Saturated sides stay
  // below 2^63: signed arithmetic is safe.
  const int k = value.exp10 + decimals;
  auto x = static_cast<std::int64_t>(2u * times_power_of_ten(value.mantissa, k) +
                                     (value.inexact ? 1u : 0u));
  auto y = static_cast<std::int64_t>(2u * times_power_of_ten(units, -k));
  if (value.negative) {
    x = -x;
  }
  if (bound < 0.0f) {
    y = -y;
  }
  return (x > y) - (x < y);
}

bool parse_unsigned(const Token& token, std::uint32_t& value) {
  if (token.text == nullptr || token.length == 0u || token.length > 10u) {
    return false;
  }
  std::uint64_t result = 0u;
  for (std::size_t i = 0; i < token.length; ++i) {
    if (!is_digit(token.text[i])) {
      return false;
    }
    result = result * 10u + static_cast<std::uint64_t>(token.text[i] - '0');
  }
  if (result > 0xFFFFFFFFull) {
    return false;
  }
  value = static_cast<std::uint32_t>(result);
  return true;
}

std::size_t format_unsigned(std::uint64_t value, char* out, std::size_t capacity) {
  char text[20];
  char* const end = text + sizeof text;
  return copy_out(put_digits(end, value, 0, 0), end, out, capacity);
}

std::size_t format_fixed(float value, int decimals, char* out, std::size_t capacity) {
  if (decimals < 0) {
    decimals = 0;
  } else if (decimals > 9) {
    decimals = 9;
  }
  // Written backwards from the end: the digits first, the sign last.
  char text[48];
  char* const end = text + sizeof text;
  char* p = end;
  std::uint32_t bits = 0u;
  std::memcpy(&bits, &value, sizeof bits);
  bool negative = (bits >> 31u) != 0u;
  const float magnitude = std::fabs(value);
  if ((bits & 0x7F800000u) == 0x7F800000u) {
    const bool nan = (bits & 0x7FFFFFu) != 0u;
    p -= 3;
    std::memcpy(p, nan ? "nan" : "inf", 3);
    negative = negative && !nan;
  } else if (magnitude >= 1.0e12f) {
    // Exponent form with 6 decimals in the mantissa: never reached by a parameter or a pose
    // on a working robot, but a value must never be printed as garbage.
    // One division by the (once-rounded) power of ten: repeated /10 would compound roundings.
    // The largest exponent in 12..38 whose power of ten is at most the value (the powers rise
    // with the exponent; power_of_ten(12) is 1e12f itself).
    int exponent = 38;
    while (magnitude < power_of_ten(exponent)) {
      --exponent;
    }
    std::uint32_t scaled =
        static_cast<std::uint32_t>(magnitude / power_of_ten(exponent) * 1.0e6f + 0.5f);
    // At least 1e6: value >= power_of_ten(exponent), so the rounded quotient is at least 1.
    if (scaled >= 10000000u) {  // rounded up to 10
      scaled /= 10u;
      ++exponent;
    }
    // The exponent is 12..39: two digits.
    *--p = static_cast<char>('0' + exponent % 10);
    *--p = static_cast<char>('0' + exponent / 10);
    *--p = '+';
    *--p = 'e';
    p = put_digits(p, scaled, 0, 6);  // 7 digits: "d.dddddd"
  } else {
    // Exact: the float's binary value in units of the last decimal, correctly rounded (half
    // away from zero on the magnitude). Never a "-" before an all-zero result.
    int zeros = 0;
    const std::uint64_t units = fixed_units(bits, decimals, zeros);
    negative = negative && units != 0u;
    p = put_digits(p, units, zeros, decimals);
  }
  if (negative) {
    *--p = '-';
  }
  return copy_out(p, end, out, capacity);
}

NumberArg read_number_arg(const Token& token, float lo, float hi, bool whole, float& value) {
  constexpr int decimals = 6;  // bounds as `params` and the refusal print them
  Decimal typed;
  if (!parse_decimal(token, typed)) {
    return NumberArg::not_number;
  }
  // The typed decimal against the printed bounds, exactly: 2.0000001 is above 2 though not as a
  // float.
  if (compare(typed, lo, decimals) < 0 || compare(typed, hi, decimals) > 0) {
    return NumberArg::out_of_range;
  }
  // Whole as typed: 1440.0000001 is not, although its nearest float is 1440.
  if (whole && !is_whole(typed)) {
    return NumberArg::not_whole;
  }
  const float parsed = to_float(typed);
  value = parsed < lo ? lo : (parsed > hi ? hi : parsed);
  return NumberArg::ok;
}

std::size_t split(const char* line, std::size_t length, Token* tokens, std::size_t capacity) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (i < length) {
    while (i < length && line[i] == ' ') {
      ++i;
    }
    if (i == length) {
      break;
    }
    const std::size_t start = i;
    while (i < length && line[i] != ' ') {
      ++i;
    }
    if (count == capacity) {
      return capacity + 1u;
    }
    tokens[count].text = line + start;
    tokens[count].length = i - start;
    ++count;
  }
  return count;
}

}  // namespace odocal::console
