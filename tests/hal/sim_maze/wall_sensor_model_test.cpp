// The simulated wall sensor's physics: inverse square of the distance, cosine of the incidence,
// gain, wall reflectivity, ambient, noise and the 12-bit ADC's limits, through the HAL helper.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::sim {
namespace {

constexpr double sensor_pi = std::numbers::pi;
// The east wall's face in a 1x1 maze, mm.
constexpr double east_face_mm = 180.0 - 6.0;

// A sensor at the robot's centre looking ahead.
WallSensorSpec centred_sensor(double gain = 1.0) {
  return WallSensorSpec{{0.0, 0.0, 0.0}, gain};
}

// The robot facing the east wall of a 1x1 maze from `d` mm, on the cell's centre line.
MazePose facing_east_wall(double d) {
  return MazePose{east_face_mm - d, 90.0, 0.0};
}

SensorPhysics quiet_physics() {
  SensorPhysics physics;
  physics.noise_sigma_counts = 0.0;
  return physics;
}

// The lit reading through the HAL helper, from a fresh sensor.
std::uint16_t lit_at(const SensorScene& scene, const MazePose& pose, const WallSensorSpec& spec,
                     std::uint64_t seed = 1u) {
  const FixedPose source(pose);
  SimWallSensor sensor(scene, source, spec, seed);
  return sensor.read_lit_counts();
}

TEST(WallSensorModel, HalvingTheDistanceGivesFourTimesTheLight) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, quiet_physics(), 7u);
  // 100 mm: 600 counts (k = 6e6), 50 mm: 2400, both below saturation (4095 − 100 ambient).
  const std::uint16_t far = lit_at(scene, facing_east_wall(100.0), centred_sensor());
  const std::uint16_t near = lit_at(scene, facing_east_wall(50.0), centred_sensor());
  // Each helper reading is a rounded total minus an exact ambient: ±0.5 count; ×4 on `far`.
  EXPECT_NEAR(near, 4.0 * far, 4.0 * 0.5 + 0.5);
  // And the level itself: k/d² times the wall's reflectivity.
  const RayHit hit = scene.look(centred_sensor().mount, facing_east_wall(100.0));
  ASSERT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, 100.0, 1e-9);
  EXPECT_NEAR(far, 6.0e6 / (100.0 * 100.0) * scene.reflectivity(hit.surface), 0.5);
}

TEST(WallSensorModel, ObliqueIncidenceScalesByTheCosine) {
  const Maze maze(1u, 1u);
  SensorPhysics physics = quiet_physics();
  const SensorScene scene(maze, physics, 7u);
  // From the cell centre at 20° the east wall is 84 / cos 20° away and seen 20° off its normal.
  const double angle = sensor_pi / 9.0;
  const MazePose pose{90.0, 90.0, angle};
  const double d = 84.0 / std::cos(angle);
  const RayHit hit = scene.look(centred_sensor().mount, pose);
  const double expected = 6.0e6 / (d * d) * std::cos(angle) * scene.reflectivity(hit.surface);
  EXPECT_NEAR(scene.lit_counts(centred_sensor(), pose), expected, 1e-9 * expected);
  EXPECT_NEAR(lit_at(scene, pose, centred_sensor()), expected, 0.5);
  // With p = 2 the cosine counts twice.
  physics.incidence_power = 2.0;
  const SensorScene squared(maze, physics, 7u);
  EXPECT_NEAR(squared.lit_counts(centred_sensor(), pose), expected * std::cos(angle),
              1e-9 * expected);
}

TEST(WallSensorModel, TheMountAndTheRobotPoseBothPlaceTheSensor) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, quiet_physics(), 7u);
  // Robot at the centre facing north; a sensor 30 mm ahead and 20 mm to the right, turned 90° to
  // the right, looks east from (110, 120): the east face is 64 mm away.
  const SensorMount mount{30.0, -20.0, -sensor_pi / 2.0};
  const RayHit hit = scene.look(mount, Maze::cell_centre(0u, 0u, sensor_pi / 2.0));
  EXPECT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, east_face_mm - 110.0, 1e-9);
  EXPECT_NEAR(hit.incidence_rad, 0.0, 1e-9);
}

TEST(WallSensorModel, TheHelperTakesTheAmbientAway) {
  const Maze maze(1u, 1u);
  SensorPhysics dim = quiet_physics();
  dim.ambient_counts = 50.0;
  SensorPhysics bright = quiet_physics();
  bright.ambient_counts = 800.0;
  const SensorScene dim_scene(maze, dim, 7u);
  const SensorScene bright_scene(maze, bright, 7u);
  const MazePose pose = facing_east_wall(80.0);
  EXPECT_EQ(lit_at(dim_scene, pose, centred_sensor()),
            lit_at(bright_scene, pose, centred_sensor()));
  // The raw reading with the emitter off is the ambient.
  const FixedPose source(pose);
  SimWallSensor sensor(bright_scene, source, centred_sensor(), 1u);
  sensor.set_emitter(false);
  EXPECT_EQ(sensor.read_counts(), 800u);
  EXPECT_EQ(sensor.settle_us(), SimWallSensor::default_settle_us);
  static_cast<void>(sensor.read_lit_counts());
  EXPECT_EQ(sensor.settles(), 1u);
  EXPECT_FALSE(sensor.emitter_on());
}

