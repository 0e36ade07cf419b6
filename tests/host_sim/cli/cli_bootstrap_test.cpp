// `odocal bootstrap`: determinism and provenance, an unknown at rest, and the input and the
// work it refuses.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

const std::string bootstrap_args = "bootstrap --json --b 2000 --seed 7 --date 2026-03-01";

TEST(CliBootstrap, JsonKeysDeterminismAndProvenance) {
  const std::string files = " --training " + data("bootstrap_training.csv") + " --unknowns " +
                            data("bootstrap_unknowns.csv");
  const Result first = odocal(bootstrap_args + files);
  const Result second = odocal(bootstrap_args + files);
  EXPECT_EQ(first.out, second.out);  // same seed, same bytes
  const json doc = parse_json(first);
  ASSERT_EQ(doc["unknowns"].size(), 5u);
  for (const json& u : doc["unknowns"]) {
    for (const char* key : {"lr_l", "lr_r", "boot_l", "boot_r", "ci_l", "ci_r", "r_l", "r_r"}) {
      EXPECT_TRUE(u.contains(key)) << key;
    }
    ASSERT_EQ(u["ci_l"].size(), 2u);
    EXPECT_LT(u["ci_l"][0].get<double>(), u["boot_l"].get<double>());
    EXPECT_GT(u["ci_l"][1].get<double>(), u["boot_l"].get<double>());
    EXPECT_NEAR(u["r_l"].get<double>(), u["boot_l"].get<double>() / u["lr_l"].get<double>(), 1e-12);
  }
  const json& p = doc["provenance"];
  // DESIGN: the percentile interval at the chosen level, unless --interval calibrated.
  EXPECT_EQ(p["interval"], "percentile");
  EXPECT_EQ(p["level"], 0.95);
  EXPECT_EQ(p["effective_level"], 0.95);
  EXPECT_EQ(p["seed"], 7);
  EXPECT_EQ(p["replicates"], 2000);
  expect_no_nan(doc);
  const Result other_seed = odocal("bootstrap --json --b 2000 --seed 8" + files);
  EXPECT_NE(parse_json(other_seed)["unknowns"][0]["boot_l"], doc["unknowns"][0]["boot_l"]);
  // With the geometry, eq. 7 factors per unknown: the fixture's left wheel runs 1.5 % slow.
  const json factors = parse_json(odocal(bootstrap_args + files +
                                         " --interval calibrated --wheelbase-mm 150 --dl-mm 60 "
                                         "--dr-mm 60"));
  EXPECT_EQ(factors["provenance"]["interval"], "percentile-t-calibrated");
  // t_34 widening (m = 20): 2Φ(t_34,0.975) − 1 ≈ 0.958, and the interval is wider.
  EXPECT_NEAR(factors["provenance"]["effective_level"].get<double>(), 0.958, 1e-3);
  const json& plain = doc["unknowns"][0];
  const json& wide = factors["unknowns"][0];
  EXPECT_GT(wide["ci_l"][1].get<double>() - wide["ci_l"][0].get<double>(),
            plain["ci_l"][1].get<double>() - plain["ci_l"][0].get<double>());
  for (const json& u : factors["unknowns"]) {
    EXPECT_NEAR(u["factors_lr"]["f_lat"].get<double>(), 0.985, 0.01);
    EXPECT_NEAR(u["factors_lr"]["f_lon"].get<double>(), 1.0, 0.01);
  }
}

TEST(CliBootstrap, BadInput) {
  const std::string unknowns = " --unknowns " + data("bootstrap_unknowns.csv");
  expect_bad_input(
      odocal(bootstrap_args + " --training " + data("bootstrap_training_few.csv") + unknowns),
      "bootstrap_training_few.csv", "4", "xdot");
  const Result degenerate = odocal(bootstrap_args + " --training " +
                                   data("bootstrap_training_degenerate.csv") + unknowns);
  expect_bad_input(degenerate, "bootstrap_training_degenerate.csv", "2-9", "ydot");
  EXPECT_NE(degenerate.err.find("degenerate"), std::string::npos);
  expect_bad_input(odocal(bootstrap_args + " --training " + data("bad_no_header.csv") + unknowns),
                   "bad_no_header.csv", "1", "xdot");
  const Result b_too_small =
      odocal("bootstrap --b 5 --training " + data("bootstrap_training.csv") + unknowns);
  EXPECT_EQ(b_too_small.status, 2);
  EXPECT_NE(b_too_small.err.find("--b"), std::string::npos) << b_too_small.err;
}

TEST(CliBootstrap, AbsurdTrainingValuesAreRefusedByLineAndField) {
  const Result r = odocal(bootstrap_args + " --training " + data("bootstrap_training_absurd.csv") +
                          " --unknowns " + data("bootstrap_unknowns.csv"));
  expect_bad_input(r, "bootstrap_training_absurd.csv", "6", "xdot");
  EXPECT_EQ(r.err.find("degenerate"), std::string::npos) << r.err;
}

// An unknown standing still: its LR estimates are 0, so r = boot/lr is undefined (null), and
// its eq. 7 factors too; every other field is a number and the other unknowns are unaffected.
TEST(CliBootstrap, UnknownAtRestHasNullRatiosOnly) {
  const std::string files = " --training " + data("bootstrap_training.csv") + " --unknowns " +
                            data("bootstrap_unknowns_at_rest.csv");
  const json doc =
      parse_json(odocal(bootstrap_args + files + " --wheelbase-mm 150 --dl-mm 60 --dr-mm 60"));
  ASSERT_EQ(doc["unknowns"].size(), 2u);
  const json& rest = doc["unknowns"][0];
  EXPECT_TRUE(rest["r_l"].is_null());
  EXPECT_TRUE(rest["r_r"].is_null());
  EXPECT_TRUE(rest["factors_lr"].is_null());
  EXPECT_EQ(rest["lr_l"], 0.0);
  for (const char* key : {"lr_r", "boot_l", "boot_r"}) {
    EXPECT_TRUE(rest[key].is_number()) << key;
  }
  EXPECT_TRUE(rest["ci_l"][0].is_number());
  const json& moving = doc["unknowns"][1];
  EXPECT_NEAR(moving["r_l"].get<double>(),
              moving["boot_l"].get<double>() / moving["lr_l"].get<double>(), 1e-12);
  EXPECT_TRUE(moving["factors_lr"].is_object());
  expect_no_nan(doc);
  const Result text = odocal("bootstrap" + files);
  EXPECT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("n/a"), std::string::npos) << text.out;
}

// B predictions per unknown are kept for the percentiles: 2000 unknowns at B = 10^6 would need
// 32 GB. The work is bounded (10^7 predictions) and the message says what fits.
TEST(CliBootstrap, HugeWorkIsRefusedBeforeAllocating) {
  std::string unknowns = "xdot,ydot,thetadot\n";
  for (int i = 0; i < 2000; ++i) {
    unknowns += "0.3,0.01,0.01\n";
  }
  const Result r = odocal("bootstrap --b 1000000 --training " + data("bootstrap_training.csv") +
                          " --unknowns " + temp_file("unknowns_2000.csv", unknowns));
  expect_refused(r, "unknowns_2000.csv:12: field 'xdot'", "at most 10 unknowns with this --b");
}

}  // namespace
