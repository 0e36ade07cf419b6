#pragma once
/// @file
/// The robot file (`--robot FILE`) as the host programs read it: what the firmware is told and
/// what the simulated robot really is, checked against the ranges the simulated firmware can run.

#include <cstdint>
#include <string>

#include "odocal/drive/drive_config.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/maze.hpp"
#include "odocal/sim/robot_model.hpp"
#include "odocal/sim/usual_mouse.hpp"
#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::host {

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

/// Where a robot's maze comes from (robot file `maze`).
enum class MazeSource : std::uint8_t { none, practice, file };

/// The maze a robot stands in and its wall sensors (issue 48; docs/simulation.md, "Robot file").
/// With `source` none the robot has no maze and no wall sensor (every robot before issue 48).
struct WallsSpec {
  MazeSource source = MazeSource::none;
  std::string maze_file;  ///< the maze text file as opened (source file), else empty
  sim::Maze maze{};
  std::uint32_t start_column = 0u;  ///< the cell the robot is put down in (at its centre)
  std::uint32_t start_row = 0u;
  sim::Side start_heading = sim::Side::north;  ///< where the robot faces there
  sim::WallSensorLayout sensors{};             ///< mounts and gains
  sim::SensorPhysics physics{};
  std::uint64_t seed = 1u;  ///< the walls' reflectivities (and the gains a file leaves out)

  [[nodiscard]] bool present() const { return source != MazeSource::none; }
  /// Where the plant's world origin lies in the maze: the start cell's centre, facing its heading.
  [[nodiscard]] sim::MazePose start_pose() const;
};

/// The spread of the wall sensors' gains a robot file leaves out: the usual mouse's, 1 ± 20 %.
inline constexpr double default_wall_sensor_gain_spread = sim::usual_wall_sensor_gain_spread;
/// The widest robot put in a maze by default: a corridor's clear width (180 − 12 mm). A robot is
/// taken to be as wide as its wheelbase plus one wheel diameter (tyres, body and clearance).
inline constexpr double maze_clear_width_mm = sim::cell_pitch_mm - sim::wall_thickness_mm;

/// Whether a robot told `nominal` fits the maze's corridors: wheelbase + wheel diameter at most
/// maze_clear_width_mm (the mice, 60-100 mm wheelbase and 24-45 mm wheels, do; the default
/// robot, 150 + 60 mm, does not).
[[nodiscard]] bool fits_maze(const drive::DriveConfig& nominal);

/// The usual mouse in the practice maze: start cell (0, 0) facing north, the usual four sensors
/// with gains drawn in 1 ± 20 % from `seed`, the default physics, reflectivities from `seed`.
[[nodiscard]] WallsSpec usual_mouse_in_practice_maze(std::uint64_t seed = 1u);

/// A robot as `--robot FILE` describes it: what the firmware is told, and what the robot is.
struct RobotSpec {
  drive::DriveConfig nominal{};  ///< wheel_diameter_mm, wheelbase_mm, counts_per_rev (told)
  sim::RobotModel truth{};       ///< the real robot and its floor
  EncoderFaultSpec encoder_fault{};
  WiringFault wiring = WiringFault::ok;
  WallsSpec walls{};  ///< none for the default robot (it does not fit a maze)
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
/// `wiring` (a string: "ok" or a WiringFault's name); and the maze and wall sensors (`maze`,
/// `maze_start_cell`, `maze_start_heading`, `wall_sensor_*`, `wall_reflectivity_spread`: a robot
/// that fits_maze stands in the practice maze unless the file says `"maze": "none"`).
/// @param text the file's content; @param source its name, for messages, and the path a relative
///        `maze` file is taken from (its folder).
/// @param error on failure: "<source>: <key>: <why>" (or the parse position).
/// @return false (and `spec` untouched) for malformed JSON, an unknown or repeated key, a
///         non-number or one a double cannot hold, and any value outside the ranges in which the
///         simulated firmware can run the procedures (docs/simulation.md: e.g. counts_per_rev a
///         multiple of 4 from 100, the true diameters within 5 % of wheel_diameter_mm); the error
///         names the key at fault; a maze file that does not read names its line and column.
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

}  // namespace odocal::host