TEST(WallSensorModel, GainScalesTheLight) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, quiet_physics(), 7u);
  const MazePose pose = facing_east_wall(90.0);
  const std::uint16_t low = lit_at(scene, pose, centred_sensor(0.8));
  const std::uint16_t high = lit_at(scene, pose, centred_sensor(1.2));
  // About 590 and 890 counts, each ±0.5 from rounding.
  EXPECT_NEAR(high, 1.5 * low, 1.5 * 0.5 + 0.5);
}

TEST(WallSensorModel, SaturatesAtFullScaleAndStaysAboveZero) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, quiet_physics(), 7u);
  // 10 mm from the wall: 60000 counts of light, far beyond the ADC.
  const FixedPose source(facing_east_wall(10.0));
  SimWallSensor sensor(scene, source, centred_sensor(), 1u);
  sensor.set_emitter(true);
  EXPECT_EQ(sensor.read_counts(), hal::WallSensor::full_scale_counts);
  EXPECT_EQ(sensor.read_lit_counts(), hal::WallSensor::full_scale_counts - 100u);
  // No ambient and much noise: about half the dark readings would be negative; they read 0.
  SensorPhysics noisy;
  noisy.ambient_counts = 0.0;
  noisy.noise_sigma_counts = 20.0;
  const SensorScene dark(maze, noisy, 7u);
  SimWallSensor dark_sensor(dark, source, centred_sensor(), 3u);
  dark_sensor.set_emitter(false);
  constexpr int n = 4000;
  int zeros = 0;
  for (int i = 0; i < n; ++i) {
    zeros += dark_sensor.read_counts() == 0u ? 1 : 0;
  }
  // P(N(0, 20) < 0.5) = Φ(0.025) = 0.510; its sampling error is 0.5/√n = 0.008: 5 of them.
  EXPECT_NEAR(zeros / static_cast<double>(n), 0.510, 5.0 * 0.5 / std::sqrt(n));
}

TEST(WallSensorModel, BeyondItsRangeASensorReadsAmbientAndNoise) {
  const Maze maze(3u, 1u);
  const SensorScene scene(maze, SensorPhysics{}, 7u);
  // 444 mm to the far wall, range 400 mm.
  const FixedPose source(Maze::cell_centre(0u, 0u, 0.0));
  SimWallSensor sensor(scene, source, centred_sensor(), 5u);
  EXPECT_EQ(scene.lit_counts(centred_sensor(), source.pose_in_maze()), 0.0);
  sensor.set_emitter(true);
  constexpr int n = 4000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    sum += sensor.read_counts();
  }
  // Mean 100 counts, σ = 6 per reading (rounding adds 1/12 count² of variance).
  EXPECT_NEAR(sum / n, 100.0, 5.0 * std::sqrt(36.0 + 1.0 / 12.0) / std::sqrt(n));
}

TEST(WallSensorModel, NoiseAcrossSeedsHasTheConfiguredSigma) {
  const Maze maze(1u, 1u);
  const SensorPhysics physics;  // σ = 6 counts per conversion
  const SensorScene scene(maze, physics, 7u);
  const MazePose pose = facing_east_wall(100.0);
  const RayHit hit = scene.look(centred_sensor().mount, pose);
  const double light = 6.0e6 / 1.0e4 * scene.reflectivity(hit.surface);
  constexpr int n = 3000;
  double sum = 0.0;
  double sum2 = 0.0;
  for (int seed = 1; seed <= n; ++seed) {
    const double lit = lit_at(scene, pose, centred_sensor(), static_cast<std::uint64_t>(seed));
    sum += lit;
    sum2 += lit * lit;
  }
  const double mean = sum / n;
  const double sd = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  // The helper's difference of two conversions: variance 2σ² plus two roundings' 1/12 each.
  const double expected_sd = std::sqrt(2.0 * 36.0 + 2.0 / 12.0);
  EXPECT_NEAR(mean, light, 5.0 * expected_sd / std::sqrt(n));
  // The sample sd's relative standard error is 1/√(2(n−1)): 5 of them.
  EXPECT_NEAR(sd, expected_sd, 5.0 * expected_sd / std::sqrt(2.0 * (n - 1)));
}

TEST(WallSensorModel, TheSameSeedGivesTheSameReadings) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, SensorPhysics{}, 7u);
  const FixedPose source(facing_east_wall(60.0));
  SimWallSensor a(scene, source, centred_sensor(), 11u);
  SimWallSensor b(scene, source, centred_sensor(), 11u);
  SimWallSensor c(scene, source, centred_sensor(), 12u);
  int differ = 0;
  for (int i = 0; i < 50; ++i) {
    const std::uint16_t from_a = a.read_lit_counts();
    EXPECT_EQ(from_a, b.read_lit_counts());
    differ += from_a != c.read_lit_counts() ? 1 : 0;
  }
  EXPECT_GT(differ, 25);
}

