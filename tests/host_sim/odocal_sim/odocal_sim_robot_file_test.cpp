// odocal-sim driven through its stdio: the robot file's nominal keys are what the firmware is
// told, until the store holds a saved set.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "sim_process.hpp"

namespace {

using odocal::test::sim_program;
using odocal::test::temp_file;

/// Runs odocal-sim with `script` on stdin; `replies` gets the reply lines (not the `#` ones).
int run_sim(const std::string& args, const std::string& script, std::vector<std::string>& replies,
            std::string& output) {
  const std::string in = temp_file("odocal_sim_robot_in.txt", script);
  const std::string out = ::testing::TempDir() + "odocal_sim_robot_out.txt";
  const int status =
      std::system((sim_program() + " --speed 0 " + args + " <" + in + " >" + out).c_str());
  std::ifstream o(out);
  output.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  replies.clear();
  std::istringstream lines(output);
  for (std::string l; std::getline(lines, l);) {
    if (!l.empty() && l[0] != '#') {
      replies.push_back(l);
    }
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The value of `ok name=value`, or NaN.
double value_of(const std::string& reply, const std::string& name) {
  double value = 0.0;
  return std::sscanf(reply.c_str(), ("ok " + name + "=%lf").c_str(), &value) == 1 ? value
                                                                                  : 0.0 / 0.0;
}

const char* const kGetGeometry = "get wheel_diameter_mm\nget wheelbase_mm\nget counts_per_rev\n";

TEST(OdocalSimRobotFile, NominalKeysAreTheFirmwareParametersWhenNothingIsSaved) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  // Values exactly representable in a float, printed by `get` with 6 decimals.
  const std::string robot = temp_file("odocal_sim_robot_a.json",
                                      R"({"wheel_diameter_mm": 72.5, "wheelbase_mm": 201.25,
                                          "counts_per_rev": 2048,
                                          "true_left_diameter_mm": 72.4,
                                          "true_right_diameter_mm": 72.6,
                                          "true_wheelbase_mm": 203})");
  std::vector<std::string> replies;
  std::string out;
  ASSERT_EQ(
      run_sim("--robot " + robot, std::string(kGetGeometry) + "run line 0.5\nodom\n", replies, out),
      0);
  ASSERT_EQ(replies.size(), 5u) << out;
  EXPECT_DOUBLE_EQ(value_of(replies[0], "wheel_diameter_mm"), 72.5) << replies[0];
  EXPECT_DOUBLE_EQ(value_of(replies[1], "wheelbase_mm"), 201.25) << replies[1];
  EXPECT_DOUBLE_EQ(value_of(replies[2], "counts_per_rev"), 2048.0) << replies[2];
  // The robot drives with them: the 0.5 m line ends by odometry within a tick of travel.
  EXPECT_NEAR(value_of(replies[4], "x_mm"), 500.0, 2.0) << replies[4];

  // Without a robot file the firmware keeps its own defaults (60 mm, 150 mm, 1440 counts).
  ASSERT_EQ(run_sim("", kGetGeometry, replies, out), 0);
  ASSERT_EQ(replies.size(), 3u) << out;
  EXPECT_DOUBLE_EQ(value_of(replies[0], "wheel_diameter_mm"), 60.0);
  EXPECT_DOUBLE_EQ(value_of(replies[1], "wheelbase_mm"), 150.0);
  EXPECT_DOUBLE_EQ(value_of(replies[2], "counts_per_rev"), 1440.0);
}

TEST(OdocalSimRobotFile, ASavedParameterSetWinsOverTheRobotFile) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  const std::string store = ::testing::TempDir() + "odocal_sim_robot_file.store";
  std::remove(store.c_str());
  // The real robot must be near what the firmware is told (5 % on the wheels, 10 % on the
  // wheelbase), so each file gives it too.
  const std::string first = temp_file("odocal_sim_robot_b.json",
                                      R"({"wheel_diameter_mm": 80, "wheelbase_mm": 250.5,
                                          "true_left_diameter_mm": 80,
                                          "true_right_diameter_mm": 80.1,
                                          "true_wheelbase_mm": 251})");
  const std::string second = temp_file("odocal_sim_robot_c.json",
                                       R"({"wheel_diameter_mm": 65, "wheelbase_mm": 170,
                                           "true_left_diameter_mm": 65,
                                           "true_right_diameter_mm": 65.1,
                                           "true_wheelbase_mm": 171})");
  std::vector<std::string> replies;
  std::string out;
  // Empty store: the first file's values are in force; the user saves them.
  ASSERT_EQ(
      run_sim("--store " + store + " --robot " + first, "get wheelbase_mm\nsave\n", replies, out),
      0);
  ASSERT_EQ(replies.size(), 2u) << out;
  EXPECT_DOUBLE_EQ(value_of(replies[0], "wheelbase_mm"), 250.5);
  EXPECT_EQ(replies[1].rfind("ok", 0), 0u) << replies[1];
  // Restart with another robot file and the same store: what was saved wins.
  ASSERT_EQ(run_sim("--store " + store + " --robot " + second, kGetGeometry, replies, out), 0);
  ASSERT_EQ(replies.size(), 3u) << out;
  EXPECT_DOUBLE_EQ(value_of(replies[0], "wheel_diameter_mm"), 80.0);
  EXPECT_DOUBLE_EQ(value_of(replies[1], "wheelbase_mm"), 250.5);
  EXPECT_DOUBLE_EQ(value_of(replies[2], "counts_per_rev"), 1440.0);
  // Without a store (parameters in RAM) the second file applies.
  ASSERT_EQ(run_sim("--robot " + second, kGetGeometry, replies, out), 0);
  ASSERT_EQ(replies.size(), 3u) << out;
  EXPECT_DOUBLE_EQ(value_of(replies[0], "wheel_diameter_mm"), 65.0);
  EXPECT_DOUBLE_EQ(value_of(replies[1], "wheelbase_mm"), 170.0);
}

/// Runs odocal-sim with `args` and empty input; returns its exit status, `err` its stderr.
int run_sim_status(const std::string& args, std::string& err) {
  const std::string err_file = ::testing::TempDir() + "odocal_sim_robot_err.txt";
  const int status =
      std::system((sim_program() + " " + args + " </dev/null >/dev/null 2>" + err_file).c_str());
  std::ifstream e(err_file);
  err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimRobotFile, ANumberTooLargeForADoubleExitsTwoNamingFileAndKey) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  const std::string robot =
      temp_file("odocal_sim_robot_big.json", R"({"wheel_diameter_mm":1e400})");
  std::string err;
  EXPECT_EQ(run_sim_status("--robot " + robot, err), 2);
  EXPECT_NE(err.find(robot + ": wheel_diameter_mm: "), std::string::npos) << err;
}

TEST(OdocalSimSpeed, OnlyZeroOrAFiniteDecimalInRangeIsAccepted) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  std::string err;
  for (const char* bad : {"nan", "0x1", "1e-300", "-1", "inf", "2x", "1e400", "0.001", "2e6"}) {
    EXPECT_EQ(run_sim_status(std::string("--speed ") + bad, err), 2) << bad;
    EXPECT_NE(err.find("--speed"), std::string::npos) << bad << ": " << err;
  }
  EXPECT_EQ(run_sim_status("--seed -1", err), 2);
  EXPECT_NE(err.find("--seed"), std::string::npos) << err;
  for (const char* good : {"0", "0.01", "1", "1e6", "250.5"}) {
    EXPECT_EQ(run_sim_status(std::string("--speed ") + good, err), 0) << good << ": " << err;
  }
}

}  // namespace
