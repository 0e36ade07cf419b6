#pragma once
/// @file
/// The simulated robot as the host programs use it: the firmware's control loop wired to the
/// hal/sim plant and run by a deterministic event loop. The robot it simulates comes from the
/// robot file (robot_file.hpp).

#include <array>
#include <cstdint>
#include <functional>

#include "odocal/drive/control_loop.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/host/path_geometry.hpp"
#include "odocal/host/robot_file.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/plant.hpp"
#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::host {

/// One wheel's encoder lines wired straight to the firmware's decoder (no hal::EdgeSink between):
/// same levels, same instants, same channel faults as sim::EncoderWiring.
using DecoderWiring = sim::BasicEncoderWiring<drive::QuadratureDecoder&>;

/// One path driven from the origin, as seen by the truth, the firmware and the measurement.
struct RunOutcome {
  sim::WorldPose truth{};       ///< ground truth at the end, m / rad
  sim::WorldPose measured{};    ///< the "absolute" measurement (truth + noise)
  drive::Pose odometry{};       ///< what the firmware believes
  double duration_s = 0.0;      ///< from the start of the path to the end of its last segment
  double left_wheel_rad = 0.0;  ///< encoder rotation of each wheel over the path (firmware view)
  double right_wheel_rad = 0.0;
  bool completed = false;  ///< false: timed out or faulted
};

/// Called with the true pose every `trace_period_ms` while a path runs (for pictures).
using TraceFn = std::function<void(const sim::WorldPose&)>;

/// The firmware's control loop on the simulated plant. Single-threaded and deterministic: the
/// event loop runs the physics to each tick instant (edges reach the decoders at their own
/// instants), then calls ControlLoop::tick.
class SimulatedRobot {
 public:
  /// @param spec the robot; its truth must pass sim::check. @param seed of every random term.
  SimulatedRobot(const RobotSpec& spec, std::uint64_t seed);
  ~SimulatedRobot();

  SimulatedRobot(const SimulatedRobot&) = delete;
  SimulatedRobot& operator=(const SimulatedRobot&) = delete;

  drive::ControlLoop& loop() { return loop_; }
  sim::Plant& plant() { return plant_; }
  [[nodiscard]] const RobotSpec& spec() const { return spec_; }

  /// Replaces the firmware configuration (applied at the next tick). False when invalid.
  [[nodiscard]] bool configure(const drive::DriveConfig& config);

  /// Runs ticks until simulated time reaches `t_ns` (ns since construction).
  void run_until_ns(std::uint64_t t_ns);
  /// Runs exactly one control period.
  void tick_once();
  /// With `on`, each tick's host execution time is reported to the loop (`status` shows it as
  /// tick_us_avg / tick_us_max), as a target's cycle counter would. Off by default: procedures
  /// need no clock reads.
  void measure_tick_time(bool on) { measure_tick_time_ = on; }
  /// Re-reads the firmware's control_hz (after a console `set`) and ticks at that rate.
  void follow_control_rate();
  /// Call after each tick when the console may reset odometry: remembers the true pose at each
  /// reset, so that `measure_in_odometry_frame` can answer in the odometry frame.
  void follow_odometry_frame();
  /// The simulated tape measure: the true pose plus the robot's measurement noise, in the frame
  /// odometry had at its last reset (the world frame before any).
  [[nodiscard]] sim::WorldPose measure_in_odometry_frame();

  /// The robot's wall sensors (issue 48): the layout's four with a maze (RobotSpec::walls), none
  /// without. They look from the plant's true pose put into the maze at the start cell's centre
  /// (where run_path puts the robot down), through the scene's maze, physics and reflectivities;
  /// each draws its noise from a stream of its own derived from the robot's seed, so the plant's
  /// random terms are the same with or without them.
  [[nodiscard]] std::uint32_t wall_sensor_count() const {
    return spec_.walls.present() ? sim::WallSensorLayout::count : 0u;
  }
  /// Sensor `index` (< wall_sensor_count(), in the layout's order: left front, left diagonal,
  /// right diagonal, right front); an index beyond is taken as the last sensor.
  hal::WallSensor& wall_sensor(std::uint32_t index) { return wall_sensors_[sensor_slot(index)]; }
  /// The same sensor as the simulator sees it (its mount, gain, emitter).
  [[nodiscard]] const sim::SimWallSensor& sim_wall_sensor(std::uint32_t index) const {
    return wall_sensors_[sensor_slot(index)];
  }
  /// The maze, physics and reflectivities the sensors read.
  [[nodiscard]] const sim::SensorScene& wall_scene() const { return wall_scene_; }
  /// The robot's true pose in the maze frame, mm and rad.
  [[nodiscard]] sim::MazePose pose_in_maze() const { return plant_in_maze_.pose_in_maze(); }

  /// Simulated time, s.
  [[nodiscard]] double simulated_s() const { return static_cast<double>(plant_.now_ns()) * 1e-9; }

  /// Puts the robot at the origin, resets odometry, drives `path` to its end, lets the wheels
  /// come to rest, and measures. `timeout_s` bounds the simulated time spent.
  RunOutcome run_path(const drive::Path& path, double timeout_s = 600.0, const TraceFn& trace = {},
                      std::uint32_t trace_period_ms = 100u);

 private:
  /// The firmware's motor connector on `side` (0 left, 1 right) as the robot's wiring has it.
  drive::MotorChannel motor_connector(int side);
  /// Line A (`a`) or B of the encoder the firmware's connector on `side` reads.
  sim::EncoderLine& encoder_line(int side, bool a);

  static std::uint32_t sensor_slot(std::uint32_t index) {
    return index < sim::WallSensorLayout::count ? index : sim::WallSensorLayout::count - 1u;
  }
  /// Sensor `index` of the layout, reading the plant in the maze with its own noise stream.
  sim::SimWallSensor make_wall_sensor(std::uint32_t index, std::uint64_t seed) const;

  RobotSpec spec_;
  sim::Plant plant_;
  drive::InvertedOutput reversed_direction_;  ///< the reversed motor's direction line (if any)
  drive::ControlLoop loop_;
  DecoderWiring left_wiring_;
  DecoderWiring right_wiring_;
  std::uint64_t period_ns_ = 1000000u;
  bool measure_tick_time_ = false;
  std::uint64_t next_tick_ns_ = 0u;
  bool fault_pending_ = false;
  std::uint32_t pose_resets_ = 0u;
  sim::WorldPose frame_{};       ///< true pose at the last odometry reset
  sim::SensorScene wall_scene_;  ///< reads spec_.walls.maze (kept here, never moved)
  sim::PlantInMaze plant_in_maze_;
  std::array<sim::SimWallSensor, sim::WallSensorLayout::count> wall_sensors_;
};

}  // namespace odocal::host
