#include "odocal/console/text.hpp"

#include <cmath>
#include <cstring>

namespace odocal::console {
namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

double power_of_ten(int exponent) {
  double result = 1.0;
  double base = 10.0;
  unsigned n = static_cast<unsigned>(exponent < 0 ? -exponent : exponent);
  while (n != 0u) {  // square-and-multiply: at most 9 steps for |exponent| < 512
    if ((n & 1u) != 0u) {
      result *= base;
    }
    base *= base;
    n >>= 1u;
  }
  return exponent < 0 ? 1.0 / result : result;
}

}  // namespace

bool Token::is(const char* word) const {
  const std::size_t n = std::strlen(word);
  return n == length && std::memcmp(text, word, n) == 0;
}

bool parse_number(const Token& token, double& value) {
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
  std::uint64_t mantissa = 0u;
  int exponent10 = 0;  // value = mantissa * 10^exponent10
  int digits = 0;
  bool point = false;
  for (; p != end; ++p) {
    if (is_digit(*p)) {
      ++digits;
      if (mantissa < 100000000000000000ull) {  // 17 significant digits: more than a double has
        mantissa = mantissa * 10u + static_cast<std::uint64_t>(*p - '0');
        if (point) {
          --exponent10;
        }
      } else if (!point) {
        ++exponent10;  // a dropped integer digit still scales the value
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
  double result = static_cast<double>(mantissa);
  if (mantissa != 0u) {
    if (exponent10 > 400) {
      return false;  // overflows a double
    }
    if (exponent10 < -400) {
      result = 0.0;
    } else if (exponent10 < -300) {
      result = result * power_of_ten(-300) * power_of_ten(exponent10 + 300);
    } else {
      result *= power_of_ten(exponent10);
    }
  }
  if (!std::isfinite(result)) {
    return false;
  }
  value = negative ? -result : result;
  return true;
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
  char digits[20];
  std::size_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u);
  if (out == nullptr || n > capacity) {
    return 0u;
  }
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = digits[n - 1 - i];
  }
  return n;
}

std::size_t format_fixed(double value, int decimals, char* out, std::size_t capacity) {
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
    if (value < 0.0) {
      text[n++] = '-';
    }
    std::memcpy(text + n, "inf", 3);
    n += 3;
  } else {
    const bool negative = value < 0.0;
    double magnitude = negative ? -value : value;
    if (magnitude >= 1.0e12) {
      // Exponent form with 6 decimals in the mantissa: never reached by a parameter or a pose
      // on a working robot, but a value must never be printed as garbage.
      int exponent = 0;
      while (magnitude >= 10.0) {
        magnitude /= 10.0;
        ++exponent;
      }
      std::uint64_t scaled = static_cast<std::uint64_t>(magnitude * 1.0e6 + 0.5);
      if (scaled >= 10000000u) {
        scaled /= 10u;
        ++exponent;
      }
      if (negative) {
        text[n++] = '-';
      }
      text[n++] = static_cast<char>('0' + scaled / 1000000u);
      text[n++] = '.';
      std::uint64_t fraction = scaled % 1000000u;
      for (int i = 5; i >= 0; --i) {
        text[n + static_cast<std::size_t>(i)] = static_cast<char>('0' + fraction % 10u);
        fraction /= 10u;
      }
      n += 6;
      text[n++] = 'e';
      text[n++] = '+';
      n += format_unsigned(static_cast<std::uint64_t>(exponent), text + n, sizeof text - n);
    } else {
      std::uint64_t scale = 1u;
      for (int i = 0; i < decimals; ++i) {
        scale *= 10u;
      }
      const std::uint64_t scaled =
          static_cast<std::uint64_t>(magnitude * static_cast<double>(scale) + 0.5);
      if (negative && scaled != 0u) {
        text[n++] = '-';
      }
      n += format_unsigned(scaled / scale, text + n, sizeof text - n);
      if (decimals > 0) {
        text[n++] = '.';
        std::uint64_t fraction = scaled % scale;
        for (int i = decimals - 1; i >= 0; --i) {
          text[n + static_cast<std::size_t>(i)] = static_cast<char>('0' + fraction % 10u);
          fraction /= 10u;
        }
        n += static_cast<std::size_t>(decimals);
      }
    }
  }
  if (n > capacity) {
    return 0u;
  }
  std::memcpy(out, text, n);
  return n;
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
