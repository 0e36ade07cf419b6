// The console's number text I/O against the code it replaced (text_reference.hpp), by brute
// force: the smaller robot code must print the same bytes, accept and refuse the same strings,
// read the same floats and compare the same way.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "odocal/console/text.hpp"
#include "text_reference.hpp"

namespace odocal::console {
namespace {

float from_bits(std::uint32_t bits) {
  float f = 0.0f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

std::uint32_t to_bits(float f) {
  std::uint32_t bits = 0u;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

/// Both formatters on `value`, with room and with every capacity around the length.
void expect_same_fixed(float value, int decimals) {
  char expected[64];
  char actual[64];
  const std::size_t n = reference::format_fixed(value, decimals, expected, sizeof expected);
  const std::size_t m = format_fixed(value, decimals, actual, sizeof actual);
  ASSERT_EQ(std::string(actual, m), std::string(expected, n))
      << "bits 0x" << std::hex << to_bits(value) << std::dec << " decimals " << decimals;
  ASSERT_EQ(format_fixed(value, decimals, actual, n), n);
  ASSERT_EQ(format_fixed(value, decimals, actual, n - 1u), 0u);
}

TEST(TextEquivalence, FormatFixedOnRandomBitPatterns) {
  // Every exponent (denormals, the exponent form, inf and nan included), every decimals value
  // the function clamps to and a few it clamps.
  std::mt19937 rng(1u);
  for (int i = 0; i < 400000; ++i) {
    const float value = from_bits(static_cast<std::uint32_t>(rng()));
    const int decimals = static_cast<int>(rng() % 12u) - 1;
    expect_same_fixed(value, decimals);
  }
}

TEST(TextEquivalence, FormatFixedOnDecimalsAroundTheirRoundingPoints) {
  // Values a robot prints (poses, factors, parameters) and the ties and near-ties of every
  // decimals count: k / 10^d ± half a unit, and the floats either side of them.
  std::mt19937 rng(2u);
  for (int decimals = 0; decimals <= 9; ++decimals) {
    for (int i = 0; i < 40000; ++i) {
      const double unit = std::pow(10.0, -decimals);
      const double scale = std::pow(10.0, static_cast<int>(rng() % 14u) - 1);
      const double k = std::floor(static_cast<double>(rng()) / 4294967296.0 * scale / unit);
      const float tie = static_cast<float>((k + 0.5) * unit) * (rng() % 2u == 0u ? 1.0f : -1.0f);
      for (float value : {tie, std::nextafter(tie, 0.0f), std::nextafter(tie, 2.0f * tie)}) {
        expect_same_fixed(value, decimals);
      }
    }
  }
}

TEST(TextEquivalence, FormatFixedOnEveryFloatOfSomeRanges) {
  // Consecutive floats: around 0 (denormals), 1, 2^24, 2^40 and 1e12 (both forms' edges).
  const float starts[] = {0.0f, 0.999f, 16777000.0f, 1099511000000.0f, 999999000000.0f, 5e-5f};
  for (float start : starts) {
    const std::uint32_t first = to_bits(start);
    for (std::uint32_t bits = first; bits < first + 30000u; ++bits) {
      for (int decimals = 0; decimals <= 9; decimals += 3) {
        expect_same_fixed(from_bits(bits), decimals);
        expect_same_fixed(-from_bits(bits), decimals + 1);
      }
    }
  }
}

TEST(TextEquivalence, FormatFixedAroundEveryPowerOfTenOfTheExponentForm) {
  // Where the exponent form picks its exponent and where its 7 digits carry over (9.9999995e+n).
  for (int exponent = 12; exponent <= 38; ++exponent) {
    for (double mantissa : {1.0, 9.9999995, 9.99999949, 9.9999996}) {
      const double value = mantissa * std::pow(10.0, exponent);
      if (value > std::numeric_limits<float>::max()) {
        continue;
      }
      const auto center = static_cast<float>(value);
      const std::uint32_t bits = to_bits(center);
      for (std::uint32_t b = bits - 300u; b <= bits + 300u; ++b) {
        expect_same_fixed(from_bits(b), 6);
        expect_same_fixed(-from_bits(b), 2);
      }
    }
  }
  expect_same_fixed(std::numeric_limits<float>::max(), 6);
  expect_same_fixed(-std::numeric_limits<float>::max(), 0);
}

TEST(TextEquivalence, FormatUnsigned) {
  std::mt19937_64 rng(3u);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t value = rng() >> (rng() % 64u);
    char expected[32];
    char actual[32];
    const std::size_t n = reference::format_unsigned(value, expected, sizeof expected);
    ASSERT_EQ(format_unsigned(value, actual, sizeof actual), n);
    ASSERT_EQ(std::string(actual, n), std::string(expected, n));
    ASSERT_EQ(format_unsigned(value, actual, n - 1u), 0u);
  }
  char buffer[4];
  EXPECT_EQ(format_unsigned(0u, nullptr, 4u), 0u);
  EXPECT_EQ(format_fixed(1.0f, 2, nullptr, 64u), 0u);
  EXPECT_EQ(format_unsigned(0u, buffer, 1u), 1u);
}

/// A random string over the characters a number is made of (and a few it is not).
std::string random_text(std::mt19937& rng) {
  static const char alphabet[] = "0123456789012345678900000.eE+-x 9";
  const std::size_t length = rng() % 16u;
  std::string text;
  for (std::size_t i = 0; i < length; ++i) {
    text += alphabet[rng() % (sizeof alphabet - 1u)];
  }
  return text;
}

/// A random well-formed decimal: sign, 1..22 digits with a point somewhere, an exponent.
std::string random_number(std::mt19937& rng) {
  std::string text;
  const unsigned sign = rng() % 3u;
  text += sign == 0u ? "" : (sign == 1u ? "-" : "+");
  const int digits = 1 + static_cast<int>(rng() % 22u);
  const int point = static_cast<int>(rng() % static_cast<unsigned>(digits + 2));
  const bool zeros = rng() % 4u == 0u;  // runs of zeros: whole numbers and exact digits
  for (int i = 0; i < digits; ++i) {
    if (i == point) {
      text += '.';
    }
    text += static_cast<char>('0' + (zeros && i > 2 ? 0u : rng() % 10u));
  }
  if (rng() % 2u == 0u) {
    text += rng() % 2u == 0u ? 'e' : 'E';
    const unsigned exponent_sign = rng() % 3u;
    text += exponent_sign == 0u ? "" : (exponent_sign == 1u ? "-" : "+");
    const unsigned size = rng() % 4u;
    text += std::to_string(size == 0u   ? rng() % 10u
                           : size == 1u ? rng() % 50u
                           : size == 2u ? rng() % 400u
                                        : rng() % 100000u);
  }
  return text;
}

/// A bound as parameter tables hold them: small decimals, whole numbers, their floats.
float random_bound(std::mt19937& rng, int decimals) {
  const double limit = 8e18 / std::pow(10.0, decimals);  // the units stay below 2^62
  switch (rng() % 4u) {
    case 0u:
      return 0.0f;
    case 1u:
      return static_cast<float>(static_cast<int>(rng() % 2001u) - 1000);
    case 2u:
      return static_cast<float>((static_cast<double>(rng()) / 4294967296.0 - 0.5) *
                                std::pow(10.0, static_cast<int>(rng() % 12u) - 6));
    default:
      // Any size up to the largest compare takes.
      return static_cast<float>((static_cast<double>(rng()) / 4294967296.0 - 0.5) * limit *
                                std::pow(10.0, -static_cast<int>(rng() % 16u)));
  }
}

void expect_same_parse(const std::string& text, std::mt19937& rng) {
  const Token token{text.data(), text.size()};
  Decimal expected;
  Decimal actual;
  expected.mantissa = 77u;
  actual.mantissa = 77u;
  const bool ok = reference::parse_decimal(token, expected);
  ASSERT_EQ(parse_decimal(token, actual), ok) << text;
  ASSERT_EQ(actual.mantissa, expected.mantissa) << text;
  float expected_float = 42.0f;
  float actual_float = 42.0f;
  ASSERT_EQ(parse_number(token, actual_float), reference::parse_number(token, expected_float));
  ASSERT_EQ(to_bits(actual_float), to_bits(expected_float)) << text;
  std::uint32_t expected_unsigned = 7u;
  std::uint32_t actual_unsigned = 7u;
  ASSERT_EQ(parse_unsigned(token, actual_unsigned),
            reference::parse_unsigned(token, expected_unsigned))
      << text;
  ASSERT_EQ(actual_unsigned, expected_unsigned) << text;
  if (!ok) {
    return;
  }
  ASSERT_EQ(actual.exp10, expected.exp10) << text;
  ASSERT_EQ(actual.negative, expected.negative) << text;
  ASSERT_EQ(actual.inexact, expected.inexact) << text;
  ASSERT_EQ(actual.fraction_dropped, expected.fraction_dropped) << text;
  ASSERT_EQ(is_whole(actual), reference::is_whole(expected)) << text;
  ASSERT_EQ(to_bits(to_float(actual)), to_bits(reference::to_float(expected))) << text;
  for (int i = 0; i < 4; ++i) {
    const int decimals = static_cast<int>(rng() % 10u);
    // The typed value's own float as a bound, where its units stay below 2^62 as bounds' do.
    const float typed = reference::to_float(expected);
    const bool fits = std::fabs(static_cast<double>(typed)) < 4e18 / std::pow(10.0, decimals);
    const float bound = i == 0 && fits ? typed : random_bound(rng, decimals);
    ASSERT_EQ(compare(actual, bound, decimals), reference::compare(expected, bound, decimals))
        << text << " against " << bound << " at " << decimals << " decimals";
  }
}

TEST(TextEquivalence, ParseAndCompareRandomStrings) {
  std::mt19937 rng(4u);
  for (int i = 0; i < 300000; ++i) {
    expect_same_parse(random_text(rng), rng);
  }
  const Token empty{nullptr, 0u};
  Decimal d;
  std::uint32_t u = 0u;
  EXPECT_FALSE(parse_decimal(empty, d));
  EXPECT_FALSE(parse_unsigned(empty, u));
}

TEST(TextEquivalence, ParseAndCompareRandomNumbers) {
  std::mt19937 rng(5u);
  for (int i = 0; i < 300000; ++i) {
    expect_same_parse(random_number(rng), rng);
  }
}

TEST(TextEquivalence, ParseAtTheEdgesOfFloatsRange) {
  // Mantissas of 1 to 9 digits (float's largest, smallest normal and smallest denormal among
  // them) at every exponent around float's range and far beyond it: overflow to the largest
  // float, underflow to 0 and the two-division path below 10^-38.
  const char* mantissas[] = {"1",        "9",         "5",          "34028234",  "340282357",
                             "34028236", "117549435", "1175494",    "14",        "140129846",
                             "7006492",  "7",         "999999999",  "100000000", "123456789",
                             "0",        "2",         "4999999999", "1.5",       "0.0000001"};
  std::mt19937 rng(7u);
  for (const char* mantissa : mantissas) {
    for (int exponent = -130; exponent <= 130; ++exponent) {
      for (const char* sign : {"", "-"}) {
        expect_same_parse(sign + std::string(mantissa) + "e" + std::to_string(exponent), rng);
      }
    }
    for (int exponent : {-100000, -99999, -10000, -9999, 300, 301, 307, 308, 309, 99999}) {
      expect_same_parse(std::string(mantissa) + "e" + std::to_string(exponent), rng);
    }
  }
}

TEST(TextEquivalence, CompareEveryPrintedBoundWithItsNeighbours) {
  // The typed text of a bound as `params` prints it, one unit of its last digit either side
  // and digits beyond: the comparisons that decide `out_of_range`.
  std::mt19937 rng(6u);
  for (int i = 0; i < 100000; ++i) {
    const int decimals = static_cast<int>(rng() % 10u);
    const float bound = random_bound(rng, decimals);
    char printed[64];
    const std::size_t n = reference::format_fixed(bound, decimals, printed, sizeof printed);
    const std::string text(printed, n);
    for (const std::string& typed : {text, text + "1", text + "0000000000001", text + "e0",
                                     text + "e-1", "-" + text, text + "9999999999"}) {
      expect_same_parse(typed, rng);
      Decimal expected;
      Decimal actual;
      if (reference::parse_decimal(Token{typed.data(), typed.size()}, expected) &&
          parse_decimal(Token{typed.data(), typed.size()}, actual)) {
        ASSERT_EQ(compare(actual, bound, decimals), reference::compare(expected, bound, decimals))
            << typed << " against " << bound << " at " << decimals << " decimals";
      }
    }
  }
}

}  // namespace
}  // namespace odocal::console
