#include "odocal/console/text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

namespace odocal::console {
namespace {

Token tok(const char* s) {
  return Token{s, std::strlen(s)};
}

bool parses(const char* s, double& v) {
  return parse_number(tok(s), v);
}

std::string fixed(double v, int decimals) {
  char buffer[64];
  const std::size_t n = format_fixed(v, decimals, buffer, sizeof buffer);
  return std::string(buffer, n);
}

TEST(ParseNumber, AcceptsPlainDecimalForms) {
  double v = 0;
  ASSERT_TRUE(parses("1", v));
  EXPECT_EQ(v, 1.0);
  ASSERT_TRUE(parses("-2.5", v));
  EXPECT_EQ(v, -2.5);
  ASSERT_TRUE(parses("+0.125", v));
  EXPECT_EQ(v, 0.125);
  ASSERT_TRUE(parses(".5", v));
  EXPECT_EQ(v, 0.5);
  ASSERT_TRUE(parses("5.", v));
  EXPECT_EQ(v, 5.0);
  ASSERT_TRUE(parses("1e3", v));
  EXPECT_EQ(v, 1000.0);
  ASSERT_TRUE(parses("2.5E-3", v));
  EXPECT_NEAR(v, 0.0025, 1e-18);
  ASSERT_TRUE(parses("-0", v));
  EXPECT_EQ(v, 0.0);
  ASSERT_TRUE(parses("0.000000001", v));
  EXPECT_NEAR(v, 1e-9, 1e-24);
  // More digits than a double holds: still the right value to double precision.
  ASSERT_TRUE(parses("3.14159265358979323846264338", v));
  EXPECT_NEAR(v, 3.14159265358979323846, 1e-15);
  ASSERT_TRUE(parses("123456789012345678901234567890", v));
  EXPECT_NEAR(v, 1.2345678901234568e29, 1e14);
  ASSERT_TRUE(parses("1e-400", v));  // underflows to zero: finite
  EXPECT_EQ(v, 0.0);
}

TEST(ParseNumber, RefusesAnythingElse) {
  const char* bad[] = {"",      "-",      "+",     ".",   "1.2.3", "1e",   "1e+",
                       "e5",    "1x",     "1.0a",  " 1",  "1 ",    "0x10", "inf",
                       "-inf",  "nan",    "NaN",   "1,5", "--1",   "+-1",  "1e5.5",
                       "1e999", "-1e400", "1_000", "١",   "1e--3", "12f",  "0b1"};
  for (const char* s : bad) {
    double v = 42.0;
    EXPECT_FALSE(parses(s, v)) << '"' << s << '"';
    EXPECT_EQ(v, 42.0) << "value touched by a refused parse: " << s;
  }
  double v = 0;
  EXPECT_FALSE(parse_number(Token{nullptr, 0}, v));
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
  EXPECT_EQ(fixed(1.0, 6), "1.000000");
  EXPECT_EQ(fixed(-2.5, 3), "-2.500");
  EXPECT_EQ(fixed(0.0333, 6), "0.033300");
  EXPECT_EQ(fixed(1440.0, 0), "1440");
  EXPECT_EQ(fixed(0.0000004, 6), "0.000000");
  EXPECT_EQ(fixed(-0.0000004, 6), "0.000000");  // no "-0"
  EXPECT_EQ(fixed(0.9999996, 6), "1.000000");
  EXPECT_EQ(fixed(999999999999.0, 1), "999999999999.0");
  EXPECT_EQ(fixed(1.5e15, 6), "1.500000e+15");
  EXPECT_EQ(fixed(-2e20, 3), "-2.000000e+20");
  EXPECT_EQ(fixed(NAN, 3), "nan");
  EXPECT_EQ(fixed(INFINITY, 3), "inf");
  EXPECT_EQ(fixed(-INFINITY, 3), "-inf");
  char small[4];
  EXPECT_EQ(format_fixed(1.0, 6, small, sizeof small), 0u);
}

TEST(FormatFixed, PrintedFloatsParseBackWithinHalfAnUlpOfTheLastDigit) {
  // 6 decimals: the printed value is within 0.5e-6 of the float (plus double rounding).
  const float values[] = {0.05f, 0.033f, 1.0f, 25.0f, 150.0f, 1440.0f, 0.001f, 1.0e6f, 0.99123f};
  for (float f : values) {
    char buffer[64];
    const std::size_t n = format_fixed(static_cast<double>(f), 6, buffer, sizeof buffer);
    double back = 0;
    ASSERT_TRUE(parse_number(Token{buffer, n}, back));
    EXPECT_NEAR(back, static_cast<double>(f), 0.5e-6 + 1e-12);
  }
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
