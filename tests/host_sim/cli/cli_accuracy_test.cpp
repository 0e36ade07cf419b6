// `odocal accuracy`: the paper's Tables 3 and 4 through the program, an undefined improvement,
// and the input it refuses.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

// Maddahi & Zareinia Tables 3 and 4 through the program, to the printed precision.
TEST(CliAccuracy, ReproducesTables3And4) {
  struct Expected {
    const char* file;
    double rms[3];
    double improvement[3];
  };
  for (const Expected& e :
       {Expected{"table3_systematic.csv", {57.5, 11.0, 7.1}, {0.0, 80.9, 87.6}},
        Expected{"table4_bumps.csv", {3995.3, 742.8, 476.7}, {0.0, 81.4, 88.1}}}) {
    const json doc = parse_json(odocal("accuracy --json --baseline NC " + data(e.file)));
    const json& s = doc["scenarios"];
    ASSERT_EQ(s.size(), 3u);
    const char* names[3] = {"NC", "CL", "CB"};
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(s[i]["name"], names[i]);
      EXPECT_EQ(s[i]["trials"], 5);
      EXPECT_NEAR(s[i]["rms_mm"].get<double>(), e.rms[i], 0.05) << e.file << " " << names[i];
      EXPECT_NEAR(s[i]["improvement_pct"].get<double>(), e.improvement[i], 0.05)
          << e.file << " " << names[i];
    }
    EXPECT_EQ(doc["provenance"]["runs"], 15);
  }
  const Result text = odocal("accuracy " + data("table3_systematic.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("87.6"), std::string::npos) << text.out;
}

TEST(CliAccuracy, BadInput) {
  expect_bad_input(odocal("accuracy --json " + data("accuracy_bad.csv")), "accuracy_bad.csv", "3",
                   "y_mm");
  expect_bad_input(odocal("accuracy " + data("bad_one_run.csv")), "bad_one_run.csv", "1",
                   "scenario");
  const Result no_baseline = odocal("accuracy --baseline XX " + data("table3_systematic.csv"));
  EXPECT_EQ(no_baseline.status, 2);
  EXPECT_NE(no_baseline.err.find("XX"), std::string::npos);
}

// Errors of 1e155 mm overflow x² + y²; scenario names that are not text break the JSON.
TEST(CliAccuracy, AbsurdErrorsAndNonAsciiNamesAreRefused) {
  expect_bad_input(odocal("accuracy --json " + data("accuracy_huge.csv")), "accuracy_huge.csv", "4",
                   "x_mm");
  const std::string bad_name = temp_file("accuracy_not_utf8.csv",
                                         "scenario,trial,x_mm,y_mm\nNC,1,1,1\nN\xFF"
                                         "C,1,2,2\n");
  const Result r = odocal("accuracy --json " + bad_name);
  expect_bad_input(r, "accuracy_not_utf8.csv", "3", "scenario");
  EXPECT_NE(r.err.find("ASCII"), std::string::npos) << r.err;
}

// A baseline RMS of 0 leaves the improvement undefined: null in JSON, n/a in text, never 0.
TEST(CliAccuracy, ZeroBaselineHasNoImprovementInJsonOrText) {
  const json doc = parse_json(odocal("accuracy --json " + data("accuracy_zero_baseline.csv")));
  ASSERT_EQ(doc["scenarios"].size(), 2u);
  EXPECT_EQ(doc["scenarios"][0]["rms_mm"], 0.0);
  EXPECT_NEAR(doc["scenarios"][1]["rms_mm"].get<double>(), std::sqrt(12.5), 1e-12);
  for (const json& s : doc["scenarios"]) {
    EXPECT_TRUE(s["improvement_pct"].is_null());
  }
  const Result text = odocal("accuracy " + data("accuracy_zero_baseline.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("n/a"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("0.0 \n"), std::string::npos) << text.out;
}

}  // namespace
