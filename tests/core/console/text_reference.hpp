#pragma once
/// @file
/// The console's number text I/O as it was before the footprint work on it (commit fd452bb),
/// kept verbatim (but for two calls qualified against argument-dependent lookup) as the reference
/// the smaller code must match exactly: same bytes out, same strings accepted and refused, same
/// floats, same comparisons.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "odocal/console/text.hpp"
#include "odocal/math/numeric.hpp"

namespace odocal::console::reference {

inline bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// 10^n for 0 <= n <= 38 in float: exact up to 10^10 (5^10 < 2^24), then one rounding per step.
inline float power_of_ten(int n) {
  float result = 1.0f;
  for (; n >= 10; n -= 10) {
    result *= 1e10f;
  }
  constexpr float small[10] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f};
  return result * small[n];
}

/// Number of decimal digits of a nonzero value.
inline int decimal_digits(std::uint32_t value) {
  int digits = 0;
  for (; value != 0u; value /= 10u) {
    ++digits;
  }
  return digits;
}

/// Writes `value` as exactly `width` digits (leading zeros) when width > 0, else as few as it
/// needs. The Cortex-M4 has no 64-bit divide (libgcc's costs ~0.7 KB): digits by the drive's
/// long division in 16-bit steps, which the robot links anyway.
inline std::size_t put_decimal(std::uint64_t value, std::size_t width, char* out) {
  char reversed[20];
  std::size_t n = 0;
  do {
    const std::uint64_t quotient = math::divide_u64(value, 10u);
    reversed[n++] = static_cast<char>('0' + static_cast<int>(value - quotient * 10u));
    value = quotient;
  } while (value != 0u || n < width);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = reversed[n - 1u - i];
  }
  return n;
}

/// Exact digits of a non-negative float below 2^40: magnitude = m · 2^e with a 24-bit integer m,
/// so the integer part and the fraction rounded to `decimals` (0..9) digits follow from integer
/// arithmetic on m, correctly rounded (half up) on the float's exact binary value.
/// @return 10^decimals (the unit of `digits`).
inline std::uint64_t fixed_digits(float magnitude, int decimals, std::uint64_t& whole,
                                  std::uint64_t& digits) {
  std::uint32_t bits = 0u;
  std::memcpy(&bits, &magnitude, sizeof bits);
  const std::uint32_t biased = (bits >> 23u) & 0xFFu;
  const std::uint64_t m = biased == 0u ? (bits & 0x7FFFFFu) : ((bits & 0x7FFFFFu) | 0x800000u);
  const int k = biased == 0u ? 149 : 150 - static_cast<int>(biased);  // fraction bits
  std::uint64_t fraction = 0u;                                        // numerator over 2^k
  whole = 0u;
  if (k <= 0) {
    whole = m << static_cast<unsigned>(-k);  // < 2^40: fits
  } else if (k < 64) {
    whole = m >> static_cast<unsigned>(k);
    fraction = m - (whole << static_cast<unsigned>(k));
  } else {
    fraction = m;
  }
  std::uint64_t scale = 1u;
  for (int i = 0; i < decimals; ++i) {
    scale *= 10u;
  }
  digits = 0u;
  if (k > 0 && k < 64) {
    // fraction < 2^24 and scale <= 10^9 < 2^30: the product fits in 54 bits.
    digits =
        (fraction * scale + (1ull << static_cast<unsigned>(k - 1))) >> static_cast<unsigned>(k);
  }  // k >= 64: below 2^-40, rounds to 0 at 9 decimals or fewer
  if (digits >= scale) {
    digits -= scale;
    ++whole;
  }
  return scale;
}

