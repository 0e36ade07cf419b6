// `odocal fit`'s noise object and `odocal ros2 --from FIT.json`'s covariances, end to end through
// the program; the sessions that fit give the same JSON, and `ros2 --from` reads their
// session.json.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

std::string odocal_binary() {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  return odocal.empty() || !std::ifstream(odocal) ? std::string() : odocal;
}

int run_command(const std::string& command, std::string& out, std::string& err) {
  const std::string tag = std::to_string(::getpid());
  const std::string out_file = ::testing::TempDir() + "odocal_noise_out_" + tag + ".txt";
  const std::string err_file = ::testing::TempDir() + "odocal_noise_err_" + tag + ".txt";
  const int status = std::system((command + " >" + out_file + " 2>" + err_file).c_str());
  std::ifstream o(out_file);
  out.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  std::ifstream e(err_file);
  err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The six numbers of a YAML line `key: [a, b, c, d, e, f]`.
std::vector<double> yaml_list(const std::string& text, const std::string& key) {
  std::vector<double> values;
  const auto at = text.find(key + ": [");
  if (at == std::string::npos) {
    return values;
  }
  std::string list = text.substr(at + key.size() + 3);
  list = list.substr(0, list.find(']'));
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    values.push_back(std::stod(item));
  }
  return values;
}

TEST(OdocalFitNoise, FitJsonCarriesNoiseAndRos2WritesItsCovariances) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  RobotSpec spec = default_robot();
  spec.truth.slip_sigma = 0.003;
  SimulatedRobot robot(spec, 31u);
  std::string logs;
  for (int i = 0; i < 16; ++i) {
    const drive::Path path =
        i % 4 == 3 ? drive::make_line(2.0f) : drive::make_umbmark_square(i % 2 == 0, 2.0f);
    TickLog log;
    ASSERT_TRUE(run_path_logged(robot, path, log, LogTruth::end_only, 20u).completed);
    const std::string file = ::testing::TempDir() + "noise_cmd_run" + std::to_string(i) + ".csv";
    std::ofstream out(file);
    write_tick_log(log, out);
    logs += " " + file;
  }
  std::string out, err;
  ASSERT_EQ(run_command(odocal + " fit --log" + logs +
                            " --wheel-diameter-mm 60 --wheelbase-mm 150 --counts-per-rev 1440"
                            " --b 100 --seed 2 --json",
                        out, err),
            0)
      << err << out;
  const nlohmann::json fit = nlohmann::json::parse(out);
  ASSERT_TRUE(fit.contains("noise")) << out;
  const nlohmann::json& noise = fit["noise"];
  for (const char* key : {"k_l", "k_r", "ci"}) {
    ASSERT_TRUE(noise.contains(key)) << key;
  }
  for (const char* key : {"k_l", "k_r"}) {
    const double k = noise[key].get<double>();
    ASSERT_EQ(noise["ci"][key].size(), 2u);
    EXPECT_LE(noise["ci"][key][0].get<double>(), k);
    EXPECT_GE(noise["ci"][key][1].get<double>(), k);
    EXPECT_GE(k, 0.0);
  }

  const std::string fit_file = ::testing::TempDir() + "noise_cmd_fit.json";
  std::ofstream(fit_file) << out;
  ASSERT_EQ(run_command(odocal + " ros2 --from " + fit_file +
                            " --speed-mps 0.3 --update-rate-hz 20 --velocity-window 4 "
                            "--pose-distance-m 2",
                        out, err),
            0)
      << err;
  const std::vector<double> pose = yaml_list(out, "pose_covariance_diagonal");
  const std::vector<double> twist = yaml_list(out, "twist_covariance_diagonal");
  ASSERT_EQ(pose.size(), 6u) << out;
  ASSERT_EQ(twist.size(), 6u) << out;
  const Ros2Covariance expected =
      ros2_covariance(WheelNoise{noise["k_l"].get<double>(), noise["k_r"].get<double>()},
                      fit["wheelbase_mm"].get<double>(), 0.3, RosVelocityEstimate{20.0, 4u}, 2.0);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(pose[i], expected.pose[i], 1e-12 * expected.pose[i]) << i;
    EXPECT_NEAR(twist[i], expected.twist[i], 1e-12 * expected.twist[i]) << i;
  }
  EXPECT_NE(out.find("wheel_separation_multiplier"), std::string::npos);
  // The comment says which estimator the twist follows.
  EXPECT_NE(out.find("update rate 20 Hz, velocity_rolling_window_size 4"), std::string::npos)
      << out;

  // A noise object with a negative growth is refused, naming the field.
  nlohmann::json bad = fit;
  bad["noise"]["k_r"] = -1.0;
  const std::string bad_file = ::testing::TempDir() + "noise_cmd_bad.json";
  std::ofstream(bad_file) << bad.dump();
  EXPECT_EQ(run_command(odocal + " ros2 --from " + bad_file, out, err), 2);
  EXPECT_NE(err.find("noise.k_r"), std::string::npos) << err;
  EXPECT_TRUE(out.empty()) << out;
  EXPECT_EQ(run_command(odocal + " ros2 --from " + fit_file + " --update-rate-hz 0", out, err), 2);
  EXPECT_NE(err.find("--update-rate-hz"), std::string::npos) << err;
  EXPECT_EQ(run_command(odocal + " ros2 --from " + fit_file + " --velocity-window 0", out, err), 2);
  EXPECT_NE(err.find("--velocity-window"), std::string::npos) << err;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// `odocal ros2 --from FILE`'s covariance diagonals and multipliers agree with the fit object
