#pragma once
/// @file
/// The simulated robot as the host programs use it: the robot file, and the firmware's control
/// loop wired to the hal/sim plant and run by a deterministic event loop.

#include <cstdint>
#include <functional>
#include <string>

#include "odocal/drive/control_loop.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/plant.hpp"

namespace odocal::host {

/// One wheel's encoder lines wired straight to the firmware's decoder (no hal::EdgeSink between):
/// same levels, same instants, same channel faults as sim::EncoderWiring.
using DecoderWiring = sim::BasicEncoderWiring<drive::QuadratureDecoder&>;

/// An encoder that fails (robot file `encoder_fault`, `encoder_fault_after_s`).
struct EncoderFaultSpec {
  int wheel = -1;  ///< 0 left, 1 right, -1 none
  sim::ChannelFault fault = sim::ChannelFault::none;
  double after_s = 0.0;  ///< simulated time at which it starts
};

/// One wiring mistake of the robot (robot file `wiring`, DESIGN "Wiring self-test"): a motor's
/// leads reversed, an encoder's A and B lines exchanged, the two encoders' or the two motors'
/// connectors exchanged between the sides.
enum class WiringFault : std::uint8_t {
  ok,
  left_motor_reversed,
  right_motor_reversed,
  left_encoder_reversed,
  right_encoder_reversed,
  encoders_swapped,
  motors_swapped,
};

/// Robot-file spelling of a wiring fault ("left_motor_reversed", "ok").
[[nodiscard]] const char* to_string(WiringFault fault);

/// A robot as `--robot FILE` describes it: what the firmware is told, and what the robot is.
struct RobotSpec {
  drive::DriveConfig nominal{};  ///< wheel_diameter_mm, wheelbase_mm, counts_per_rev (told)
  sim::RobotModel truth{};       ///< the real robot and its floor
  EncoderFaultSpec encoder_fault{};
  WiringFault wiring = WiringFault::ok;
};

/// The default simulated robot: nominal D 60 mm, b 150 mm, 1440 counts/rev; true D_L 59.91 mm,
/// D_R 60.03 mm (E_d = 1.002), b 151.5 mm (1 % longer), slip and measurement noise, smooth floor.
[[nodiscard]] RobotSpec default_robot();

/// Reads a flat JSON robot object (DESIGN "Host program odocal", `--robot FILE`): every key is
/// optional and falls back to `default_robot()`. Keys: wheel_diameter_mm, wheelbase_mm,
/// counts_per_rev, true_left_diameter_mm, true_right_diameter_mm, true_wheelbase_mm, slip_sigma,
/// bump_height_mm, bump_spacing_mm, measure_sigma_mm, and `encoder_fault` (a string: "none",
/// "left_dead", "right_dead", "left_noisy", "right_noisy": channel A of that wheel's encoder stuck,
/// or glitching at every 5th B edge) with `encoder_fault_after_s` (when it starts, s), and
/// `wiring` (a string: "ok" or a WiringFault's name).
/// @param text the file's content; @param source its name, for messages.
/// @param error on failure: "<source>: <key>: <why>" (or the parse position).
/// @return false (and `spec` untouched) for malformed JSON, an unknown or repeated key, a
///         non-number or one a double cannot hold, and any value outside the ranges in which the
///         simulated firmware can run the procedures (docs/simulation.md: e.g. counts_per_rev a
///         multiple of 4 from 100, the true diameters within 5 % of wheel_diameter_mm); the error
///         names the key at fault.
[[nodiscard]] bool parse_robot(const std::string& text, const std::string& source, RobotSpec& spec,
                               std::string& error);

/// Reads and parses a robot file; false with "<path>: cannot read" when it cannot be opened.
[[nodiscard]] bool load_robot_file(const std::string& path, RobotSpec& spec, std::string& error);

/// The truth as the UMBmark figures see it: E_d = D_R/D_L and the wheelbase factor that makes the
/// nominal odometry turn right, E_b = (b_true/b_nominal)·(D_nominal/D_true,mean).
struct TrueErrors {
  double e_d = 1.0;
  double e_b = 1.0;
};
[[nodiscard]] TrueErrors true_errors(const RobotSpec& spec);

/// A point of a driven path, m (world frame = start frame).
struct PathPoint {
  double x_m = 0.0;
  double y_m = 0.0;
};

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
  sim::WorldPose frame_{};  ///< true pose at the last odometry reset
};

}  // namespace odocal::host
