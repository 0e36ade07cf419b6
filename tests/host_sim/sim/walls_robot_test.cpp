// The maze and the wall sensors in the robot file and the simulated robot (issue 48): the keys'
// defaults and refusals, a mouse put down in the practice maze's start cell reading what the
// sensor scene predicts, and nothing of the motion changed by them.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "odocal/host/robot_file.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {
namespace {

// A mouse: 32 mm wheels, 80 mm wheelbase (112 mm, well inside a corridor's 168 mm).
const std::string mouse_keys = R"("wheel_diameter_mm": 32, "wheelbase_mm": 80)";

RobotSpec parse_ok(const std::string& text) {
  RobotSpec spec;
  std::string error;
  EXPECT_TRUE(parse_robot(text, "r.json", spec, error)) << text << " -> " << error;
  return spec;
}

RobotSpec mouse(const std::string& more = "") {
  return parse_ok("{" + mouse_keys + (more.empty() ? "" : ", " + more) + "}");
}

// One reading through hal::WallSensor::read_lit_counts: two conversions, noise σ√2.
double reading_sigma(const RobotSpec& spec) {
  return spec.walls.physics.noise_sigma_counts * std::numbers::sqrt2;
}

TEST(RobotFileWalls, TheDefaultRobotDoesNotFitAMazeAndHasNone) {
  // 150 mm wheelbase + 60 mm wheels: wider than a corridor's 168 mm.
  const RobotSpec spec = parse_ok("{}");
  EXPECT_FALSE(fits_maze(spec.nominal));
  EXPECT_FALSE(spec.walls.present());
  EXPECT_FALSE(default_robot().walls.present());
  SimulatedRobot robot(spec, 1u);
  EXPECT_EQ(robot.wall_sensor_count(), 0u);
}

TEST(RobotFileWalls, AMouseStandsInThePracticeMazeWithTheUsualFourSensors) {
  const RobotSpec spec = mouse();
  ASSERT_TRUE(spec.walls.present());
  EXPECT_EQ(spec.walls.source, MazeSource::practice);
  EXPECT_EQ(spec.walls.maze, sim::practice_maze());
  EXPECT_EQ(spec.walls.start_column, 0u);
  EXPECT_EQ(spec.walls.start_row, 0u);
  // Facing out of the start cell: north, its only open side.
  EXPECT_EQ(spec.walls.start_heading, sim::Side::north);
  const sim::MazePose start = spec.walls.start_pose();
  EXPECT_DOUBLE_EQ(start.x_mm, 90.0);
  EXPECT_DOUBLE_EQ(start.y_mm, 90.0);
  EXPECT_DOUBLE_EQ(start.theta_rad, 0.5 * std::numbers::pi);
  // The usual mouse's mounts, gains drawn within ±20 % (not all 1), the default physics; the same
  // as usual_mouse_in_practice_maze, which tests and generated mice start from.
  const sim::WallSensorLayout usual;
  int gains_of_one = 0;
  for (std::uint32_t i = 0; i < sim::WallSensorLayout::count; ++i) {
    const sim::WallSensorSpec& sensor = spec.walls.sensors.sensors[i];
    EXPECT_EQ(sensor.mount.x_mm, usual.sensors[i].mount.x_mm);
    EXPECT_EQ(sensor.mount.y_mm, usual.sensors[i].mount.y_mm);
    EXPECT_EQ(sensor.mount.yaw_rad, usual.sensors[i].mount.yaw_rad);
    EXPECT_GE(sensor.gain, 0.8);
    EXPECT_LE(sensor.gain, 1.2);
    gains_of_one += sensor.gain == 1.0 ? 1 : 0;
    EXPECT_EQ(sensor.gain, usual_mouse_in_practice_maze().sensors.sensors[i].gain);
  }
  EXPECT_LT(gains_of_one, 4);
  EXPECT_EQ(spec.walls.physics.k_counts_mm2, sim::SensorPhysics{}.k_counts_mm2);
  SimulatedRobot robot(spec, 1u);
  EXPECT_EQ(robot.wall_sensor_count(), 4u);
}

TEST(RobotFileWalls, EveryKeyIsReadAndTheGainsFollowTheSeed) {
  const RobotSpec spec = mouse(R"("maze_start_cell": [3, 2], "maze_start_heading": "east",
      "wall_sensor_seed": 7, "wall_sensor_layout": [[45, 25, 5], [30, 15, 45], [30, -15, -45],
      [45, -25, -5]], "wall_sensor_k_counts_mm2": 5e6, "wall_sensor_incidence_power": 1.5,
      "wall_sensor_ambient_counts": 200, "wall_sensor_noise_counts": 4,
      "wall_sensor_range_mm": 300, "wall_reflectivity_spread": 0.1)");
  const WallsSpec& w = spec.walls;
  EXPECT_EQ(w.start_column, 3u);
  EXPECT_EQ(w.start_row, 2u);
  EXPECT_EQ(w.start_heading, sim::Side::east);
  EXPECT_EQ(w.seed, 7u);
  EXPECT_DOUBLE_EQ(w.sensors.sensors[1].mount.yaw_rad, 45.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(w.sensors.sensors[3].mount.y_mm, -25.0);
  EXPECT_DOUBLE_EQ(w.physics.k_counts_mm2, 5e6);
  EXPECT_DOUBLE_EQ(w.physics.incidence_power, 1.5);
  EXPECT_DOUBLE_EQ(w.physics.ambient_counts, 200.0);
  EXPECT_DOUBLE_EQ(w.physics.noise_sigma_counts, 4.0);
  EXPECT_DOUBLE_EQ(w.physics.range_mm, 300.0);
  EXPECT_DOUBLE_EQ(w.physics.reflectivity_spread, 0.1);
  // The gains are the seed's draw; another seed draws others; given gains are taken as they are.
  const WallsSpec seven = usual_mouse_in_practice_maze(7u);
  const RobotSpec other = mouse(R"("wall_sensor_seed": 8)");
  for (std::uint32_t i = 0; i < sim::WallSensorLayout::count; ++i) {
    EXPECT_EQ(w.sensors.sensors[i].gain, seven.sensors.sensors[i].gain);
    EXPECT_NE(other.walls.sensors.sensors[i].gain, seven.sensors.sensors[i].gain);
  }
  const RobotSpec given = mouse(R"("wall_sensor_gains": [1, 0.85, 1.1, 1.2])");
  EXPECT_EQ(given.walls.sensors.sensors[1].gain, 0.85);
  EXPECT_EQ(given.walls.sensors.sensors[3].gain, 1.2);
  EXPECT_FALSE(mouse(R"("maze": "none")").walls.present());
}

struct BadWalls {
  const char* keys;  // after the mouse's geometry
  const char* key;   // named in the error
  const char* says;  // part of the why
};

TEST(RobotFileWalls, EveryBadValueIsRefusedNamingItsKeyAndChangesNothing) {
  const BadWalls cases[] = {
      {R"("maze": 3)", "maze", "\"practice\", \"none\""},
      {R"("maze": "")", "maze", "\"practice\", \"none\""},
      {R"("maze": "no_such_maze.txt")", "maze", "no such maze file"},
      {R"("maze_start_cell": [6, 0])", "maze_start_cell", "inside the 6x6 maze"},
      {R"("maze_start_cell": [0.5, 0])", "maze_start_cell", "whole numbers"},
      {R"("maze_start_cell": [0])", "maze_start_cell", "[column, row]"},
      {R"("maze_start_cell": [-1, 0])", "maze_start_cell", "column 0 to 5"},
      {R"("maze_start_heading": "up")", "maze_start_heading", "\"north\""},
      {R"("maze_start_heading": 90)", "maze_start_heading", "\"out\""},
      {R"("wall_sensor_seed": -1)", "wall_sensor_seed", "whole number"},
      {R"("wall_sensor_seed": 1.5)", "wall_sensor_seed", "whole number"},
      {R"("wall_sensor_gains": [1, 1, 1])", "wall_sensor_gains", "four numbers"},
      {R"("wall_sensor_gains": [1, 1, 1, 0])", "wall_sensor_gains", "from 0.1 to 10"},
      {R"("wall_sensor_gains": [1, 1, "1", 1])", "wall_sensor_gains", "four numbers"},
      {R"("wall_sensor_layout": [[40, 30, 0]])", "wall_sensor_layout", "four [x_mm"},
      {R"("wall_sensor_layout": [[40, 30, 0], [35, 20, 50], [35, -20, -50], [90, 0, 0]])",
       "wall_sensor_layout", "sensor 4: "},
      {R"("wall_sensor_layout": [[40, 30, 0], [35, 20, 250], [35, -20, -50], [40, -30, 0]])",
       "wall_sensor_layout", "sensor 2: "},
      {R"("wall_sensor_layout": [[40, 30], [35, 20, 50], [35, -20, -50], [40, -30, 0]])",
       "wall_sensor_layout", "four [x_mm"},
      {R"("wall_sensor_k_counts_mm2": 0)", "wall_sensor_k_counts_mm2", "> 0"},
      {R"("wall_sensor_incidence_power": -1)", "wall_sensor_incidence_power", ">= 0"},
      {R"("wall_sensor_ambient_counts": 5000)", "wall_sensor_ambient_counts", "0 to 4095"},
      {R"("wall_sensor_noise_counts": -2)", "wall_sensor_noise_counts", ">= 0"},
      {R"("wall_sensor_range_mm": "far")", "wall_sensor_range_mm", "> 0"},
      {R"("wall_reflectivity_spread": 0.6)", "wall_reflectivity_spread", "0 to 0.5"},
      // Sensor keys need a maze.
      {R"("maze": "none", "wall_sensor_seed": 3)", "wall_sensor_seed", "\"maze\" is \"none\""},
  };
  for (const BadWalls& c : cases) {
    const std::string text = "{" + mouse_keys + ", " + c.keys + "}";
    RobotSpec spec = default_robot();
    spec.walls.seed = 12345u;
    std::string error;
    EXPECT_FALSE(parse_robot(text, "r.json", spec, error)) << text;
    EXPECT_EQ(error.rfind(std::string("r.json: ") + c.key + ": ", 0), 0u)
        << text << " -> " << error;
    EXPECT_NE(error.find(c.says), std::string::npos) << text << " -> " << error;
    EXPECT_EQ(spec.walls.seed, 12345u) << text;
    EXPECT_FALSE(spec.walls.present()) << text;
  }
}

TEST(RobotFileWalls, ARobotThatDoesNotFitIsRefusedAMazeAndItsSensorKeys) {
  RobotSpec spec;
  std::string error;
  EXPECT_FALSE(parse_robot(R"({"maze": "practice"})", "r.json", spec, error));
  EXPECT_EQ(error.rfind("r.json: maze: the robot does not fit a maze", 0), 0u) << error;
  EXPECT_NE(error.find("210 mm is wider than a corridor's 168 mm"), std::string::npos) << error;
  EXPECT_FALSE(parse_robot(R"({"wall_sensor_gains": [1, 1, 1, 1]})", "r.json", spec, error));
  EXPECT_EQ(error.rfind("r.json: wall_sensor_gains: needs a maze, and this robot has none", 0), 0u)
      << error;
  // The widest robot that fits: 168 mm.
  EXPECT_TRUE(
      parse_robot(R"({"wheel_diameter_mm": 40, "wheelbase_mm": 128})", "r.json", spec, error))
      << error;
  EXPECT_TRUE(spec.walls.present());
  EXPECT_TRUE(
      parse_robot(R"({"wheel_diameter_mm": 40, "wheelbase_mm": 128.5})", "r.json", spec, error))
      << error;
  EXPECT_FALSE(spec.walls.present());
  // A near miss of a maze key says which.
  EXPECT_FALSE(parse_robot("{" + mouse_keys + R"(, "wall_sensor_gain": [1, 1, 1, 1]})", "r.json",
                           spec, error));
  EXPECT_NE(error.find("did you mean \"wall_sensor_gains\""), std::string::npos) << error;
}

/// Writes `text` to `name` in the test's temporary folder; returns its path.
std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(RobotFileWalls, AMazeFileIsReadBesideTheRobotFileAndATypoNamesItsLineAndColumn) {
  // A 3x2 maze: the start cell (0, 0) open to the east only.
  const std::string good =
      "+---+---+---+\n"
      "|           |\n"
      "+---+   +   +\n"
      "| S     |   |\n"
      "+---+---+---+\n";
  write_file("walls_test_maze.txt", good);
  const std::string robot =
      write_file("walls_test_robot.json", "{" + mouse_keys + R"(, "maze": "walls_test_maze.txt"})");
  RobotSpec spec;
  std::string error;
  ASSERT_TRUE(load_robot_file(robot, spec, error)) << error;
  EXPECT_EQ(spec.walls.source, MazeSource::file);
  EXPECT_EQ(spec.walls.maze.width(), 3u);
  EXPECT_EQ(spec.walls.maze.height(), 2u);
  EXPECT_EQ(spec.walls.start_heading, sim::Side::east);  // its first open side
  EXPECT_NE(spec.walls.maze_file.find("walls_test_maze.txt"), std::string::npos);

  // Line 3, column 5: a post expected, '-' found.
  std::string typo = good;
  typo[2u * 14u + 4u] = '-';
  write_file("walls_test_typo.txt", typo);
  const std::string bad = write_file("walls_test_bad_robot.json",
                                     "{" + mouse_keys + R"(, "maze": "walls_test_typo.txt"})");
  RobotSpec kept = default_robot();
  EXPECT_FALSE(load_robot_file(bad, kept, error));
  EXPECT_EQ(error.rfind(bad + ": maze: ", 0), 0u) << error;
  EXPECT_NE(error.find("walls_test_typo.txt: line 3, column 5: "), std::string::npos) << error;
  EXPECT_FALSE(kept.walls.present());
}

TEST(SimulatedRobotWalls, FacingTheStartCellsWallTheFrontSensorsReadWhatTheSceneSays) {
  // Turned west in the start cell: the front sensors, 40 mm ahead of the centre, are 84 − 40 =
  // 44 mm from the west wall's face, square on.
  const RobotSpec spec = mouse(R"("maze_start_heading": "west")");
  SimulatedRobot robot(spec, 3u);
  const sim::MazePose pose = robot.pose_in_maze();
  EXPECT_DOUBLE_EQ(pose.x_mm, 90.0);
  EXPECT_DOUBLE_EQ(pose.theta_rad, std::numbers::pi);
  const double sigma = reading_sigma(spec);
  for (const std::uint32_t i : {0u, 3u}) {
    const sim::WallSensorSpec& sensor = robot.sim_wall_sensor(i).spec();
    const sim::RayHit hit = robot.wall_scene().look(sensor.mount, pose);
    ASSERT_EQ(hit.kind, sim::SurfaceKind::wall);
    EXPECT_NEAR(hit.distance_mm, 44.0, 1e-9);
    const double predicted = robot.wall_scene().lit_counts(sensor, pose);
    // gain · k / d², times the wall's reflectivity within ±5 %.
    EXPECT_NEAR(predicted / (sensor.gain * spec.walls.physics.k_counts_mm2 / (44.0 * 44.0)), 1.0,
                0.05 + 1e-12);
    double sum = 0.0;
    const int reads = 400;
    for (int n = 0; n < reads; ++n) {
      const double lit = robot.wall_sensor(i).read_lit_counts();
      EXPECT_NEAR(lit, predicted, 5.0 * sigma + 1.0);
      sum += lit;
    }
    // The mean of 400 readings within 4 σ/√400 and the ADC's rounding.
    EXPECT_NEAR(sum / reads, predicted, 4.0 * sigma / 20.0 + 0.5) << "sensor " << i;
  }
}

TEST(SimulatedRobotWalls, FacingOutTheFrontSensorsSeeNothingAndTheDiagonalsThePostsAhead) {
  const RobotSpec spec = mouse();
  SimulatedRobot robot(spec, 3u);
  const sim::MazePose pose = robot.pose_in_maze();
  const double sigma = reading_sigma(spec);
  for (std::uint32_t i = 0; i < robot.wall_sensor_count(); ++i) {
    const sim::WallSensorSpec& sensor = robot.sim_wall_sensor(i).spec();
    const double predicted = robot.wall_scene().lit_counts(sensor, pose);
    const bool front = i == 0u || i == 3u;
    // The west corridor runs 984 mm north to its end wall, beyond the 400 mm range.
    if (front) {
      EXPECT_EQ(predicted, 0.0);
    } else {
      // From the cell's centre a diagonal's axis meets the side wall's line at the post ahead
      // (y ≈ 179 mm, the post spans 174-186 mm): what it sees is the post's face.
      EXPECT_EQ(robot.wall_scene().look(sensor.mount, pose).kind, sim::SurfaceKind::post);
      EXPECT_GT(predicted, 100.0);
    }
    for (int n = 0; n < 50; ++n) {
      EXPECT_NEAR(robot.wall_sensor(i).read_lit_counts(), predicted, 5.0 * sigma + 1.0);
    }
  }
}

/// Each sensor's readings, 20 apiece, in turn.
std::vector<int> readings(SimulatedRobot& robot) {
  std::vector<int> out;
  for (std::uint32_t i = 0; i < robot.wall_sensor_count(); ++i) {
    for (int n = 0; n < 20; ++n) {
      out.push_back(robot.wall_sensor(i).read_lit_counts());
    }
  }
  return out;
}

TEST(SimulatedRobotWalls, ReadingsAreTheSameForTheSameSeedAndDifferForAnother) {
  const RobotSpec spec = mouse(R"("maze_start_heading": "west")");
  SimulatedRobot first(spec, 5u);
  SimulatedRobot again(spec, 5u);
  SimulatedRobot other(spec, 6u);
  const std::vector<int> a = readings(first);
  EXPECT_EQ(a.size(), 80u);
  EXPECT_EQ(a, readings(again));
  EXPECT_NE(a, readings(other));
}

/// Drives 0.1 m/s straight for 1 s, waits for rest; returns the true pose.
sim::WorldPose drive_ahead(SimulatedRobot& robot) {
  robot.tick_once();
  EXPECT_TRUE(robot.loop().drive(drive::Twist{0.1f, 0.0f}, 1000u));
  robot.run_until_ns(robot.plant().now_ns() + 2'500'000'000ull);
  return robot.plant().pose();
}

TEST(SimulatedRobotWalls, TheMazeChangesNothingOfTheMotionAndTheSensorsFollowThePlant) {
  SimulatedRobot in_maze(mouse(), 9u);
  SimulatedRobot no_maze(mouse(R"("maze": "none")"), 9u);
  // Sensors read in between: their noise streams are their own.
  static_cast<void>(readings(in_maze));
  const sim::WorldPose a = drive_ahead(in_maze);
  const sim::WorldPose b = drive_ahead(no_maze);
  EXPECT_EQ(a.x_m, b.x_m);
  EXPECT_EQ(a.y_m, b.y_m);
  EXPECT_EQ(a.theta_rad, b.theta_rad);
  // About 100 mm up the west corridor: the plant's x (forward) is the maze's north.
  EXPECT_NEAR(a.x_m, 0.1, 0.02);
  const sim::MazePose pose = in_maze.pose_in_maze();
  EXPECT_NEAR(pose.x_mm, 90.0 - a.y_m * 1000.0, 1e-9);
  EXPECT_NEAR(pose.y_mm, 90.0 + a.x_m * 1000.0, 1e-9);
  EXPECT_NEAR(pose.theta_rad, 0.5 * std::numbers::pi + a.theta_rad, 1e-12);
}

}  // namespace
}  // namespace odocal::host
