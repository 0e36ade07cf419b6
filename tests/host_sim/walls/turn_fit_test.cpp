// calibrate_from_turn on its own: noiseless readings made from its own model (lit = a·cos(φ)^p/d²
// cast into the start cell) give back the pose, the angle per count and the strengths; a turn
// that leaves a sensor too few usable readings is refused, naming the sensor.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "walls_rig.hpp"

namespace odocal::host::walls {
namespace {

using rig::degrees;
using rig::pi;

struct TurnTruth {
  double centre_x_mm = 93.0;
  double centre_y_mm = 87.5;
  double start_heading_rad = pi / 2.0 + 4.0 * degrees;
  double radians_per_count = 0.0025;
  double incidence_power = 1.2;
  std::array<double, sensor_count> a_counts_mm2{5.1e6, 6.8e6, 5.6e6, 7.0e6};
  /// One face or post (RayHit::surface) that reflects `brighter` times what the others do.
  std::uint32_t bright_surface = UINT32_MAX;
  double brighter = 1.0;
};

// 450° counter-clockwise in 0.5° steps, each reading the model's exactly (0 with no face).
std::vector<TurnSample> turn_fit_samples(const sim::Maze& maze, const TurnTruth& truth) {
  const std::array<sim::SensorMount, sensor_count> mounts = usual_mouse_sensors().mounts;
  std::vector<TurnSample> samples;
  for (int j = 0; j <= 900; ++j) {
    const double turned = j * 0.5 * degrees;
    const double heading = truth.start_heading_rad + turned;
    TurnSample sample{turned / truth.radians_per_count, {}};
    for (std::size_t i = 0u; i < sensor_count; ++i) {
      const sim::SensorMount& mount = mounts[i];
      const double x =
          truth.centre_x_mm + std::cos(heading) * mount.x_mm - std::sin(heading) * mount.y_mm;
      const double y =
          truth.centre_y_mm + std::sin(heading) * mount.x_mm + std::cos(heading) * mount.y_mm;
      const sim::RayHit hit = maze.cast(x, y, heading + mount.yaw_rad, 400.0);
      if (hit.kind != sim::SurfaceKind::none) {
        sample.lit_counts[i] = (hit.surface == truth.bright_surface ? truth.brighter : 1.0) *
                               truth.a_counts_mm2[i] *
                               std::pow(std::cos(hit.incidence_rad), truth.incidence_power) /
                               (hit.distance_mm * hit.distance_mm);
      }
    }
    samples.push_back(sample);
  }
  return samples;
}

// A look's turn: the session's 5° steps (every tenth sample of turn_fit_samples).
std::vector<TurnSample> look_samples(const sim::Maze& maze, const TurnTruth& truth) {
  const std::vector<TurnSample> every = turn_fit_samples(maze, truth);
  std::vector<TurnSample> samples;
  for (std::size_t j = 0u; j < every.size(); j += 10u) {
    samples.push_back(every[j]);
  }
  return samples;
}

// The usual mouse's sensors with `truth`'s strengths and incidence power, as a look knows them.
SensorSet known_sensors(const TurnTruth& truth) {
  SensorSet sensors = usual_mouse_sensors();
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    sensors.responses[i] = SensorResponse{truth.a_counts_mm2[i], truth.incidence_power};
  }
  return sensors;
}

TEST(TurnFit, RecoversThePoseAndStrengthsFromNoiselessReadings) {
  const sim::Maze maze = rig::gapped_corridor();
  const TurnTruth truth;
  const std::vector<TurnSample> samples = turn_fit_samples(maze, truth);
  // The owner's rough placing: facing north, the nominal rate 4 % off.
  const TurnSetup setup{0u, 0u, pi / 2.0, truth.radians_per_count * 1.04};
  const TurnCalibration fit =
      calibrate_from_turn(maze, setup, usual_mouse_sensors().mounts, samples);
  // Exact data: only the numerical derivatives' steps (1e-3 mm, 1e-6 rad) and the stopping rule
  // stand between the fit and the truth.
  EXPECT_NEAR(fit.centre_x_mm, truth.centre_x_mm, 1e-3);
  EXPECT_NEAR(fit.centre_y_mm, truth.centre_y_mm, 1e-3);
  EXPECT_NEAR(fit.start_heading_rad, truth.start_heading_rad, 1e-5);
  EXPECT_NEAR(fit.radians_per_count / truth.radians_per_count, 1.0, 1e-6);
  EXPECT_NEAR(fit.sensors.responses[0].incidence_power, truth.incidence_power, 1e-4);
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    EXPECT_NEAR(fit.sensors.responses[i].a_counts_mm2 / truth.a_counts_mm2[i], 1.0, 1e-5) << i;
  }
  EXPECT_LT(fit.rms_log_residual, 1e-6);
  EXPECT_GE(fit.readings_used, 4u * 20u);
}

