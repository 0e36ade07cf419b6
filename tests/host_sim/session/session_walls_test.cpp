// `odocal session --procedure auto --truth walls` (DESIGN "No tape measure"): a mouse in its maze
// calibrated with no tape reading, on --sim and through odocal-sim on a pty as a person runs it
// (Enter once, nothing typed after), the geometry it saves against the simulated mouse's truth,
// the walls' own error against the simulator's tape, Ctrl-C in the middle of a look, and what
// the flags refuse. How close the unseen path comes to the oracle over generated mice:
// walls_study.py (a benchmark).

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <string>

#include <nlohmann/json.hpp>

#include "session_harness.hpp"
#include "session_person.hpp"

namespace {

using nlohmann::json;
using odocal_session_test::ask_robot;
using odocal_session_test::Person;
using odocal_session_test::read_json;
using odocal_session_test::Result;
using odocal_session_test::session;
using odocal_session_test::SimOnPty;
using odocal_session_test::stored;
using odocal_session_test::temp;
using odocal_session_test::value_of;
using odocal_session_test::write;

// A mouse of the test's own (not the usual one `{}` stands for): 38 mm wheels, 88 mm wheelbase,
// the right wheel 0.4 % larger than the left, the wheelbase 1.5 % longer than told; its sensors'
// gains drawn from a seed of its own, the simulator's tape exact (to judge the walls against).
constexpr const char* walls_mouse =
    R"({"wheel_diameter_mm": 38, "wheelbase_mm": 88, "counts_per_rev": 1024,
        "true_left_diameter_mm": 37.94, "true_right_diameter_mm": 38.09,
        "true_wheelbase_mm": 89.32, "wall_sensor_seed": 4242, "measure_sigma_mm": 0})";

// What the walls' stops may be off against the simulator's exact tape, as RMS over the session's
// runs: they stand in for a tape (±2 mm, ±0.4°); a stop up to 2.5 times as rough still carries
// the calibration (docs/maze.md, "The walls' own error").
constexpr double kStopRmsMm = 5.0;
constexpr double kStopRmsDeg = 1.0;

// The factors a walls session leaves, against the truth: the scale to 0.3 % (each end cell's
// walls reflect a few per cent differently: about 1 mm over the 0.9 m corridor, three times),
// the wheels' ratio to 0.06 % (2 mm of lateral error over 0.9 m bends it 0.04 % on this mouse),
// the wheelbase to 0.3 % (it comes with the scale).
void expect_near_truth(double c_l, double c_r, double wheelbase_mm) {
  const double true_c_l = 37.94 / 38.0;
  const double true_c_r = 38.09 / 38.0;
  EXPECT_NEAR(c_l / true_c_l, 1.0, 0.003);
  EXPECT_NEAR(c_r / true_c_r, 1.0, 0.003);
  EXPECT_NEAR((c_r / c_l) / (true_c_r / true_c_l), 1.0, 0.0006);
  EXPECT_NEAR(wheelbase_mm / 89.32, 1.0, 0.003);
}

