// `odocal umbmark`: the JSON contract and provenance, the text output, the square with straight
// legs, and exit status 2 naming file, line and field for bad input.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

TEST(CliUmbmark, JsonHasEveryContractKeyAndProvenance) {
  for (const std::string exact : {"", " --exact"}) {
    const json doc =
        parse_json(odocal(umbmark_args + exact + " --date 2026-03-01 --cw " +
                          data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv")));
    for (const char* key :
         {"x_cg_cw", "y_cg_cw", "x_cg_ccw", "y_cg_ccw", "r_cg_cw", "r_cg_ccw", "e_max_syst_mm",
          "alpha_deg", "beta_deg", "radius_mm", "e_d", "e_b", "c_l", "c_r", "wheelbase_new_mm",
          "sem_mm", "second_pass_recommended"}) {
      EXPECT_TRUE(doc.contains(key)) << key;
    }
    EXPECT_TRUE(doc["second_pass_recommended"].is_boolean());
    const json& p = doc["provenance"];
    EXPECT_EQ(p["method"], exact.empty() ? "umbmark" : "umbmark-exact");
    EXPECT_EQ(p["runs"], 10);
    EXPECT_EQ(p["date"], "2026-03-01");
    EXPECT_TRUE(p["interval"].is_null());
    expect_no_nan(doc);
    // The fixture was made with E_d = 1.0025, E_b = 1.012 and 15 mm run scatter (σ/√5 ≈ 7 mm
    // on a 4 m square: ~1e-4 in E_d, ~3e-4 in E_b).
    EXPECT_NEAR(doc["e_d"].get<double>(), 1.0025, 3e-4);
    EXPECT_NEAR(doc["e_b"].get<double>(), 1.012, 1e-3);
    EXPECT_NEAR(doc["c_l"].get<double>() + doc["c_r"].get<double>(), 2.0, 1e-12);
  }
}

TEST(CliUmbmark, TextOutputAndNoDateMeansToday) {
  const Result text = odocal("umbmark --side-mm 4000 --wheelbase-mm 340 --cw " +
                             data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("E_d"), std::string::npos);
  const json doc = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                                     data("umbmark_ccw.csv")));
  EXPECT_EQ(doc["provenance"]["date"].get<std::string>().size(), 10u);
}

TEST(CliUmbmark, BadInputExitsTwoNamingFileLineField) {
  const auto run = [](const std::string& cw) {
    return odocal(umbmark_args + " --cw " + data(cw) + " --ccw " + data("umbmark_ccw.csv"));
  };
  expect_bad_input(run("bad_no_header.csv"), "bad_no_header.csv", "1", "x_mm");
  expect_bad_input(run("bad_non_number.csv"), "bad_non_number.csv", "3", "y_mm");
  expect_bad_input(run("bad_one_run.csv"), "bad_one_run.csv", "2", "x_mm");
  expect_bad_input(run("bad_nan.csv"), "bad_nan.csv", "3", "x_mm");
  expect_bad_input(run("bad_inf.csv"), "bad_inf.csv", "3", "y_mm");
  expect_bad_input(run("bad_absurd.csv"), "bad_absurd.csv", "4", "x_mm");
  expect_bad_input(run("bad_field_count.csv"), "bad_field_count.csv", "3", "y_mm");
  const Result missing = run("no_such_file.csv");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("no_such_file.csv"), std::string::npos);
  const Result bad_flag = odocal("umbmark --side-mm -4 --wheelbase-mm 340 --cw " +
                                 data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(bad_flag.status, 2);
  EXPECT_NE(bad_flag.err.find("--side-mm"), std::string::npos) << bad_flag.err;
}

// β = 0 exactly: the legs are straight, the radius infinite. JSON has no infinity: null; the
// angles are 0, never −0.
TEST(CliUmbmark, StraightLegsHaveNoRadiusAndNoNegativeZero) {
  const std::string files =
      " --cw " + data("umbmark_zero.csv") + " --ccw " + data("umbmark_zero.csv");
  for (const std::string exact : {"", " --exact"}) {
    const Result r = odocal(umbmark_args + exact + files);
    const json doc = parse_json(r);
    EXPECT_TRUE(doc["radius_mm"].is_null());
    EXPECT_EQ(doc["beta_deg"], 0.0);
    EXPECT_EQ(doc["alpha_deg"], 0.0);
    EXPECT_FALSE(std::signbit(doc["beta_deg"].get<double>()));
    EXPECT_FALSE(std::signbit(doc["alpha_deg"].get<double>()));
    EXPECT_EQ(r.out.find("-0.0"), std::string::npos) << r.out;
    EXPECT_EQ(doc["e_d"], 1.0);
    const Result text = odocal("umbmark --side-mm 4000 --wheelbase-mm 340" + exact + files);
    EXPECT_EQ(text.status, 0);
    EXPECT_NE(text.out.find("inf"), std::string::npos) << text.out;
    EXPECT_EQ(text.out.find("-0 "), std::string::npos) << text.out;
  }
  // With a curvature the radius is a number: R = (L/2)/sin(β/2).
  const json curved = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                        " --ccw " + data("umbmark_ccw.csv")));
  const double beta_rad = curved["beta_deg"].get<double>() * M_PI / 180.0;
  EXPECT_NEAR(curved["radius_mm"].get<double>(), 2000.0 / std::sin(beta_rad / 2.0), 1e-6);
}

}  // namespace
