// `odocal ros2`: the parameter file from UMBmark's JSON or from flags, its float literals, and
// the names and multipliers it refuses.
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

TEST(CliRos2, FromUmbmarkJsonAndFromFlags) {
  const std::string json_file = ::testing::TempDir() + "odocal_cli_umbmark.json";
  const Result u = odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                          data("umbmark_ccw.csv"));
  ASSERT_EQ(u.status, 0);
  std::ofstream(json_file) << u.out;
  const json doc = json::parse(u.out);
  const Result yaml = odocal("ros2 --from " + json_file);
  ASSERT_EQ(yaml.status, 0) << yaml.err;
  EXPECT_NE(yaml.out.find("diff_drive_controller:\n  ros__parameters:\n"), std::string::npos);
  const auto value_of = [&](const std::string& key) {
    const auto at = yaml.out.find(key + ": ");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(yaml.out.substr(at + key.size() + 2));
  };
  EXPECT_NEAR(value_of("wheel_separation_multiplier"), doc["e_b"].get<double>(), 1e-8);
  EXPECT_NEAR(value_of("left_wheel_radius_multiplier"), doc["c_l"].get<double>(), 1e-8);
  EXPECT_NEAR(value_of("right_wheel_radius_multiplier"), doc["c_r"].get<double>(), 1e-8);
  const Result flags = odocal("ros2 --c-l 0.99 --c-r 1.01 --e-b 1.02 --controller base");
  EXPECT_EQ(flags.status, 0);
  EXPECT_NE(flags.out.find("base:\n  ros__parameters:\n    wheel_separation_multiplier: 1.02\n"),
            std::string::npos)
      << flags.out;
}

TEST(CliRos2, BadInput) {
  const Result bad_json = odocal("ros2 --from " + data("ros2_bad.json"));
  EXPECT_EQ(bad_json.status, 2);
  EXPECT_NE(bad_json.err.find("ros2_bad.json:4"), std::string::npos) << bad_json.err;
  const Result missing = odocal("ros2 --from " + data("ros2_missing_key.json"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("field 'e_b'"), std::string::npos) << missing.err;
  EXPECT_EQ(odocal("ros2 --c-l 0.99").status, 2);
  EXPECT_EQ(odocal("ros2 --from x.json --c-l 0.99").status, 2);
}

// ROS 2 declares the multipliers as doubles: every value must read back as a float (a '.' or an
// exponent), and as exactly the double odocal computed.
TEST(CliRos2, ValuesAreFloatLiteralsThatRoundTrip) {
  const auto values = [](const Result& yaml) {
    std::vector<std::string> out;
    for (const std::string key : {"wheel_separation_multiplier", "left_wheel_radius_multiplier",
                                  "right_wheel_radius_multiplier"}) {
      const auto at = yaml.out.find("    " + key + ": ");
      EXPECT_NE(at, std::string::npos) << key;
      const auto start = at + key.size() + 6;
      out.push_back(yaml.out.substr(start, yaml.out.find('\n', start) - start));
    }
    return out;
  };
  const Result ones = odocal("ros2 --c-l 1 --c-r 2 --e-b 1.000000000000000222");
  ASSERT_EQ(ones.status, 0) << ones.err;
  const std::vector<std::string> text = values(ones);
  const double expected[3] = {1.000000000000000222, 1.0, 2.0};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NE(text[i].find_first_of(".eE"), std::string::npos) << text[i];
    EXPECT_EQ(std::stod(text[i]), expected[i]) << text[i];
  }
  const std::string json_file = ::testing::TempDir() + "odocal_cli_umbmark_rt.json";
  const Result u = odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                          data("umbmark_ccw.csv"));
  ASSERT_EQ(u.status, 0);
  std::ofstream(json_file) << u.out;
  const json doc = json::parse(u.out);
  const std::vector<std::string> from = values(odocal("ros2 --from " + json_file));
  EXPECT_EQ(std::stod(from[0]), doc["e_b"].get<double>());
  EXPECT_EQ(std::stod(from[1]), doc["c_l"].get<double>());
  EXPECT_EQ(std::stod(from[2]), doc["c_r"].get<double>());
}

TEST(CliRos2, ControllerNameAndMultipliersAreValidated) {
  const std::string values = "ros2 --c-l 0.99 --c-r 1.01 --e-b 1.02 --controller ";
  EXPECT_EQ(odocal(values + "_base_2").status, 0);
  for (const std::string bad : {"'a b'", "2base", "''", "'base:'", "'x\ny'", "base-1"}) {
    const Result r = odocal(values + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_NE(r.err.find("--controller"), std::string::npos) << r.err;
  }
  for (const std::string bad : {"--c-l 0", "--c-l nan", "--c-r inf", "--e-b 11", "--e-b 1x"}) {
    const Result r = odocal("ros2 --c-l 1 --c-r 1 --e-b 1 " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find(bad.substr(0, 5)), std::string::npos) << r.err;
  }
  const std::string zero = temp_file("ros2_zero.json", R"({"c_l": 0, "c_r": 1, "e_b": 1})");
  const Result r = odocal("ros2 --from " + zero);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("field 'c_l'"), std::string::npos) << r.err;
}

}  // namespace