inline bool parse_decimal(const Token& token, Decimal& value) {
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
  int digits = 0;
  bool point = false;
  bool inexact = false;
  bool fraction_dropped = false;
  for (; p != end; ++p) {
    if (is_digit(*p)) {
      ++digits;
      if (mantissa < 100000000u) {
        mantissa = mantissa * 10u + static_cast<std::uint32_t>(*p - '0');
        if (point) {
          --exponent10;
        }
      } else {
        inexact = inexact || *p != '0';
        fraction_dropped = fraction_dropped || (point && *p != '0');
        if (!point) {
          ++exponent10;  // a dropped integer digit still scales the value
        }
      }
    } else if (*p == '.' && !point) {
      point = true;
    } else {
      break;
    }
  }
  if (digits == 0) {
    return false;
  }
  if (p != end) {
    if (*p != 'e' && *p != 'E') {
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
      if (!is_digit(*p)) {
        return false;
      }
      if (written < 10000) {  // saturate: anything this large over- or underflows anyway
        written = written * 10 + (*p - '0');
      }
    }
    exponent10 += exponent_negative ? -written : written;
  }
  if (mantissa != 0u) {
    if (decimal_digits(mantissa) - 1 + exponent10 > 308) {
      return false;  // not a finite number in any usual reading (a double overflows too)
    }
  } else {
    exponent10 = 0;
  }
  value = Decimal{mantissa, exponent10, negative, inexact, fraction_dropped};
  return true;
}

inline bool is_whole(const Decimal& value) {
  if (value.fraction_dropped) {
    return false;  // a nonzero digit after the point beyond the 9 kept
  }
  if (value.mantissa == 0u || value.exp10 >= 0) {
    return true;
  }
  if (value.exp10 < -9) {
    return false;  // mantissa < 10^9: a nonzero fraction
  }
  std::uint32_t divisor = 1u;
  for (int i = 0; i < -value.exp10; ++i) {
    divisor *= 10u;
  }
  return value.mantissa % divisor == 0u;
}

inline float to_float(const Decimal& decimal) {
  const std::uint32_t mantissa = decimal.mantissa;
  const int exponent10 = decimal.exp10;
  float result = 0.0f;
  if (mantissa != 0u) {
    const int magnitude =
        decimal_digits(mantissa) - 1 + exponent10;  // value = d.ddd × 10^magnitude
    if (magnitude > 38) {
      // Finite as written but beyond float: the largest float, so that range checks name it as
      // out of range rather than as not a number.
      result = std::numeric_limits<float>::max();
    } else if (magnitude < -46) {
      result = 0.0f;  // below float's smallest denormal
    } else {
      result = static_cast<float>(mantissa);
      if (exponent10 >= 0) {
        result *= power_of_ten(exponent10);
        if (!std::isfinite(result)) {
          result = std::numeric_limits<float>::max();
        }
      } else if (exponent10 >= -38) {
        result /= power_of_ten(-exponent10);
      } else {
        result = result / power_of_ten(38) / power_of_ten(-exponent10 - 38);
      }
    }
  }
  return decimal.negative ? -result : result;
}

inline bool parse_number(const Token& token, float& value) {
  Decimal decimal;
  if (!reference::parse_decimal(token, decimal)) {
    return false;
  }
  value = reference::to_float(decimal);
  return true;
}

inline int compare(const Decimal& value, float bound, int decimals) {
  // The bound as printed: an integer B of 10^-decimals units (exact digits, correctly rounded).
  std::uint64_t whole = 0u;
  std::uint64_t digits = 0u;
  const std::uint64_t scale = fixed_digits(bound < 0.0f ? -bound : bound, decimals, whole, digits);
  const std::int64_t units = static_cast<std::int64_t>(whole * scale + digits);
  const std::int64_t b = bound < 0.0f ? -units : units;
  // The value in the same units: q + f with q whole and f in [0, 1) (f > 0 when `fraction`).
  std::int64_t q = 0;
  bool fraction = value.inexact;
  const int k = value.exp10 + decimals;
  if (value.mantissa == 0u) {
    fraction = false;
  } else if (k >= 0) {
    std::int64_t scaled = value.mantissa;
    for (int i = 0; i < k; ++i) {
      if (scaled > 922337203685477580) {  // beyond any printed bound: compare by sign only
        return value.negative ? -1 : 1;
      }
      scaled *= 10;
    }
    q = scaled;
  } else if (k >= -9) {
    std::uint32_t divisor = 1u;
    for (int i = 0; i < -k; ++i) {
      divisor *= 10u;
    }
    q = value.mantissa / divisor;
    fraction = fraction || value.mantissa % divisor != 0u;
  } else {
    fraction = true;  // below one unit
  }
  if (!value.negative) {
    return q < b ? -1 : ((q > b || (q == b && fraction)) ? 1 : 0);
  }
  // value = −(q + f)
  return (q > -b || (q == -b && fraction)) ? -1 : (q < -b ? 1 : 0);
}

