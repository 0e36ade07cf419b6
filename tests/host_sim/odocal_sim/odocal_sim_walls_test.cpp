// `walls` through odocal-sim's stdio (issue 48): a mouse in the practice maze reads its four wall
// sensors on its console; a robot without a maze has none.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim_process.hpp"

namespace {

using odocal::test::sim_program;
using odocal::test::temp_file;

/// Runs odocal-sim with `args` on `script`; its reply lines (not the `#` ones).
std::vector<std::string> walls_replies(const std::string& args, const std::string& script) {
  return odocal::test::sim_replies("odocal_sim_walls", args, script);
}

/// The four readings of a `walls` reply, by key (asserting it has exactly those, in order).
std::map<std::string, int> readings(const std::string& reply) {
  const std::vector<std::string> keys = {"left_front", "left_diagonal", "right_diagonal",
                                         "right_front"};
  std::map<std::string, int> values;
  std::istringstream words(reply);
  std::string word;
  words >> word;
  EXPECT_EQ(word, "ok") << reply;
  for (const std::string& key : keys) {
    words >> word;
    EXPECT_EQ(word.substr(0, key.size() + 1), key + "=") << reply;
    values[key] = std::atoi(word.c_str() + key.size() + 1);
  }
  EXPECT_FALSE(words >> word) << reply;
  return values;
}

TEST(OdocalSimWalls, AMouseReadsTheStartCellsWallsThenTheWallItTurnedTo) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  // The usual mouse in the practice maze: the start cell (0, 0), facing north along the west
  // corridor (walled both sides, its north wall 984 mm ahead: beyond the sensors' 400 mm).
  const std::string robot =
      temp_file("odocal_sim_walls_mouse.json", R"({"wheel_diameter_mm": 32, "wheelbase_mm": 80})");
  const auto replies =
      walls_replies("--robot " + robot, "walls\ndrive 0 1.5708 1000\nodom\nwalls\n");
  ASSERT_EQ(replies.size(), 4u);
  const auto start = readings(replies[0]);
  // Nothing ahead: the fronts see noise only (σ 6 counts per conversion, √2 of it lit).
  EXPECT_LT(start.at("left_front"), 40);
  EXPECT_LT(start.at("right_front"), 40);
  // The side walls' faces 84 mm from the centre, seen by the diagonals (mounts 20 mm off the
  // axis, turned 50°) about 84 mm away at 40° incidence: k/d² cos φ ≈ 660 counts, gains 0.8-1.2.
  for (const char* key : {"left_diagonal", "right_diagonal"}) {
    EXPECT_GT(start.at(key), 400) << key;
    EXPECT_LT(start.at(key), 1000) << key;
  }
  // Turned a quarter left in place: facing the west wall, 84 - 40 = 44 mm ahead of the fronts
  // (about 3100 counts at gain 1, by k/d²).
  const auto turned = readings(replies[3]);
  for (const char* key : {"left_front", "right_front"}) {
    EXPECT_GT(turned.at(key), 1500) << key << " " << replies[2];
  }
}

TEST(OdocalSimWalls, ARobotWithoutAMazeHasNoWallSensors) {
  if (sim_program().empty()) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  const std::string robot = temp_file("odocal_sim_walls_none.json", "{}");
  for (const std::string& args : {std::string("--robot ") + robot, std::string()}) {
    const auto replies = walls_replies(args, "walls\n");
    ASSERT_EQ(replies.size(), 1u) << args;
    EXPECT_EQ(replies[0], "err no_sensors this robot has no wall sensors") << args;
  }
}

}  // namespace
