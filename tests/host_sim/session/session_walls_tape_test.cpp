// `--truth walls` where the walls cannot tell the wheels' scale (DESIGN "No tape measure": the
// session says so and asks for the fewest tape readings that can): a maze whose start corridor
// is one cell long, and one whose corridor ends in an open area with no corner to place the
// robot in. The turns in place are still measured by the walls, in the start cell; only the lines
// on an open floor and the verification there take a tape. On --sim (the simulator's tape), and
// through odocal-sim on a pty with a person typing the readings (a slip at the first line's and
// the first verification run's reading, then the right one), and Ctrl-C among the floor's runs.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
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

// The start cell (0, 0) opens north into one cell walled ahead: a corridor of one cell.
constexpr const char* one_cell_maze =
    "+---+---+---+---+\n"
    "|               |\n"
    "+   +   +   +   +\n"
    "|               |\n"
    "+---+   +   +   +\n"
    "|               |\n"
    "+   +---+   +   +\n"
    "| S |           |\n"
    "+---+---+---+---+\n";

// The start cell (1, 0) opens north into a corridor of three cells whose last two stand in an
// open area: no wall to a side where it ends, so a look there cannot place the robot along it.
constexpr const char* open_end_maze =
    "+---+---+---+---+\n"
    "|               |\n"
    "+   +   +   +   +\n"
    "|               |\n"
    "+   +   +   +   +\n"
    "|   |   |       |\n"
    "+   +   +   +   +\n"
    "|   | S |       |\n"
    "+---+---+---+---+\n";

// Mice of this test's own (not the usual one, not the studies'): their true geometry is what the
// factors are judged against. Their wheels are 0.6 % larger and 0.5 % smaller than they are told,
// on the mean: a session that did not take the scale from the tape's lines would miss it by four
// times the tolerance below.
struct TapeMouse {
  double nominal_d_mm, nominal_b_mm, true_left_mm, true_right_mm, true_b_mm;
};
constexpr TapeMouse one_cell_mouse{28.0, 70.0, 28.23, 28.10, 71.1};
constexpr TapeMouse open_end_mouse{34.0, 84.0, 33.76, 33.90, 82.9};

std::string mouse_file(const std::string& name, const TapeMouse& m, const std::string& maze_path,
                       const std::string& extra) {
  // The robot file names its maze from its own folder (both are written in the test's).
  const std::string maze = maze_path.substr(maze_path.rfind('/') + 1);
  char text[512];
  std::snprintf(text, sizeof text,
                R"({"wheel_diameter_mm": %g, "wheelbase_mm": %g, "counts_per_rev": 2048,
                    "true_left_diameter_mm": %g, "true_right_diameter_mm": %g,
                    "true_wheelbase_mm": %g, "wall_sensor_seed": 777, "maze": "%s"%s})",
                m.nominal_d_mm, m.nominal_b_mm, m.true_left_mm, m.true_right_mm, m.true_b_mm,
                maze.c_str(), extra.c_str());
  return write(name, text);
}

// The factors against the truth. The scale comes from the lines' x alone: eight 3 m lines with
// the tape's 2 mm and the slip's spread give it to about 0.03 % (1 sigma): 0.15 % is five sigma.
// The wheels' ratio comes from the lines' lateral offset and heading, which grow with the square
// of the length: 0.1 % leaves it room for the slip. The wheelbase: the walls' heading after 24
// turns in place (0.5 degree off at worst over 8640 degrees) on top of the scale: 0.3 %.
void expect_factors_near(const TapeMouse& m, double c_l, double c_r, double wheelbase_mm) {
  const double true_c_l = m.true_left_mm / m.nominal_d_mm;
  const double true_c_r = m.true_right_mm / m.nominal_d_mm;
  EXPECT_NEAR(c_l / true_c_l, 1.0, 0.0015);
  EXPECT_NEAR(c_r / true_c_r, 1.0, 0.0015);
  EXPECT_NEAR((c_r / c_l) / (true_c_r / true_c_l), 1.0, 0.001);
  EXPECT_NEAR(wheelbase_mm / m.true_b_mm, 1.0, 0.003);
}