/// `fit` (the arithmetic of ros2_covariance on its noise and wheelbase; the shortest decimals
/// that read back as the same doubles, so to rounding).
void expect_ros2_of(const std::string& odocal, const std::string& file, const nlohmann::json& fit) {
  std::string out, err;
  ASSERT_EQ(run_command(odocal + " ros2 --from " + file, out, err), 0) << err;
  const std::vector<double> pose = yaml_list(out, "pose_covariance_diagonal");
  const std::vector<double> twist = yaml_list(out, "twist_covariance_diagonal");
  ASSERT_EQ(pose.size(), 6u) << out;
  ASSERT_EQ(twist.size(), 6u) << out;
  // ros2's defaults: 0.2 m/s, the controller's own (100 Hz, a window of 10), the pose after 1 m
  // (docs/ros.md).
  const Ros2Covariance expected = ros2_covariance(
      WheelNoise{fit["noise"]["k_l"].get<double>(), fit["noise"]["k_r"].get<double>()},
      fit["wheelbase_mm"].get<double>(), 0.2, RosVelocityEstimate{}, 1.0);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(pose[i], expected.pose[i], 1e-12 * expected.pose[i]) << i;
    EXPECT_NEAR(twist[i], expected.twist[i], 1e-12 * expected.twist[i]) << i;
  }
  for (const auto& [key, name] : {std::pair{"e_b", "wheel_separation_multiplier"},
                                  std::pair{"c_l", "left_wheel_radius_multiplier"},
                                  std::pair{"c_r", "right_wheel_radius_multiplier"}}) {
    const auto at = out.find(std::string(name) + ": ");
    ASSERT_NE(at, std::string::npos) << out;
    EXPECT_EQ(std::stod(out.substr(at + std::string(name).size() + 2)), fit[key].get<double>())
        << name;
  }
}

TEST(OdocalFitNoise, FittingSessionsGiveOdocalFitsJsonAndRos2ReadsTheirSessionJson) {
  const std::string odocal = odocal_binary();
  if (odocal.empty() || !std::ifstream(odocal + "-sim")) {
    FAIL() << "odocal and odocal-sim not built (cmake --build --preset host builds them)";
  }
  // A robot that slips (k = σ²·50 mm = 4.5e-4 mm²/mm per wheel): the noise has something to find.
  const std::string robot = ::testing::TempDir() + "noise_session_robot.json";
  std::ofstream(robot) << R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150,
      "counts_per_rev": 1440, "true_left_diameter_mm": 59.85, "true_right_diameter_mm": 60.15,
      "true_wheelbase_mm": 153, "slip_sigma": 0.003, "bump_height_mm": 0,
      "measure_sigma_mm": 2})";
  std::string out, err;

  // --procedure fit: its result is `odocal fit`'s JSON on its logs, every key, noise included
  // (the same computation on the same files and options: equal, not merely close).
  const std::string fit_dir = ::testing::TempDir() + "noise_session_fit";
  std::system(("rm -rf " + fit_dir).c_str());
  ASSERT_EQ(run_command(odocal + " session --sim " + robot +
                            " --seed 4 --procedure fit --runs 6 --yes --json --out " + fit_dir,
                        out, err),
            0)
      << err;
  const nlohmann::json session = nlohmann::json::parse(read_file(fit_dir + "/session.json"));
  const nlohmann::json& result = session["result"];
  std::string logs;
  for (int i = 1; i <= 6; ++i) {
    logs += " " + fit_dir + "/fit_run_0" + std::to_string(i) + ".csv";
  }
  ASSERT_EQ(run_command(odocal + " fit --log" + logs +
                            " --wheel-diameter-mm 60 --wheelbase-mm 150 --counts-per-rev 1440 "
                            "--seed 4 --json",
                        out, err),
            0)
      << err;
  const nlohmann::json fit = nlohmann::json::parse(out);
  ASSERT_TRUE(fit["noise"].contains("k_l")) << fit["noise"].dump();
  for (const auto& [key, value] : fit.items()) {
    ASSERT_TRUE(result.contains(key)) << key;
    EXPECT_EQ(result[key], value) << key;
  }
  expect_ros2_of(odocal, fit_dir + "/session.json", result);

  // --procedure auto: the fit is result.fit, in the same shape, noise and its intervals included.
  const std::string auto_dir = ::testing::TempDir() + "noise_session_auto";
  std::system(("rm -rf " + auto_dir).c_str());
  ASSERT_EQ(run_command(odocal + " session --sim " + robot +
                            " --seed 4 --procedure auto --yes --json --out " + auto_dir,
                        out, err),
            0)
      << err;
  const nlohmann::json auto_session = nlohmann::json::parse(read_file(auto_dir + "/session.json"));
  const nlohmann::json& auto_fit = auto_session["result"]["fit"];
  for (const auto& [key, value] : fit.items()) {
    EXPECT_TRUE(auto_fit.contains(key)) << key;
  }
  for (const char* key : {"k_l", "k_r"}) {
    ASSERT_EQ(auto_fit["noise"]["ci"][key].size(), 2u) << auto_fit["noise"].dump();
  }
  expect_ros2_of(odocal, auto_dir + "/session.json", auto_fit);

  // A session.json whose fit lacks a multiplier is refused, naming where it should be.
  nlohmann::json bad = session;
  bad["result"].erase("c_r");
  const std::string bad_file = ::testing::TempDir() + "noise_session_bad.json";
  std::ofstream(bad_file) << bad.dump();
  EXPECT_EQ(run_command(odocal + " ros2 --from " + bad_file, out, err), 2);
  EXPECT_NE(err.find("result.c_r"), std::string::npos) << err;
}

}  // namespace
}  // namespace odocal::host
