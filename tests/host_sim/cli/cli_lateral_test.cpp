// `odocal lateral`: Maddahi's F_lat and F_lon keys and direction, and the input it refuses.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

const std::string lateral_args =
    "lateral --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 --json --trials ";

TEST(CliLateral, JsonKeysAndDirection) {
  const json doc = parse_json(odocal(lateral_args + data("lateral_trials.csv")));
  // The fixture drifts ~22 mm left and stops ~15 mm short on a 1 m line:
  // F_lat ≈ 1 + 2·atan(0.022)·150/1000 = 1.0066, F_lon ≈ 1000/985 = 1.015.
  EXPECT_NEAR(doc["f_lat"].get<double>(), 1.0066, 1.5e-3);
  EXPECT_NEAR(doc["f_lon"].get<double>(), 1.0152, 1.5e-3);
  EXPECT_EQ(doc["provenance"]["method"], "maddahi-eq4-eq5");
  EXPECT_EQ(doc["provenance"]["runs"], 10);
}

TEST(CliLateral, BadInput) {
  expect_bad_input(odocal(lateral_args + data("lateral_absurd.csv")), "lateral_absurd.csv", "3",
                   "x_mm");
  expect_bad_input(odocal(lateral_args + data("bad_one_run.csv")), "bad_one_run.csv", "2", "x_mm");
  expect_bad_input(odocal(lateral_args + data("lateral_nan.csv")), "lateral_nan.csv", "3", "y_mm");
}

TEST(CliLateral, TooManyTrialsSaysTheLimit) {
  std::string trials = "x_mm,y_mm\n";
  for (int i = 0; i < 1025; ++i) {
    trials += std::to_string(990 + i % 7) + "," + std::to_string(i % 5) + "\n";
  }
  const Result r = odocal(
      "lateral --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 "
      "--trials " +
      temp_file("lateral_1025.csv", trials));
  expect_refused(r, "lateral_1025.csv:1026: field 'x_mm'", "too many trials");
  EXPECT_NE(r.err.find("1024"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("too few"), std::string::npos) << r.err;
}

}  // namespace