std::string whole_report(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// What a session with a tape for the lines leaves in session.json: turns looked at by the walls
// in the start cell first, then runs on the floor, every one of them a tape reading.
void expect_walls_then_tape(const json& doc, std::size_t max_readings) {
  std::size_t turns = 0, floor = 0;
  bool on_floor = false;
  for (const json& run : doc["runs"]) {
    const std::string label = run["label"];
    const bool turn = label == "turns-ccw" || label == "turns-cw";
    on_floor = on_floor || !turn;
    EXPECT_TRUE(turn || label == "line" || label == "verify") << label;
    (on_floor ? floor : turns) += 1;
  }
  EXPECT_EQ(turns, 4u);  // the first round's turns, both ways twice
  EXPECT_GE(floor, 4u);  // two lines at least, two to verify
  EXPECT_EQ(doc["measurements"], floor) << "only the floor's runs are tape readings";
  EXPECT_LE(doc["measurements"].get<std::size_t>(), max_readings);
  EXPECT_EQ(doc["result"]["truth"], "walls");
  EXPECT_EQ(doc["result"]["tape"]["calibration_readings"], floor - 2u);
  EXPECT_NE(doc["result"]["tape"]["why"].get<std::string>().find("the wheels' scale"),
            std::string::npos);
  EXPECT_EQ(doc["result"]["verify"]["stops"].size(), 2u);
  EXPECT_LT(doc["result"]["verify"]["rms_mm"].get<double>(),
            doc["result"]["verify"]["before_rms_mm"].get<double>());
}

TEST(SessionWallsTape, ACorridorWithNoCornerAtItsEndTakesTheTapeForTheLinesOnly) {
  const std::string maze = write("open_end_maze.txt", open_end_maze);
  const std::string robot = mouse_file("open_end_mouse.json", open_end_mouse, maze,
                                       R"(, "maze_start_cell": [1, 0], "measure_sigma_mm": 2)");
  const std::string store = temp("open_end.store");
  const std::string out = temp("open_end_out");
  std::system(("rm -rf " + out + " " + store).c_str());
  const Result r = session("--sim " + robot + " --store " + store +
                           " --seed 11 --procedure auto --truth walls --max-measurements 10 --yes "
                           "--json --out " +
                           out);
  ASSERT_EQ(r.status, 0) << r.err;
  // It says what the walls cannot tell, and why, before anything is asked of the tape.
  const auto said = r.err.find("The walls cannot tell everything here");
  ASSERT_NE(said, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("runs 3 cell(s) and has no side wall at its end"), std::string::npos)
      << r.err;
  EXPECT_LT(said, r.err.find("Take the robot out of the maze to an open floor")) << r.err;
  EXPECT_EQ(r.err.find("leave --truth out"), std::string::npos) << r.err;
  const json doc = json::parse(r.out);
  expect_walls_then_tape(doc, 10u);
  EXPECT_TRUE(doc["saved"].get<bool>());
  // The walls' turns against the simulator's tape: only the looks are in it.
  EXPECT_EQ(doc["result"]["walls"]["against_simulator"]["theta_deg"]["runs"], 4);
  expect_factors_near(open_end_mouse, stored(robot, store, "c_l"), stored(robot, store, "c_r"),
                      stored(robot, store, "wheelbase_mm"));
}

// Through a pty (a port starts in cell (0, 0) facing north): a person presses Enter in the start
// cell, then again on the floor, puts the robot on the mark before each floor run and types what
// the simulator's tape reads there. The first line's reading is typed with x and y swapped and
// the first verification run's in metres: each is shown back and typed again.
TEST(SessionWallsTape, ThroughAPtyThePersonTypesOnlyTheFloorsReadings) {
  const std::string maze = write("one_cell_maze.txt", one_cell_maze);
  const std::string robot =
      mouse_file("one_cell_mouse.json", one_cell_mouse, maze, R"(, "measure_sigma_mm": 2)");
  const std::string store = temp("one_cell.store");
  std::system(("rm -f " + store).c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("one_cell_pty");
  std::system(("rm -rf " + out).c_str());
  Person p({"--port", sim.path(), "--procedure", "auto", "--truth", "walls", "--maze", maze,
            "--max-measurements", "10", "--yes", "--json", "--out", out});
  std::size_t enters = 0, readings = 0;
  bool line_slipped = false, verify_slipped = false;
  const auto deadline = odocal_session_test::PersonClock::now() + std::chrono::minutes(5);
  while (!p.closed()) {
    ASSERT_LT(odocal_session_test::PersonClock::now(), deadline) << p.err;
    if (p.count("press Enter to start") > enters) {
      ++enters;
      p.type("");
    } else if (p.count("Measured stop point") + p.count("Type the reading again") > readings) {
      // A reading asked for, or asked again after the check showed it back.
      ++readings;
      const std::string tape = ask_robot(sim.path(), "measure", "theta_deg");
      const double x = value_of(tape, "x_mm"), y = value_of(tape, "y_mm");
      const double theta = value_of(tape, "theta_deg");
      char text[96];
      const bool verifying = p.err.find(": verify (run") != std::string::npos;
      if (!line_slipped) {
        line_slipped = true;
        std::snprintf(text, sizeof text, "%.1f %.1f %.2f", y, x, theta);
      } else if (verifying && !verify_slipped) {
        verify_slipped = true;
        std::snprintf(text, sizeof text, "%.4f %.4f %.2f", x / 1000.0, y / 1000.0, theta);
      } else {
        std::snprintf(text, sizeof text, "%.1f %.1f %.2f", x, y, theta);
      }
      p.type(text);
    } else {
      static_cast<void>(p.wait_for("press Enter to start", enters + 1, 0.5));
    }
  }
  ASSERT_EQ(p.finish(), 0) << p.err;
  EXPECT_EQ(p.count("press Enter to start"), 2u + 10u) << "start cell twice, each floor run";
  EXPECT_NE(p.err.find("x and y swapped"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("metres for millimetres"), std::string::npos) << p.err;
  EXPECT_TRUE(verify_slipped);
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_TRUE(doc["complete"].get<bool>());
  expect_walls_then_tape(doc, 10u);
  EXPECT_EQ(readings, 10u + 2u) << "ten readings and the two typed again";
  EXPECT_EQ(p.count("Check this reading"), 2u) << "none of the right readings was questioned";
  expect_factors_near(
      one_cell_mouse, value_of(ask_robot(sim.path(), "get c_l", "c_l"), "c_l"),
      value_of(ask_robot(sim.path(), "get c_r", "c_r"), "c_r"),
      value_of(ask_robot(sim.path(), "get wheelbase_mm", "wheelbase_mm"), "wheelbase_mm"));
}

// Ctrl-C with the robot on the floor: at the Enter of the first line's start mark (the robot just
// taken out of the maze), and at the second line's reading. Each time the robot idle, what was
// measured written (the tape readings counted, the report saying what measured what), and no
// --resume offered (a walls session starts anew).
TEST(SessionWallsTape, CtrlCOnTheFloorEndsTheSessionAsEveryWallsSession) {
  const std::string maze = write("one_cell_ctrlc_maze.txt", one_cell_maze);
  const std::string robot =
      mouse_file("one_cell_ctrlc.json", one_cell_mouse, maze, R"(, "measure_sigma_mm": 2)");
  for (const bool at_the_floors_enter : {true, false}) {
    SCOPED_TRACE(at_the_floors_enter ? "Ctrl-C at the floor's Enter" : "Ctrl-C at a reading");
    SimOnPty sim(robot, "");
    ASSERT_FALSE(sim.path().empty());
    const std::string out = temp("one_cell_ctrlc");
    std::system(("rm -rf " + out).c_str());
    Person p({"--port", sim.path(), "--procedure", "auto", "--truth", "walls", "--maze", maze,
              "--out", out});
    // Enter in the start cell, before the self-test and the calibration turn.
    for (std::size_t moment = 1; moment <= 2; ++moment) {
      ASSERT_TRUE(p.wait_for("press Enter to start", moment, 120.0)) << p.err;
      p.type("");
    }
    ASSERT_TRUE(p.wait_for("The tape: the turns in the maze are done", 1, 300.0)) << p.err;
    // The first line's start mark: the Enter that says the robot stands on the floor.
    ASSERT_TRUE(p.wait_for("press Enter to start", 3, 60.0)) << p.err;
    std::size_t readings = 0;
    if (!at_the_floors_enter) {
      p.type("");
      ASSERT_TRUE(p.wait_for("Measured stop point", 1, 120.0)) << p.err;
      const std::string tape = ask_robot(sim.path(), "measure", "theta_deg");
      char first[96];
      std::snprintf(first, sizeof first, "%.1f %.1f %.2f", value_of(tape, "x_mm"),
                    value_of(tape, "y_mm"), value_of(tape, "theta_deg"));
      p.type(first);  // the first line's reading
      readings = 1;
      ASSERT_TRUE(p.wait_for("press Enter to start", 4, 60.0)) << p.err;  // line 2's mark
      p.type("");
      ASSERT_TRUE(p.wait_for("Measured stop point", 2, 120.0)) << p.err;
    }
    p.signal(SIGINT);
    EXPECT_EQ(p.finish(), 130) << p.err;
    EXPECT_NE(p.err.find("interrupted by SIGINT"), std::string::npos) << p.err;
    EXPECT_EQ(p.err.find("--resume"), std::string::npos) << p.err;
    EXPECT_NE(p.err.find("start a new one"), std::string::npos) << p.err;
    EXPECT_NE(ask_robot(sim.path(), "status", "mode").find("mode=idle"), std::string::npos);
    const json doc = read_json(out + "/session.json");
    ASSERT_TRUE(doc.is_object());
    EXPECT_FALSE(doc["complete"].get<bool>());
    EXPECT_EQ(doc["measurements"], readings) << "the lines measured on the floor";
    // The interrupted report says what measured what.
    const std::string report = whole_report(out + "/report.html");
    EXPECT_NE(report.find(readings == 0 ? "measured by the walls, no tape reading"
                                        : "the turns in the maze measured by the walls, 1 tape "
                                          "reading on the floor"),
              std::string::npos);
    EXPECT_NE(report.find("A tape measures the rest"), std::string::npos);
  }
}

// --no-wait starts each run without an Enter, but the robot has to be taken out of the maze before
// the first line: the session waits for the person who types the readings to say it is on the
// floor (without it the robot would drive 3 m into the maze's walls).
TEST(SessionWallsTape, WithNoWaitItStillWaitsForTheRobotToLeaveTheMaze) {
  const std::string maze = write("one_cell_nowait_maze.txt", one_cell_maze);
  const std::string robot = mouse_file("one_cell_nowait.json", one_cell_mouse, maze, "");
  SimOnPty sim(robot, "");
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("one_cell_nowait");
  std::system(("rm -rf " + out).c_str());
  Person p({"--port", sim.path(), "--procedure", "auto", "--truth", "walls", "--maze", maze,
            "--no-wait", "--out", out});
  ASSERT_TRUE(p.wait_for("press Enter when the robot stands on the open floor", 1, 120.0)) << p.err;
  // Nothing moves while it waits (the lockstep robot would have run the line in milliseconds).
  static_cast<void>(p.wait_for("Run 5/", 1, 2.0));
  EXPECT_EQ(p.count("Run 5/"), 0u) << p.err;
  EXPECT_NE(ask_robot(sim.path(), "status", "mode").find("mode=idle"), std::string::npos);
  p.type("");
  EXPECT_TRUE(p.wait_for("Measured stop point", 1, 60.0)) << p.err;
  p.signal(SIGINT);
  EXPECT_EQ(p.finish(), 130) << p.err;
}

}  // namespace