TEST(TurnFit, RefusesASensorWithTooFewUsableReadings) {
  const sim::Maze maze = rig::gapped_corridor();
  const TurnTruth truth;
  std::vector<TurnSample> samples = turn_fit_samples(maze, truth);
  // The right front sensor dark (below 150 counts) but for 19 samples: one short of 20.
  std::size_t kept = 0u;
  for (TurnSample& sample : samples) {
    if (sample.lit_counts[right_front] >= 150.0 && sample.lit_counts[right_front] < 3800.0 &&
        kept < 19u) {
      ++kept;
    } else {
      sample.lit_counts[right_front] = 40.0;
    }
  }
  const TurnSetup setup{0u, 0u, pi / 2.0, truth.radians_per_count};
  try {
    static_cast<void>(calibrate_from_turn(maze, setup, usual_mouse_sensors().mounts, samples));
    FAIL() << "a sensor with 19 usable readings was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("sensor 3"), std::string::npos) << error.what();
  }
  // Too few samples at all, or no nominal rate: refused before any fitting.
  samples.resize(10u);
  EXPECT_THROW(
      static_cast<void>(calibrate_from_turn(maze, setup, usual_mouse_sensors().mounts, samples)),
      std::invalid_argument);
}

// A robot in the practice maze's corner cell (0, 5), `dx_mm`, `dy_mm` off its centre, facing
// `off_deg` from north.
TurnTruth standing_in_corner(double dx_mm, double dy_mm, double off_deg) {
  TurnTruth truth;
  const sim::MazePose cell = sim::Maze::cell_centre(0u, 5u);
  truth.centre_x_mm = cell.x_mm + dx_mm;
  truth.centre_y_mm = cell.y_mm + dy_mm;
  truth.start_heading_rad = pi / 2.0 + off_deg * degrees;
  return truth;
}

// A look (locate_by_turn): the sensors known, a turn in a corner cell of the practice maze (walls
// north and west only) in the session's 5° steps gives back where the robot stood.
TEST(TurnLook, LocatesTheRobotInACornerCellWithTheSensorsKnown) {
  const sim::Maze maze = sim::practice_maze();
  const TurnTruth truth = standing_in_corner(6.0, -9.0, -3.0);
  const std::vector<TurnSample> samples = look_samples(maze, truth);
  const SensorSet sensors = known_sensors(truth);
  // Thought to stand at the cell's centre, facing north, the rate 2 % off.
  const TurnSetup setup{0u, 5u, pi / 2.0, truth.radians_per_count * 1.02};
  const TurnLocation look = locate_by_turn(maze, setup, sensors, samples);
  EXPECT_NEAR(look.centre_x_mm, truth.centre_x_mm, 1e-3);
  EXPECT_NEAR(look.centre_y_mm, truth.centre_y_mm, 1e-3);
  EXPECT_NEAR(look.start_heading_rad, truth.start_heading_rad, 1e-5);
  EXPECT_NEAR(look.radians_per_count / truth.radians_per_count, 1.0, 1e-6);
  EXPECT_LT(look.rms_log_residual, 1e-6);
  // Thought to be a cell further east, where the walls seen are not: refused.
  const TurnSetup elsewhere{2u, 2u, pi / 2.0, truth.radians_per_count};
  EXPECT_THROW(static_cast<void>(locate_by_turn(maze, elsewhere, sensors, samples)),
               std::invalid_argument);
}

// Walls reflect a little differently (1 ± 5 %): a look fits each face's reflectivity with the
// pose (a prior of that spread), so a brighter wall is not taken for a nearer one. Unfitted, the
// west wall 5 % brighter would look nearer by 1 − 1.05^(−1/2) = 2.4 % of its distance (lit falls
// with d²): up to 2 mm, about 1 mm here where the other walls hold the centre too. Fitted, the
// prior leaves 0.48/(n + 0.48) of it: under 0.1 mm with the tens of readings a wall gets.
TEST(TurnLook, ABrighterWallIsNotTakenForANearerOne) {
  const sim::Maze maze = sim::practice_maze();
  TurnTruth truth = standing_in_corner(4.0, -5.0, -2.0);
  const sim::MazePose cell = sim::Maze::cell_centre(0u, 5u);
  truth.bright_surface = maze.cast(cell.x_mm, cell.y_mm, pi, 400.0).surface;  // the west wall
  truth.brighter = 1.05;
  const std::vector<TurnSample> samples = look_samples(maze, truth);
  const SensorSet sensors = known_sensors(truth);
  TurnSetup setup{0u, 5u, pi / 2.0, truth.radians_per_count};
  setup.fit_rate = false;
  const TurnLocation look = locate_by_turn(maze, setup, sensors, samples);
  EXPECT_NEAR(look.centre_x_mm, truth.centre_x_mm, 0.3);
  EXPECT_NEAR(look.centre_y_mm, truth.centre_y_mm, 0.3);
  EXPECT_NEAR(look.start_heading_rad, truth.start_heading_rad, 0.05 * degrees);
}

}  // namespace
}  // namespace odocal::host::walls
