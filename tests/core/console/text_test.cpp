#include "odocal/console/text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace odocal::console {
namespace {

Token tok(const char* s) {
  return Token{s, std::strlen(s)};
}

bool parses(const char* s, float& v) {
  return parse_number(tok(s), v);
}

/// Units in the last place between two finite floats of the same sign.
std::int64_t ulps_between(float a, float b) {
  std::int32_t ia = 0;
  std::int32_t ib = 0;
  std::memcpy(&ia, &a, sizeof ia);
  std::memcpy(&ib, &b, sizeof ib);
  return std::llabs(static_cast<std::int64_t>(ia) - static_cast<std::int64_t>(ib));
}

std::string fixed(float v, int decimals) {
  char buffer[64];
  const std::size_t n = format_fixed(v, decimals, buffer, sizeof buffer);
  return std::string(buffer, n);
}

TEST(ParseNumber, AcceptsPlainDecimalForms) {
  float v = 0;
  ASSERT_TRUE(parses("1", v));
  EXPECT_EQ(v, 1.0f);
  ASSERT_TRUE(parses("-2.5", v));
  EXPECT_EQ(v, -2.5f);
  ASSERT_TRUE(parses("+0.125", v));
  EXPECT_EQ(v, 0.125f);
  ASSERT_TRUE(parses(".5", v));
  EXPECT_EQ(v, 0.5f);
  ASSERT_TRUE(parses("5.", v));
  EXPECT_EQ(v, 5.0f);
  ASSERT_TRUE(parses("1e3", v));
  EXPECT_EQ(v, 1000.0f);
  // A short decimal over a power of ten is one correctly rounded division: the nearest float.
  ASSERT_TRUE(parses("2.5E-3", v));
  EXPECT_EQ(v, 0.0025f);
  ASSERT_TRUE(parses("0.001", v));
  EXPECT_EQ(v, 0.001f);
  ASSERT_TRUE(parses("151.58", v));
  EXPECT_EQ(v, 151.58f);
  ASSERT_TRUE(parses("-0", v));
  EXPECT_EQ(v, 0.0f);
  ASSERT_TRUE(parses("0.000000001", v));
  EXPECT_EQ(v, 1e-9f);
  // More digits than a float holds: still the float nearest the value, or its neighbour.
  ASSERT_TRUE(parses("3.14159265358979323846264338", v));
  EXPECT_LE(ulps_between(v, 3.14159265358979323846f), 1);
  ASSERT_TRUE(parses("123456789012345678901234567890", v));
  EXPECT_LE(ulps_between(v, 1.2345678901234568e29f), 1);
  ASSERT_TRUE(parses("1e-400", v));  // underflows to zero: finite
  EXPECT_EQ(v, 0.0f);
  ASSERT_TRUE(parses("1e-50", v));  // below float's smallest denormal
  EXPECT_EQ(v, 0.0f);
  // Finite as written, beyond float: the largest float, so that a range check refuses it.
  ASSERT_TRUE(parses("1e39", v));
  EXPECT_EQ(v, std::numeric_limits<float>::max());
  ASSERT_TRUE(parses("-4e38", v));
  EXPECT_EQ(v, -std::numeric_limits<float>::max());
}

TEST(ParseNumber, RandomDecimalsLandWithinOneUlpOfTheNearestFloat) {
  // Reference: strtof (correctly rounded). 20,000 decimals with 1 to 12 significant digits and
  // exponents across the range parameters, poses and factors use.
  std::mt19937_64 rng(20261123u);
  std::uniform_int_distribution<int> digit_count(1, 12);
  std::uniform_int_distribution<int> digit(0, 9);
  std::uniform_int_distribution<int> exponent(-12, 12);
  constexpr int kCases = 20000;
  for (int i = 0; i < kCases; ++i) {
    std::string text;
    const int n = digit_count(rng);
    const int point = std::uniform_int_distribution<int>(0, n)(rng);
    for (int d = 0; d < n; ++d) {
      if (d == point) {
        text += '.';
      }
      text += static_cast<char>('0' + digit(rng));
    }
    text += 'e' + std::to_string(exponent(rng));
    float v = 0;
    ASSERT_TRUE(parses(text.c_str(), v)) << text;
    const float reference = std::strtof(text.c_str(), nullptr);
    ASSERT_LE(ulps_between(v, reference), 1) << text;
    // Up to 7 significant digits (exact in a float) over a power of ten up to 10^10 (exact too):
    // one correctly rounded operation, so the nearest float itself.
    const std::size_t e_at = text.find('e');
    const int power = std::atoi(text.c_str() + e_at + 1) - (point < n ? n - point : 0);
    if (n <= 7 && power >= -10 && power <= 10) {
      ASSERT_EQ(v, reference) << text;
    }
  }
}

TEST(ParseNumber, RefusesAnythingElse) {
  const char* bad[] = {"",      "-",      "+",     ".",   "1.2.3", "1e",   "1e+",
                       "e5",    "1x",     "1.0a",  " 1",  "1 ",    "0x10", "inf",
                       "-inf",  "nan",    "NaN",   "1,5", "--1",   "+-1",  "1e5.5",
                       "1e999", "-1e400", "1_000", "١",   "1e--3", "12f",  "0b1"};
  for (const char* s : bad) {
    float v = 42.0f;
    EXPECT_FALSE(parses(s, v)) << '"' << s << '"';
    EXPECT_EQ(v, 42.0f) << "value touched by a refused parse: " << s;
  }
  float v = 0;
  EXPECT_FALSE(parse_number(Token{nullptr, 0}, v));
}

int compare_text(const char* typed, float bound) {
  Decimal d;
  EXPECT_TRUE(parse_decimal(tok(typed), d)) << typed;
  return compare(d, bound, 6);
}

TEST(CompareDecimal, ComparesTheTypedDigitsWithTheBoundAsPrinted) {
  EXPECT_EQ(compare_text("0.001", 0.001f), 0);  // the float is 0.0010000000475: prints 0.001000
  EXPECT_EQ(compare_text("0.000999", 0.001f), -1);
  EXPECT_EQ(compare_text("2.0000001", 2.0f), 1);  // the float 2 itself, but typed above 2
  EXPECT_EQ(compare_text("1.9999999", 2.0f), -1);
  EXPECT_EQ(compare_text("2", 2.0f), 0);
  EXPECT_EQ(compare_text("2e0", 2.0f), 0);
  EXPECT_EQ(compare_text("-0.5", -0.5f), 0);
  EXPECT_EQ(compare_text("-0.5000001", -0.5f), -1);
  EXPECT_EQ(compare_text("-0.4999999", -0.5f), 1);
  EXPECT_EQ(compare_text("0", 0.0f), 0);
  EXPECT_EQ(compare_text("-0", 0.0f), 0);
  EXPECT_EQ(compare_text("0.0000004", 0.0f), 1);
  EXPECT_EQ(compare_text("-1e-30", 0.0f), -1);
  EXPECT_EQ(compare_text("1e20", 5.0f), 1);
  EXPECT_EQ(compare_text("-1e20", -5.0f), -1);
  EXPECT_EQ(compare_text("599999.9999999", 600000.0f), -1);
  EXPECT_EQ(compare_text("600000", 600000.0f), 0);
  // Digits beyond the 9 kept still count: 1.0000000001 is above 1.
  EXPECT_EQ(compare_text("1.00000000000001", 1.0f), 1);
  EXPECT_EQ(compare_text("100000000000000000001e-20", 1.0f), 1);
}

TEST(CompareDecimal, WholeAsTyped) {
  const auto whole = [](const char* typed) {
    Decimal d;
    EXPECT_TRUE(parse_decimal(tok(typed), d)) << typed;
    return is_whole(d);
  };
  EXPECT_TRUE(whole("1440"));
  EXPECT_TRUE(whole("1440.000"));
  EXPECT_TRUE(whole("1.44e3"));
  EXPECT_TRUE(whole("0"));
  EXPECT_TRUE(whole("-0.0"));
  EXPECT_TRUE(whole("12345678901234"));  // digits dropped before the point are whole
  EXPECT_FALSE(whole("1440.5"));
  EXPECT_FALSE(whole("1440.0000001"));          // its nearest float is 1440, but typed it is not
  EXPECT_FALSE(whole("123456789.5"));           // the fraction is beyond the 9 kept digits
  EXPECT_FALSE(whole("1440.000000000000001"));  // far beyond
  EXPECT_FALSE(whole("1e-12"));
  EXPECT_FALSE(whole("1.5e0"));
}

TEST(ParseUnsigned, DigitsOnlyAndBounded) {
  std::uint32_t v = 0;
  ASSERT_TRUE(parse_unsigned(tok("0"), v));
  EXPECT_EQ(v, 0u);
  ASSERT_TRUE(parse_unsigned(tok("4294967295"), v));
  EXPECT_EQ(v, 4294967295u);
  EXPECT_FALSE(parse_unsigned(tok("4294967296"), v));
  EXPECT_FALSE(parse_unsigned(tok("-1"), v));
  EXPECT_FALSE(parse_unsigned(tok("+1"), v));
  EXPECT_FALSE(parse_unsigned(tok("1.0"), v));
  EXPECT_FALSE(parse_unsigned(tok(""), v));
}

TEST(FormatFixed, RoundsAndPads) {
  EXPECT_EQ(fixed(1.0f, 6), "1.000000");
  EXPECT_EQ(fixed(-2.5f, 3), "-2.500");
  EXPECT_EQ(fixed(0.0333f, 6), "0.033300");
  EXPECT_EQ(fixed(1440.0f, 0), "1440");
  EXPECT_EQ(fixed(2.5f, 0), "3");    // half away from zero
  EXPECT_EQ(fixed(-2.5f, 0), "-3");  // half away from zero
  EXPECT_EQ(fixed(0.0000004f, 6), "0.000000");
  EXPECT_EQ(fixed(-0.0000004f, 6), "0.000000");  // no "-0"
  EXPECT_EQ(fixed(-0.0f, 2), "0.00");
  EXPECT_EQ(fixed(0.9999996f, 6), "1.000000");
  EXPECT_EQ(fixed(151.58f, 6), "151.580002");  // the float's exact value, correctly rounded
  EXPECT_EQ(fixed(549755813888.0f, 1), "549755813888.0");  // 2^39
  EXPECT_EQ(fixed(1e-30f, 9), "0.000000000");
  EXPECT_EQ(fixed(1.5e15f, 6), "1.500000e+15");
  EXPECT_EQ(fixed(-2e20f, 3), "-2.000000e+20");
  EXPECT_EQ(fixed(NAN, 3), "nan");
  EXPECT_EQ(fixed(INFINITY, 3), "inf");
  EXPECT_EQ(fixed(-INFINITY, 3), "-inf");
  char small[4];
  EXPECT_EQ(format_fixed(1.0f, 6, small, sizeof small), 0u);
}

TEST(FormatFixed, MatchesTheExactValueCorrectlyRounded) {
  // Reference: printf of the float's exact binary value (a double holds it exactly), which
  // rounds half to even where format_fixed rounds half away from zero: exact ties are skipped.
  std::mt19937_64 rng(7u);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-9, 11);
  std::uniform_int_distribution<int> decimals(0, 9);
  for (int i = 0; i < 20000; ++i) {
    const float f = static_cast<float>((i % 2 == 0 ? 1.0 : -1.0) * mantissa(rng) *
                                       std::pow(10.0, exponent(rng)));
    const int d = decimals(rng);
    char exact[160];
    std::snprintf(exact, sizeof exact, "%.80f", static_cast<double>(f));
    const std::string digits(exact);
    const std::size_t after = digits.find('.') + 1u + static_cast<std::size_t>(d);
    if (digits[after] == '5' && digits.find_first_not_of('0', after + 1u) == std::string::npos) {
      continue;  // a tie
    }
    char reference[160];
    std::snprintf(reference, sizeof reference, "%.*f", d, static_cast<double>(f));
    std::string expected(reference);
    if (expected.find_first_not_of("-0.") == std::string::npos && expected[0] == '-') {
      expected.erase(0, 1);  // format_fixed never writes "-0"
    }
    ASSERT_EQ(fixed(f, d), expected) << exact << " with " << d << " decimals";
  }
}