TEST(SessionWalls, AMouseInThePracticeMazeCalibratesWithNoTapeReading) {
  const std::string robot = write("walls_mouse.json", walls_mouse);
  const std::string store = temp("walls_mouse.store");
  const std::string out = temp("walls_sim");
  std::system(("rm -rf " + out + " " + store).c_str());
  const Result r = session("--sim " + robot + " --store " + store +
                           " --seed 5 --procedure auto --truth walls --yes --json --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  EXPECT_EQ(doc["measurements"], 0);
  EXPECT_EQ(doc["result"]["truth"], "walls");
  EXPECT_TRUE(doc["saved"].get<bool>());
  EXPECT_EQ(r.err.find("Measured stop point"), std::string::npos) << "a tape reading was asked";
  // The runs a maze allows: lines along the start corridor, turns in place, the verification.
  for (const json& run : doc["runs"]) {
    const std::string label = run["label"];
    EXPECT_TRUE(label == "line" || label == "turns-ccw" || label == "turns-cw" || label == "verify")
        << label;
  }
  // The sensors learnt: four strengths, none typed.
  const json& walls = doc["result"]["walls"];
  ASSERT_EQ(walls["calibration"]["sensors"].size(), 4u);
  // The walls' stops against the simulator's exact tape.
  const json& against = walls["against_simulator"];
  EXPECT_EQ(against["x_mm"]["runs"], doc["runs"].size());
  EXPECT_LT(against["x_mm"]["rms"].get<double>(), kStopRmsMm);
  EXPECT_LT(against["y_mm"]["rms"].get<double>(), kStopRmsMm);
  EXPECT_LT(against["theta_deg"]["rms"].get<double>(), kStopRmsDeg);
  // The verification is judged by the walls, and the factors beat the nominal ones there.
  const json& verify = doc["result"]["verify"];
  EXPECT_EQ(verify["judged_by"], "walls");
  EXPECT_EQ(verify["stops"].size(), 2u);
  EXPECT_LT(verify["rms_mm"].get<double>(), verify["before_rms_mm"].get<double>());
  // What the store holds after a restart.
  expect_near_truth(stored(robot, store, "c_l"), stored(robot, store, "c_r"),
                    stored(robot, store, "wheelbase_mm"));
}

TEST(SessionWalls, EmptyRobotFileIsTheUsualMouseInThePracticeMaze) {
  const std::string robot = write("walls_empty.json", "{}");
  const std::string out = temp("walls_empty");
  std::system(("rm -rf " + out).c_str());
  const Result r =
      session("--sim " + robot + " --procedure auto --truth walls --json --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  EXPECT_EQ(doc["measurements"], 0);
  EXPECT_EQ(doc["result"]["truth"], "walls");
  // Without a terminal and without --yes nothing is saved.
  EXPECT_FALSE(doc["saved"].get<bool>());
  EXPECT_NE(r.err.find("the practice maze"), std::string::npos) << r.err;
  // The robot file odocal-sim ran: the usual mouse's size, the rest as given.
  const json derived = read_json(out + "/robot.json");
  EXPECT_EQ(derived["wheel_diameter_mm"], 32.0);
  EXPECT_EQ(derived["wheelbase_mm"], 76.0);
}

TEST(SessionWalls, ThroughAPtyAsAPersonRunsIt) {
  const std::string robot = write("walls_pty_mouse.json", walls_mouse);
  const std::string store = temp("walls_pty.store");
  std::system(("rm -f " + store).c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("walls_pty");
  std::system(("rm -rf " + out).c_str());
  Person p({"--port", sim.path(), "--procedure", "auto", "--truth", "walls", "--yes", "--json",
            "--out", out});
  // Enter before the self-test and before the calibration turn: nothing else is asked.
  for (std::size_t moment = 1; moment <= 2; ++moment) {
    ASSERT_TRUE(p.wait_for("press Enter to start", moment)) << p.err;
    p.type("");
  }
  ASSERT_EQ(p.finish(), 0) << p.err;
  EXPECT_EQ(p.count("press Enter to start"), 2u) << p.err;
  EXPECT_EQ(p.err.find("Measured stop point"), std::string::npos) << p.err;
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_TRUE(doc["complete"].get<bool>());
  EXPECT_EQ(doc["measurements"], 0);
  EXPECT_EQ(doc["result"]["truth"], "walls");
  // On a port the robot's `measure` is not asked: nothing against a simulator.
  EXPECT_FALSE(doc["result"]["walls"].contains("against_simulator"));
  expect_near_truth(
      value_of(ask_robot(sim.path(), "get c_l", "c_l"), "c_l"),
      value_of(ask_robot(sim.path(), "get c_r", "c_r"), "c_r"),
      value_of(ask_robot(sim.path(), "get wheelbase_mm", "wheelbase_mm"), "wheelbase_mm"));
}

TEST(SessionWalls, CtrlCInALookStopsTheRobotAndPutsBackWhatItChanged) {
  const std::string robot = write("walls_ctrlc_mouse.json", walls_mouse);
  SimOnPty sim(robot, "", "1");  // real time: a look takes seconds
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("walls_ctrlc");
  std::system(("rm -rf " + out).c_str());
  Person p(
      {"--port", sim.path(), "--procedure", "auto", "--truth", "walls", "--no-wait", "--out", out});
  ASSERT_TRUE(p.wait_for("The walls: the robot learns its sensors", 1, 120.0)) << p.err;
  p.signal(SIGINT);
  EXPECT_EQ(p.finish(), 130) << p.err;
  EXPECT_NE(p.err.find("interrupted by SIGINT"), std::string::npos) << p.err;
  // A walls session is not resumed (--resume refuses it): the way out does not offer it.
  EXPECT_EQ(p.err.find("--resume"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("start a new one"), std::string::npos) << p.err;
  EXPECT_NE(ask_robot(sim.path(), "status", "mode").find("mode=idle"), std::string::npos);
  EXPECT_DOUBLE_EQ(value_of(ask_robot(sim.path(), "get c_l", "c_l"), "c_l"), 1.0);
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_FALSE(doc["complete"].get<bool>());
}

TEST(SessionWalls, FlagsItRefusesNameWhatIsWrongAndRunNothing) {
  const std::string mouse = write("walls_refuse_mouse.json", walls_mouse);
  const std::string wide = write("walls_wide.json", R"({"wheel_diameter_mm": 60,
      "wheelbase_mm": 150})");
  const std::string csv = write("walls_refuse.csv", "x_mm,y_mm\n1,2\n");
  const std::string bad_maze = write("walls_bad_maze.txt", "+---+\n| S |\n+-x-+\n");
  struct Case {
    std::string args;
    std::string says;
  };
  const Case cases[] = {
      {"--sim " + mouse + " --procedure fit --truth walls", "only with --procedure auto"},
      {"--sim " + mouse + " --procedure auto --truth walls --measurements " + csv,
       "takes no tape reading"},
      {"--port /dev/null --procedure auto --maze practice", "only with --truth walls"},
      {"--sim " + wide + " --procedure auto --truth walls", "stands in no maze"},
      {"--sim " + mouse + " --procedure auto --truth paper", "--truth"},
      {"--port /dev/null --procedure auto --truth walls --maze " + bad_maze, "--maze: line 3"},
      {"--sim " + mouse + " --procedure auto --truth walls --protocol ros-arduino-bridge",
       "ROSArduinoBridge has no such command"},
  };
  for (const Case& c : cases) {
    const std::string out = temp("walls_refused");
    std::system(("rm -rf " + out).c_str());
    const Result r = session(c.args + " --out " + out);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(odocal_session_test::exists(out + "/session.json")) << c.args;
  }
}

}  // namespace
