// End-to-end: the firmware control loop on the simulated robot, through the procedures.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {
namespace {

constexpr double pi = 3.14159265358979323846;

RobotSpec robot_with_errors(double e_d, double wheelbase_mm) {
  RobotSpec spec = default_robot();
  // Mean diameter kept at the nominal 60 mm so E_b is the wheelbase ratio alone.
  spec.truth.left_diameter_m = 0.060 * 2.0 / (1.0 + e_d);
  spec.truth.right_diameter_m = 0.060 * 2.0 * e_d / (1.0 + e_d);
  spec.truth.wheelbase_m = wheelbase_mm * 1e-3;
  return spec;
}

TEST(SimUmbmark, CalibrationRecoversKnownErrorsAndImprovesTheRobot) {
  const RobotSpec spec = robot_with_errors(1.003, 148.5);  // E_d = 1.003, E_b = 0.99
  UmbmarkOptions options;                                  // 4 m square, 5 + 5 runs, as the paper
  const UmbmarkReport report = run_umbmark(spec, 7u, options);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_NEAR(report.truth.e_d, 1.003, 1e-12);
  EXPECT_NEAR(report.truth.e_b, 0.99, 1e-12);
  // Before: E_d bends each 4 m leg by β ≈ (E_d − 1)·L/b = 0.08 rad and E_b turns each corner
  // α = 0.9° short; the return errors are hundreds of mm.
  EXPECT_GT(report.passes.front().result.e_max_syst_mm, 300.0);
  // The return errors scatter with σ ≈ 10-20 mm (slip, 2 mm measurement), so a centre of gravity
  // of 5 runs is known to 3·SEM ≈ 25 mm. On a 4 m square that bounds
  // δβ ≈ √2·25 mm/(4L) = 2.2 mrad -> δE_d = 2b·δβ/L ≈ 1.7e-4, and δα ≈ 2.2 mrad ->
  // δE_b = δα/(π/2) ≈ 1.4e-3.
  EXPECT_NEAR(report.recovered_e_d, report.truth.e_d, 3e-4);
  EXPECT_NEAR(report.recovered_e_b, report.truth.e_b, 2e-3);
  // After: only the c.g. uncertainty is left, so the fold improvement is several-fold at least.
  EXPECT_GT(report.improvement_fold, 5.0);
  EXPECT_LT(report.passes.back().result.e_max_syst_mm, 60.0);
}

UmbmarkReport short_umbmark(std::uint64_t seed) {
  UmbmarkOptions options;
  options.side_m = 1.0;
  options.runs = 3;
  options.max_passes = 1;
  return run_umbmark(default_robot(), seed, options);
}

TEST(SimUmbmark, SameSeedSameReportAnotherSeedDiffers) {
  const std::string a = umbmark_report_json(short_umbmark(5u)).dump();
  const std::string b = umbmark_report_json(short_umbmark(5u)).dump();
  const std::string c = umbmark_report_json(short_umbmark(6u)).dump();
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(SimMonteCarlo, ThreadCountDoesNotChangeTheResult) {
  MonteCarloOptions options;
  options.robots = 4;
  options.umbmark.side_m = 0.5;
  options.umbmark.runs = 2;
  options.umbmark.max_passes = 1;
  options.threads = 1;
  const std::string one =
      montecarlo_report_json(run_montecarlo(default_robot(), 3u, options)).dump();
  options.threads = 2;
  const std::string two =
      montecarlo_report_json(run_montecarlo(default_robot(), 3u, options)).dump();
  EXPECT_EQ(one, two);
}

TEST(SimRobot, UnseenPathEndsWhereMaddahiFigure9Says) {
  const sim::WorldPose end = path_end(drive::make_unseen_path());
  EXPECT_NEAR(end.x_m, 0.0, 1e-6);
  EXPECT_NEAR(end.y_m, 1.6, 1e-6);
  EXPECT_NEAR(end.theta_rad, 5.0 * pi, 1e-5);  // 4·90° + 3·120° + 180°
}

TEST(SimRobot, FirmwareOdometryOfAPerfectRobotMatchesTheTruth) {
  RobotSpec spec = robot_with_errors(1.0, 150.0);
  spec.truth.slip_sigma = 0.0;
  spec.truth.measure_sigma_m = 0.0;
  spec.truth.measure_heading_sigma_rad = 0.0;
  SimulatedRobot robot(spec, 1u);
  const RunOutcome out = robot.run_path(drive::make_umbmark_square(true, 1.0f));
  ASSERT_TRUE(out.completed);
  // Same geometry in firmware and plant: truth and belief differ only by the encoder
  // quantisation (one count = π·60/1440 = 0.13 mm of wheel travel).
  EXPECT_NEAR(out.truth.x_m, static_cast<double>(out.odometry.x_m), 1e-3);
  EXPECT_NEAR(out.truth.y_m, static_cast<double>(out.odometry.y_m), 1e-3);
}

struct BadRobot {
  const char* text;
  const char* key;
};

TEST(RobotFile, RefusesBadRobotsNamingTheKey) {
  const BadRobot cases[] = {
      {R"({"wheel_diameter_mm": 60, "tyre_pressure": 2})", "tyre_pressure"},
      {R"({"true_left_diameter_mm": 0})", "true_left_diameter_mm"},
      {R"({"true_right_diameter_mm": -60})", "true_right_diameter_mm"},
      {R"({"wheel_diameter_mm": -1})", "wheel_diameter_mm"},
      {R"({"true_wheelbase_mm": 50})", "true_wheelbase_mm"},
      {R"({"wheelbase_mm": 40})", "wheelbase_mm"},
      {R"({"counts_per_rev": 1442})", "counts_per_rev"},
      {R"({"slip_sigma": "high"})", "slip_sigma"},
      {R"({"bump_height_mm": 40})", "bump_height_mm"},
  };
  for (const BadRobot& c : cases) {
    RobotSpec spec;
    std::string error;
    EXPECT_FALSE(parse_robot(c.text, "r.json", spec, error)) << c.text;
    EXPECT_NE(error.find(c.key), std::string::npos) << error;
    EXPECT_EQ(error.rfind("r.json", 0), 0u) << error;
  }
  RobotSpec spec;
  std::string error;
  EXPECT_FALSE(parse_robot("{\"wheelbase_mm\": ", "r.json", spec, error));
  EXPECT_FALSE(parse_robot("[1, 2]", "r.json", spec, error));
}

TEST(RobotFile, EveryKeyIsOptionalAndFallsBackToTheDefaultRobot) {
  RobotSpec spec;
  std::string error;
  ASSERT_TRUE(parse_robot("{}", "r.json", spec, error)) << error;
  EXPECT_EQ(spec.truth.left_diameter_m, default_robot().truth.left_diameter_m);
  ASSERT_TRUE(parse_robot(R"({"true_left_diameter_mm": 59.5, "bump_height_mm": 10,
                              "measure_sigma_mm": 1})",
                          "r.json", spec, error))
      << error;
  EXPECT_DOUBLE_EQ(spec.truth.left_diameter_m, 0.0595);
  EXPECT_DOUBLE_EQ(spec.truth.bump_height_m, 0.010);
  EXPECT_DOUBLE_EQ(spec.truth.measure_sigma_m, 0.001);
  EXPECT_EQ(spec.truth.right_diameter_m, default_robot().truth.right_diameter_m);
}