TEST(FormatFixed, PrintedFloatsParseBackWithinHalfAnUlpOfTheLastDigit) {
  // 6 decimals: the printed value is within 0.5e-6 of the float, and parses back to it (or its
  // neighbour) when 6 decimals resolve the float.
  const float values[] = {0.05f, 0.033f, 1.0f, 25.0f, 150.0f, 1440.0f, 0.001f, 1.0e6f, 0.99123f};
  for (float f : values) {
    char buffer[64];
    const std::size_t n = format_fixed(f, 6, buffer, sizeof buffer);
    float back = 0;
    ASSERT_TRUE(parse_number(Token{buffer, n}, back));
    EXPECT_LE(ulps_between(back, f), 1) << std::string(buffer, n);
  }
}

TEST(FormatUnsigned, AllSixtyFourBits) {
  char buffer[32];
  const std::uint64_t values[] = {
      0u, 9u, 10u, 4294967295u, 4294967296u, 10000000000000000000ull, 18446744073709551615ull};
  for (std::uint64_t v : values) {
    const std::size_t n = format_unsigned(v, buffer, sizeof buffer);
    EXPECT_EQ(std::string(buffer, n), std::to_string(v));
  }
  EXPECT_EQ(format_unsigned(123u, buffer, 2u), 0u);
}

TEST(Split, SeparatesOnSpacesAndCountsOverflow) {
  Token tokens[3];
  EXPECT_EQ(split("  set  c_l 1 ", 13, tokens, 3), 3u);
  EXPECT_TRUE(tokens[0].is("set"));
  EXPECT_TRUE(tokens[1].is("c_l"));
  EXPECT_TRUE(tokens[2].is("1"));
  EXPECT_EQ(split("a b c d", 7, tokens, 3), 4u);
  EXPECT_EQ(split("   ", 3, tokens, 3), 0u);
}

}  // namespace
}  // namespace odocal::console
