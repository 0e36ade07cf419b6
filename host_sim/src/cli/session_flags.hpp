#pragma once
// `odocal session`'s flags checked against each other (session_flags.cpp): the procedure, --runs,
// and --protocol ros-arduino-bridge with the robot's nominal geometry.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/bridge_console.hpp"
#include "odocal/host/ros2_yaml.hpp"
#include "odocal/host/session.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace odocal::host {

/// --procedure NAME (or session.json's "procedure" on --resume); an unknown name throws
/// InputError naming the procedures there are.
[[nodiscard]] Procedure procedure_of(const std::string& name,
                                     const std::string& where = "--procedure",
                                     const std::string& key = "");

/// The names --procedure accepts, from `procedures` (session.hpp).
[[nodiscard]] std::vector<std::string> procedure_words();

/// --runs within the procedure's bounds (`procedures`, session.hpp). Throws InputError.
void check_runs(Procedure procedure, std::uint64_t runs);

inline constexpr const char* kBridgeProtocol = "ros-arduino-bridge";

/// --max-measurements' default for a ROSArduinoBridge robot (docs/ros.md, "The budget"): its
/// own loop leaves tens of millimetres of tracking error on the unseen path, so precision past
/// what 12 measurements give (the geometry to a few hundredths of a per cent on robots that
/// scatter little) shows nowhere; the tape time is better saved.
inline constexpr std::size_t kBridgeMaxMeasurements = 12;

/// What the command line says about the robot's firmware and geometry.
struct BridgeFlags {
  std::string protocol;
  std::string sim_robot;
  std::string store;
  std::optional<double> wheel_diameter_mm;
  std::optional<double> wheelbase_mm;
  std::optional<double> counts_per_rev;
};

/// --protocol and the nominal geometry it needs: a ROSArduinoBridge robot knows nothing of its
/// geometry, so the owner gives it (with --sim the robot file's nominal keys stand in). Throws
/// InputError naming the flag.
void check_bridge_flags(const BridgeFlags& f, Procedure procedure);

/// The nominal geometry of a ROSArduinoBridge robot: the flags, with --sim the robot file's
/// nominal keys where a flag is not given. Throws InputError for a robot file it cannot read.
[[nodiscard]] BridgeNominal bridge_nominal(const BridgeFlags& f);

/// --ros-update-rate-hz and --ros-velocity-window: how the robot's diff_drive_controller
/// estimates its velocity, for the twist covariance of diff_drive_controller.yaml (docs/ros.md).
struct RosFlags {
  std::optional<double> update_rate_hz;
  std::optional<std::uint64_t> window;
};
/// Adds them to `cmd`.
void add_ros_flags(CLI::App& cmd, RosFlags& flags);
/// What they say, the controller's defaults where not given.
[[nodiscard]] RosVelocityEstimate ros_estimate(const RosFlags& flags);
/// session.json's record of them (under `recorded`, the options object).
void record_ros_flags(const RosFlags& flags, nlohmann::json& recorded);
/// --resume: the interrupted session's (from `options`, its options object in `file`); one given
/// on the command line (`cmd`) that differs is refused (InputError).
void resume_ros_flags(const nlohmann::json& options, const std::string& file, const CLI::App& cmd,
                      RosFlags& flags);

/// A count of session.json's options (--runs, --seed, --baud, ...): an integer from 0 within 64
/// bits, nothing else (InputError naming `file` and the key).
[[nodiscard]] std::uint64_t count_in(const nlohmann::json& options, const char* key,
                                     const std::string& file);

/// An interrupted session's session.json (`file`), refused unless it can be resumed.
[[nodiscard]] nlohmann::json interrupted_session(const std::string& file);

/// `--truth` and `--maze` as given (session_walls.cpp).
struct WallsFlags {
  std::string truth;  ///< tape or walls
  std::string maze;   ///< --maze (with --port): practice or a maze text file
  std::string sim_robot;
};

/// Whether the walls measure (`--truth walls`), checked against the procedure (auto only), a
/// measurement file and ROSArduinoBridge (refused); --maze without it is refused. InputError.
[[nodiscard]] bool check_walls_flags(const WallsFlags& f, Procedure procedure, bool measurements,
                                     bool bridge);

/// The robot file odocal-sim runs under --truth walls: `path` itself, or, for a file that says
/// nothing of the robot's size (`{}`), the file with a usual mouse's size (wheels 32 mm,
/// wheelbase 76 mm, each a little off), written to `out_dir`/robot.json.
[[nodiscard]] std::string walls_robot_file(const std::string& path, const std::string& out_dir);

/// What the session knows of the maze: with --sim the robot file's (`sim_file`) maze, start and
/// sensor mounts; with --port `--maze` (the practice maze by default), the start cell (0, 0)
/// facing north and the usual mouse's mounts. InputError naming the file or flag at fault.
[[nodiscard]] MazeKnowledge maze_knowledge(const WallsFlags& f, const std::string& sim_file);

/// Registers --truth and --maze (--maze needs `port`).
void add_walls_flags(CLI::App& cmd, std::string& truth, std::string& maze, CLI::Option* port);

}  // namespace odocal::host