TEST(WallSensorModel, WallsReflectWithinTheSpreadAndEachTheSame) {
  const Maze maze(1u, 1u);
  const SensorScene scene(maze, SensorPhysics{}, 7u);
  const SensorScene other(maze, SensorPhysics{}, 8u);
  double lowest = 2.0;
  double highest = 0.0;
  int differ = 0;
  for (std::uint32_t surface = 0u; surface < 500u; ++surface) {
    const double r = scene.reflectivity(surface);
    EXPECT_GE(r, 0.95);
    EXPECT_LE(r, 1.05);
    EXPECT_EQ(r, scene.reflectivity(surface));
    lowest = r < lowest ? r : lowest;
    highest = r > highest ? r : highest;
    differ += r != other.reflectivity(surface) ? 1 : 0;
  }
  // Uniform over ±5 %: 500 draws all above 0.96 or all below 1.04 would have probability 0.8^500.
  EXPECT_LT(lowest, 0.96);
  EXPECT_GT(highest, 1.04);
  EXPECT_EQ(differ, 500);
}

TEST(WallSensorModel, TheUsualMouseLooksAheadAndDiagonally) {
  const WallSensorLayout layout;
  const WallSensorSpec& left_front = layout.at(SensorPlace::left_front);
  const WallSensorSpec& right_front = layout.at(SensorPlace::right_front);
  EXPECT_EQ(left_front.mount.yaw_rad, 0.0);
  EXPECT_EQ(right_front.mount.yaw_rad, 0.0);
  EXPECT_GT(left_front.mount.y_mm, 0.0);
  EXPECT_LT(right_front.mount.y_mm, 0.0);
  const double left_diagonal = layout.at(SensorPlace::left_diagonal).mount.yaw_rad;
  const double right_diagonal = layout.at(SensorPlace::right_diagonal).mount.yaw_rad;
  EXPECT_GE(left_diagonal, sensor_pi / 4.0);
  EXPECT_LE(left_diagonal, sensor_pi / 3.0);
  EXPECT_EQ(right_diagonal, -left_diagonal);
  for (const WallSensorSpec& spec : layout.sensors) {
    EXPECT_EQ(check(spec), SensorModelError::none);
    EXPECT_GT(spec.mount.x_mm, 0.0);
  }
  EXPECT_EQ(check(SensorPhysics{}), SensorModelError::none);
  // Drawn gains: within ±20 %, the mounts kept, the same for a seed.
  const WallSensorLayout drawn = with_random_gains(layout, 0.2, 5u);
  for (std::uint32_t i = 0u; i < WallSensorLayout::count; ++i) {
    EXPECT_GE(drawn.sensors[i].gain, 0.8);
    EXPECT_LE(drawn.sensors[i].gain, 1.2);
    EXPECT_EQ(drawn.sensors[i].mount.yaw_rad, layout.sensors[i].mount.yaw_rad);
    EXPECT_EQ(drawn.sensors[i].gain, with_random_gains(layout, 0.2, 5u).sensors[i].gain);
  }
}

TEST(WallSensorModel, ChecksRefuseImpossibleValues) {
  SensorPhysics physics;
  physics.k_counts_mm2 = 0.0;
  EXPECT_EQ(check(physics), SensorModelError::k);
  physics = SensorPhysics{};
  physics.ambient_counts = 5000.0;
  EXPECT_EQ(check(physics), SensorModelError::ambient);
  physics = SensorPhysics{};
  physics.noise_sigma_counts = -1.0;
  EXPECT_EQ(check(physics), SensorModelError::noise);
  physics = SensorPhysics{};
  physics.reflectivity_spread = 0.6;
  EXPECT_EQ(check(physics), SensorModelError::reflectivity);
  EXPECT_EQ(check(centred_sensor(0.0)), SensorModelError::gain);
  EXPECT_EQ(check(WallSensorSpec{{NAN, 0.0, 0.0}, 1.0}), SensorModelError::mount);
}

TEST(WallSensorModel, ThePlantsPoseIsPutIntoTheMaze) {
  Plant plant(RobotModel{}, 1u);
  ASSERT_TRUE(plant.ok());
  plant.place(WorldPose{0.1, 0.02, 0.1});  // metres
  // The plant's origin at the start cell's centre, facing north.
  const PlantInMaze source(plant, Maze::cell_centre(0u, 0u, sensor_pi / 2.0));
  const MazePose pose = source.pose_in_maze();
  // Forward (world x) is maze north, world left (y) is maze west.
  EXPECT_NEAR(pose.x_mm, 90.0 - 20.0, 1e-9);
  EXPECT_NEAR(pose.y_mm, 90.0 + 100.0, 1e-9);
  EXPECT_NEAR(pose.theta_rad, sensor_pi / 2.0 + 0.1, 1e-12);
}

}  // namespace
}  // namespace odocal::sim
