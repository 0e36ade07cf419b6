// The host toolkit's CLI11 checks: the message names the flag, what is allowed and what was given.

#include "odocal/toolkit/cli_checks.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace odocal::toolkit {
namespace {

/// The message `check` gives for `text`, "" when it accepts it.
std::string verdict(const CLI::Validator& check, std::string text) {
  return check(text);
}

TEST(RangeCheck, AcceptsBothClosedBoundsExactly) {
  const CLI::Validator check = range_check(1.0, 1e6, "mm");
  EXPECT_EQ(verdict(check, "1"), "");
  EXPECT_EQ(verdict(check, "1000000"), "");
  EXPECT_EQ(verdict(check, "1e6"), "");
  EXPECT_EQ(verdict(check, "0.9999999"),
            "must be a finite number from 1 to 1000000 mm, got '0.9999999'");
  EXPECT_EQ(verdict(check, "1000000.1"),
            "must be a finite number from 1 to 1000000 mm, got '1000000.1'");
  EXPECT_EQ(verdict(check, "nan"), "must be a finite number from 1 to 1000000 mm, got 'nan'");
}

TEST(RangeCheck, AnOpenLowBoundRefusesTheBoundItself) {
  const CLI::Validator check = range_check(0.0, 1e7, "", LowBound::open);
  EXPECT_EQ(verdict(check, "0"), "must be a finite number > 0 and at most 10000000, got '0'");
  EXPECT_EQ(verdict(check, "1e-300"), "");
  EXPECT_EQ(verdict(check, "10000000"), "");
}

TEST(ZeroOrRangeCheck, TakesZeroBesideTheRange) {
  const CLI::Validator check = zero_or_range_check(0.01, 1e6, "");
  EXPECT_EQ(verdict(check, "0"), "");
  EXPECT_EQ(verdict(check, "0.01"), "");
  EXPECT_EQ(verdict(check, "0.005"),
            "must be 0 or a finite number from 0.01 to 1000000, got '0.005'");
}

TEST(NumberCheck, RefusesWhatTheParserRefusesBeforeThePredicate) {
  const CLI::Validator check =
      number_check("a finite number strictly between 0 and 1", [](double) { return true; });
  for (const char* bad : {"", " 0.5", "0.5x", "0x1", "inf", "1e999"}) {
    EXPECT_NE(verdict(check, bad), "") << "'" << bad << "'";
  }
}

TEST(WholeCheck, NamesTheQuantityAndTakesExactBounds) {
  const CLI::Validator check = whole_check(100u, 1000000u, "of replicates");
  EXPECT_EQ(verdict(check, "100"), "");
  EXPECT_EQ(verdict(check, "1000000"), "");
  EXPECT_EQ(verdict(check, "99"),
            "must be a whole number of replicates from 100 to 1000000, got '99'");
  EXPECT_EQ(verdict(check, "-1"),
            "must be a whole number of replicates from 100 to 1000000, got '-1'");
}

TEST(WholeCheck, TheFull64BitRangeNeverWraps) {
  const CLI::Validator check = whole_check(0u, UINT64_MAX);
  EXPECT_EQ(verdict(check, "18446744073709551615"), "");
  EXPECT_EQ(verdict(check, "18446744073709551616"),
            "must be a whole number from 0 to 18446744073709551615, got '18446744073709551616'");
  EXPECT_NE(verdict(check, "-1"), "");
  EXPECT_NE(verdict(check, "1.5"), "");
}

TEST(Checks, NameTheFlagThroughCli11) {
  CLI::App app;
  double side_mm = 0.0;
  app.add_option("--side-mm", side_mm)->check(range_check(1.0, 1e6, "mm"));
  try {
    app.parse(std::vector<std::string>{"nan", "--side-mm"});
    FAIL() << "nan was accepted";
  } catch (const CLI::ValidationError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--side-mm: must be a finite number from 1 to 1000000 mm, got 'nan'");
  }
}

}  // namespace
}  // namespace odocal::toolkit
