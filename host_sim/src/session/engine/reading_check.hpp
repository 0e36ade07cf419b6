#pragma once
// Internal to the session: a reading is checked before it is taken. It is compared with where the
// robot's odometry says the run stopped, allowing what the robot can be (its geometry anywhere in
// the reading box below around the model in force) and its noise, and with the readings of the
// same run driven before in this session. A reading that cannot be is shown back with the slip
// that would explain it (docs/calibration.md, "Readings are checked").

#include <optional>
#include <string>
#include <vector>

#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/host/session.hpp"

namespace odocal::host::session {

/// Degrees per radian.
inline constexpr double deg_per_rad = 180.0 / 3.14159265358979323846;

/// How far the real robot's geometry can be from the model in force, relative: the mean wheel
/// diameter (a tyre's size), the right-to-left diameter ratio, the wheelbases. Wider than any
/// robot that drives straight enough to calibrate, narrower than the plausible ranges of a result
/// (which also take robots told a wrong size).
namespace reading_box {
inline constexpr double scale = 0.05;
inline constexpr double ratio = 0.02;
inline constexpr double wheelbase = 0.08;
}  // namespace reading_box

/// The run-to-run noise a reading is allowed on top of the geometry: a tape's few millimetres, a
/// share of the distance driven (slip), a share of the turning (a turn in place's slip), and the
/// heading's scatter carried over half the path's length.
namespace reading_noise {
inline constexpr double position_mm = 10.0;
inline constexpr double position_per_mm = 0.01;
inline constexpr double heading_deg = 2.0;
inline constexpr double heading_per_deg = 0.005;
/// Per wheelbase of distance: the wheels' slip differs, and the heading wanders by their
/// difference over the wheelbase (a small robot on a long line wanders most).
inline constexpr double heading_per_wheelbase_deg = 0.1;
}  // namespace reading_noise

/// How far a run's real stop can be from where its odometry says it stopped.
struct ReadingAllowance {
  double position_mm = 0.0;
  double heading_deg = 0.0;
};

/// Length (mm) and turning (deg, every turn counted) of a path.
struct PathExtent {
  double length_mm = 0.0;
  double turned_deg = 0.0;
  double wheelbase_mm = 0.0;  ///< the robot's (0: unknown; the per-wheelbase noise left out)
};
[[nodiscard]] PathExtent extent_of(const drive::Path& path);

/// The geometry box's reach (the largest change of the end pose over the box's corners, the path
/// driven by the odometry of `in_force`, mm) plus the noise allowance.
[[nodiscard]] ReadingAllowance allowance_of(const drive::Path& path,
                                            const drive::model::Geometry<double>& in_force_mm);

/// A run of the same command measured before in this session (procedures whose runs are not judged
/// by all the others, run_jury.hpp: UMBmark's squares, the lateral lines, the extended figure).
struct EarlierReading {
  SessionPose odom;
  SessionPose measured;
  bool same_factors = false;  ///< the same factors were in force (else a calibration came between)
};

/// What the check knows about the run being measured.
struct ReadingFacts {
  SessionPose odom;
  std::optional<ReadingAllowance> allowance;  ///< none: the command's path is unknown
  PathExtent extent;
  std::vector<EarlierReading> earlier;
  bool heading_needed = false;
};

/// "x y [theta]" as a person would type it back: `decimals` decimals at most, trailing zeros
/// dropped down to one (a suggestion keeps the digits typed: typed_decimals).
[[nodiscard]] std::string pose_text(const SessionPose& pose, int decimals = 1);

/// The most decimals of any number in `typed` (at least 1, at most 4).
[[nodiscard]] int typed_decimals(const std::string& typed);

/// The decimals a reading's numbers need (at least 1, at most 3): a suggestion for a reading that
/// came from a file keeps them.
[[nodiscard]] int decimals_of(const SessionPose& pose);

/// A slip a person makes reading a tape or typing a reading, and the reading it would have been.
struct SlipCandidate {
  std::string what;
  SessionPose reading;
};

/// Every single slip that could have turned a reading into `reading` (typed as `typed`, "" from
/// a file), each undone: a decimal comma read as a separator, the sign of the heading, a heading a
/// turn off, x and y swapped (and a sign), the sign of x or of y, metres or centimetres for
/// millimetres, the difference from the odometry `odom` typed instead of the stop; and each of
/// these after a decimal comma.
[[nodiscard]] std::vector<SlipCandidate> slip_candidates(const SessionPose& reading,
                                                         const std::string& typed,
                                                         const SessionPose& odom);

/// How the reading `typed` was read, when it holds a comma (a comma is never a silent
/// separator): "read as x 2998, y -103, heading 5" and, for a comma between digits, what a decimal
/// comma would have meant. "" without a comma.
[[nodiscard]] std::string comma_note(const std::string& typed, const SessionPose& read);

/// Judges `reading` (typed as `typed`, "" when it came from a file).
[[nodiscard]] ReadingVerdict judge_reading(const ReadingFacts& facts, const SessionPose& reading,
                                           const std::string& typed);

}  // namespace odocal::host::session
