#pragma once
/// @file
/// Motion segments, ready-made paths, and the executor that drives them on odometry.

#include <array>
#include <cstdint>

#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/drive/odometry.hpp"

namespace odocal::drive {

/// One piece of a path. Signs: distance > 0 forward, angle > 0 counter-clockwise (left).
///  - line: `distance_m` != 0, `angle_rad` == 0
///  - turn in place: `distance_m` == 0, `angle_rad` != 0
///  - arc: both non-zero; radius = distance_m / angle_rad
struct Segment {
  float distance_m = 0.0f;
  float angle_rad = 0.0f;
};

/// Which ready-made path is loaded (reported by `status`).
enum class PathId : std::uint8_t { none, umbmark_cw, umbmark_ccw, line, unseen, drive };

/// Name of a path as the console spells it ("umbmark-cw", ...; "none"; "drive" names a timed
/// `drive` in trial records).
[[nodiscard, gnu::noinline]] const char* path_name(PathId id);

/// A fixed-capacity list of segments.
struct Path {
  static constexpr std::uint8_t capacity = 16u;
  std::array<Segment, capacity> segments{};
  std::uint8_t count = 0u;
  PathId id = PathId::none;

  /// Appends a segment; false (and nothing appended) when full.
  bool push(const Segment& segment);
};

/// UMBmark bidirectional square (seed 002, section 6): four legs of `side_m`, a turn in place of
/// 90° at each corner (right turns for cw, left for ccw), ending at the start facing the start
/// heading. `side_m` must be in (0, 20].
[[nodiscard]] Path make_umbmark_square(bool clockwise, float side_m);
/// Straight calibration line of `length_m` (Maddahi section II), (0, 20].
[[nodiscard]] Path make_line(float length_m);
/// Maddahi unseen path (Fig. 9): a 100 cm square (left turns), a 100 cm equilateral triangle
/// (left turns of 120°), then an 80 cm-radius left semicircle. Ends at (0, 1.6 m) facing 180°.
[[nodiscard]] Path make_unseen_path();

/// Drives a path one segment at a time. Each segment runs a speed profile limited by the
/// configured cruise speed and acceleration, decelerating on the distance (or angle) that remains
/// *according to odometry*, and ends when odometry says it has covered the segment; the robot
/// then settles at standstill for `settle_ms` before the next segment. Near the end the profile
/// keeps a creep speed (2 % of cruise, or more with a coarse encoder so that each wheel still sees
/// an edge every 20 ms) so the end is always reached.
///
/// Headings are planned from where the path started: a turn ends at the path's planned heading
/// (so what the turn before it overran is made good, not added to), and lines and arcs steer
/// toward the heading the plan has at that point, a heading error decaying over 0.2 m of travel.
/// The robot therefore ends where its odometry says the path ends, up to the last segment's
/// overrun, however many segments came before.
class MotionExecutor {
 public:
  /// Loads a path and starts it from the current odometry.
  void start(const Path& path, const Odometry& odometry);
  /// Loads a path without starting it (what is running is cancelled): the tick copies a new path
  /// straight from the main loop's mailbox, once.
  void load(const Path& path);
  /// Starts the loaded path from the current odometry.
  void start_loaded(const Odometry& odometry);
  /// The loaded path.
  [[nodiscard]] const Path& path() const { return path_; }
  /// Abandons the path (the twist drops to zero at once).
  void cancel();

  /// One tick: the body twist to command. Tick context.
  /// @param odometry the pose after this tick's update; @param dt_s tick period, s.
  [[nodiscard]] Twist update(const Odometry& odometry, const DriveConfig& limits, float dt_s);

  [[nodiscard]] bool busy() const { return busy_; }
  [[nodiscard]] PathId path_id() const { return path_.id; }
  [[nodiscard]] std::uint8_t segment_index() const { return index_; }

 private:
  void begin_segment(const Odometry& odometry);

  Path path_{};
  std::uint8_t index_ = 0u;
  bool busy_ = false;
  bool settling_ = false;
  float settle_s_ = 0.0f;
  float start_distance_m_ = 0.0f;
  float start_rotation_rad_ = 0.0f;  ///< planned heading where this segment begins (odometry's)
  float heading_goal_rad_ = 0.0f;    ///< planned heading where this segment ends
  float speed_ = 0.0f;  ///< profile speed along the segment's own coordinate (m/s or rad/s)
};

}  // namespace odocal::drive
