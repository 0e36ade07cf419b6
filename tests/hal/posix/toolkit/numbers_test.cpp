// The host toolkit's number parsing: what every host program accepts as a number.

#include "odocal/toolkit/numbers.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

namespace odocal::toolkit {
namespace {

TEST(ParseReal, TakesPlainDecimalNotation) {
  EXPECT_EQ(parse_real("4000"), 4000.0);
  EXPECT_EQ(parse_real("-2.5e3"), -2500.0);
  EXPECT_EQ(parse_real("+1.5"), 1.5);  // a leading '+' is a sign, as people write it
  EXPECT_EQ(parse_real(".5"), 0.5);
  EXPECT_EQ(parse_real("5."), 5.0);
  EXPECT_EQ(parse_real("1E-3"), 1e-3);
  EXPECT_EQ(parse_real("-0"), 0.0);
}

TEST(ParseReal, RefusesAnythingElse) {
  for (const char* bad :
       {"",     " ",   " 1",   "1 ",       "\t1", "1\r",   "abc",   "4000x", "1.2.3",
        "1e",   "e5",  "--1",  "+-1",      "1+2", "0x10",  "0X1p3", "nan",   "NaN",
        "-nan", "inf", "-inf", "Infinity", "1,5", "1e999", "-1e999"}) {
    EXPECT_FALSE(parse_real(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(ReadNumber, TellsOverflowFromJunk) {
  double value = 7.0;
  EXPECT_EQ(read_number("1e999", value), NumberText::out_of_range);
  EXPECT_EQ(read_number("-1e400", value), NumberText::out_of_range);
  EXPECT_EQ(read_number("inf", value), NumberText::not_a_number);
  EXPECT_EQ(read_number("", value), NumberText::not_a_number);
  EXPECT_EQ(value, 7.0) << "value is set only on ok";
  // The largest double is still a number; the next decade is not.
  EXPECT_EQ(read_number("1.7976931348623157e308", value), NumberText::ok);
  EXPECT_EQ(value, std::numeric_limits<double>::max());
  EXPECT_EQ(read_number("1.8e308", value), NumberText::out_of_range);
}

TEST(ReadNumber, AnUnderflowIsANumberTakenAsItRounds) {
  double value = 7.0;
  ASSERT_EQ(read_number("1e-310", value), NumberText::ok);  // subnormal
  EXPECT_GT(value, 0.0);
  EXPECT_LT(value, std::numeric_limits<double>::min());
  ASSERT_EQ(read_number("1e-400", value), NumberText::ok);  // below the smallest subnormal
  EXPECT_EQ(value, 0.0);
}

TEST(ParseWhole, TakesDigitsUpToTwoToThe64Minus1) {
  EXPECT_EQ(parse_whole("0"), 0u);
  EXPECT_EQ(parse_whole("007"), 7u);
  EXPECT_EQ(parse_whole("18446744073709551615"), UINT64_MAX);
}

TEST(ParseWhole, RefusesSignsFractionsJunkAndOverflow) {
  for (const char* bad : {"", " 1", "1 ", "-1", "+1", "1.0", "1e3", "0x10", "12a", "nan", "inf",
                          "18446744073709551616", "99999999999999999999999"}) {
    EXPECT_FALSE(parse_whole(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(ParseWholeIn, TakesExactlyTheClosedRange) {
  EXPECT_EQ(parse_whole_in("2", 2u, 64u), 2u);
  EXPECT_EQ(parse_whole_in("64", 2u, 64u), 64u);
  EXPECT_FALSE(parse_whole_in("1", 2u, 64u).has_value());
  EXPECT_FALSE(parse_whole_in("65", 2u, 64u).has_value());
  EXPECT_EQ(parse_whole_in("18446744073709551615", 0u, UINT64_MAX), UINT64_MAX);
}

TEST(ParseInteger, TakesAMinusSignAndTheWholeSignedRange) {
  EXPECT_EQ(parse_integer("-120"), -120);
  EXPECT_EQ(parse_integer("9223372036854775807"), INT64_MAX);
  EXPECT_EQ(parse_integer("-9223372036854775808"), INT64_MIN);
  for (const char* bad :
       {"", "+1", "1.0", "1e3", " 1", "-", "9223372036854775808", "-9223372036854775809", "0x1"}) {
    EXPECT_FALSE(parse_integer(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(Trim, RemovesSpacesTabsAndCarriageReturnsAtBothEnds) {
  EXPECT_EQ(trim(" \t a b \r"), "a b");
  EXPECT_EQ(trim(" \t\r "), "");
  EXPECT_EQ(trim(""), "");
}

TEST(BoundText, WritesBoundsAsPeopleDo) {
  EXPECT_EQ(bound_text(1e6), "1000000");
  EXPECT_EQ(bound_text(0.5), "0.5");
  EXPECT_EQ(bound_text(1e4), "10000");
  EXPECT_EQ(bound_text(0.01), "0.01");
  EXPECT_EQ(bound_text(1e7), "10000000");
}

}  // namespace
}  // namespace odocal::toolkit