inline bool parse_unsigned(const Token& token, std::uint32_t& value) {
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

inline std::size_t format_unsigned(std::uint64_t value, char* out, std::size_t capacity) {
  char digits[20];
  const std::size_t n = put_decimal(value, 0u, digits);
  if (out == nullptr || n > capacity) {
    return 0u;
  }
  std::memcpy(out, digits, n);
  return n;
}

inline std::size_t format_fixed(float value, int decimals, char* out, std::size_t capacity) {
  if (out == nullptr) {
    return 0u;
  }
  if (decimals < 0) {
    decimals = 0;
  } else if (decimals > 9) {
    decimals = 9;
  }
  char text[48];
  std::size_t n = 0;
  if (std::isnan(value)) {
    std::memcpy(text, "nan", 3);
    n = 3;
  } else if (std::isinf(value)) {
    if (value < 0.0f) {
      text[n++] = '-';
    }
    std::memcpy(text + n, "inf", 3);
    n += 3;
  } else {
    const bool negative = std::signbit(value);
    float magnitude = negative ? -value : value;
    if (magnitude >= 1.0e12f) {
      // Exponent form with 6 decimals in the mantissa: never reached by a parameter or a pose
      // on a working robot, but a value must never be printed as garbage.
      // One division by the (once-rounded) power of ten: repeated /10 would compound roundings.
      int exponent = 12;
      while (exponent < 38 && magnitude >= power_of_ten(exponent + 1)) {
        ++exponent;
      }
      std::uint32_t scaled =
          static_cast<std::uint32_t>(magnitude / power_of_ten(exponent) * 1.0e6f + 0.5f);
      if (scaled >= 10000000u) {
        scaled /= 10u;
        ++exponent;
      } else if (scaled < 1000000u) {  // the power of ten rounded up past the value
        scaled = 1000000u;
      }
      if (negative) {
        text[n++] = '-';
      }
      text[n++] = static_cast<char>('0' + scaled / 1000000u);
      text[n++] = '.';
      n += put_decimal(scaled % 1000000u, 6u, text + n);
      text[n++] = 'e';
      text[n++] = '+';
      n += put_decimal(static_cast<std::uint64_t>(exponent), 0u, text + n);
    } else {
      // Exact: magnitude = m · 2^e with a 24-bit integer m; the integer part and the rounded
      // `decimals` digits of the fraction follow from integer arithmetic on m, correctly rounded
      // (half away from zero) on the float's exact binary value.
      std::uint64_t whole = 0u;
      std::uint64_t digits = 0u;
      fixed_digits(magnitude, decimals, whole, digits);
      if (negative && (whole != 0u || digits != 0u)) {
        text[n++] = '-';
      }
      n += put_decimal(whole, 0u, text + n);
      if (decimals > 0) {
        text[n++] = '.';
        n += put_decimal(digits, static_cast<std::size_t>(decimals), text + n);
      }
    }
  }
  if (n > capacity) {
    return 0u;
  }
  std::memcpy(out, text, n);
  return n;
}

}  // namespace odocal::console::reference