/// Runs a shell command; returns its exit status and stderr.
int run(const std::string& command, std::string& err) {
  const std::string err_file = ::testing::TempDir() + "odocal_sim_err.txt";
  const int status = std::system((command + " >/dev/null 2>" + err_file).c_str());
  std::ifstream in(err_file);
  err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimCommand, BadRobotFileExitsTwoNamingFileAndKey) {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  if (odocal.empty() || !std::ifstream(odocal)) {
    GTEST_SKIP() << "odocal not built";
  }
  const std::string file = ::testing::TempDir() + "bad_robot.json";
  std::ofstream(file) << R"({"true_wheelbase_mm": 30})";
  std::string err;
  EXPECT_EQ(run(odocal + " sim umbmark --robot " + file, err), 2);
  EXPECT_NE(err.find("true_wheelbase_mm"), std::string::npos) << err;
  EXPECT_NE(err.find(file), std::string::npos) << err;
  EXPECT_EQ(run(odocal + " sim validate --robot /nonexistent/robot.json", err), 2);
  EXPECT_NE(err.find("/nonexistent/robot.json"), std::string::npos) << err;
}

}  // namespace
}  // namespace odocal::host

namespace odocal::host {
namespace {

/// Runs odocal-sim with `script` on stdin; returns its stdout.
int run_sim(const std::string& sim, const std::string& args, const std::string& script,
            std::string& output) {
  const std::string in = ::testing::TempDir() + "odocal_sim_in.txt";
  const std::string out = ::testing::TempDir() + "odocal_sim_out.txt";
  std::ofstream(in) << script;
  const int status = std::system((sim + " " + args + " <" + in + " >" + out).c_str());
  std::ifstream o(out);
  output.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimProgram, ScriptedSessionDrivesTheRobotAndKeepsWhatWasSaved) {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string sim = bin != nullptr ? std::string(bin) + "/odocal-sim" : "";
  if (sim.empty() || !std::ifstream(sim)) {
    GTEST_SKIP() << "odocal-sim not built";
  }
  const std::string store = ::testing::TempDir() + "odocal_sim_test.store";
  std::remove(store.c_str());
  std::string out;
  ASSERT_EQ(run_sim(sim, "--speed 0 --store " + store,
                    "odom\nrun line 0.5\nodom\nset c_l 0.998\nsave\n", out),
            0);
  // One reply per line; the run finished before `odom` was read: x is the 0.5 m line
  // (odometry ends the segment within a tick at most of travel, < 1 mm at 0.2 m/s).
  std::istringstream lines(out);
  std::vector<std::string> replies;
  for (std::string l; std::getline(lines, l);) {
    if (!l.empty() && l[0] != '#')
      replies.push_back(l);
  }
  ASSERT_EQ(replies.size(), 5u) << out;
  EXPECT_EQ(replies[1].rfind("ok", 0), 0u);
  double x_mm = 0.0;
  ASSERT_EQ(std::sscanf(replies[2].c_str(), "ok x_mm=%lf", &x_mm), 1) << replies[2];
  EXPECT_NEAR(x_mm, 500.0, 2.0);
  // Restart with the same store: the saved c_l is back.
  ASSERT_EQ(run_sim(sim, "--speed 0 --store " + store, "get c_l\n", out), 0);
  EXPECT_NE(out.find("c_l=0.998"), std::string::npos) << out;
}

}  // namespace
}  // namespace odocal::host
