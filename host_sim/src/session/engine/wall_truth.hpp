#pragma once
// Internal to the session: `--truth walls` (DESIGN "No tape measure"), the walls of the maze as
// the session's measurement source. The robot learns its sensors from a turn in the start cell;
// after every run it looks (a turn in place, stopping every few degrees to read its four sensors)
// and the walls around it say where it stopped, in the run's start frame, as a tape would.

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/session.hpp"
#include "odocal/host/walls.hpp"

namespace odocal::host::session {

/// A straight corridor of the maze from a cell, along a heading: how many cells it runs before a
/// wall ahead, and whether its last cell has a wall to a side (a look there then fixes both
/// coordinates). cells 0: a wall right ahead.
struct Corridor {
  std::uint32_t cells = 0u;
  bool end_has_side_wall = false;
  std::uint32_t end_column = 0u;
  std::uint32_t end_row = 0u;
  [[nodiscard]] double length_mm() const { return cells * sim::cell_pitch_mm; }
};

/// The corridor from (column, row) along `heading` (a multiple of 90°, maze frame).
Corridor corridor_from(const sim::Maze& maze, std::uint32_t column, std::uint32_t row,
                       double heading_rad);

/// The walls as the session's tape: every measured run's stop looked at.
class WallTruth final : public MeasurementSource {
 public:
  WallTruth(RobotClient& robot, const MazeKnowledge& maze, std::ostream& log);

  /// The turn in the start cell (about a turn and a quarter): the sensors learnt, the robot's
  /// pose in the maze; then it faces its start heading again. Throws std::runtime_error when the
  /// robot has no wall sensors or the walls do not explain what they read.
  void calibrate();
  [[nodiscard]] bool calibrated() const { return calibration_.has_value(); }

  /// Whether the robot stands in the start cell now.
  [[nodiscard]] bool in_start_cell() const;
  /// The robot's pose now (maze frame), as the last look and the turns since left it.
  [[nodiscard]] const sim::MazePose& pose() const { return pose_; }

  /// Turns in place to face `heading_rad` (maze frame), squared up to the maze's quarters: no run
  /// (a line up the corridor and back down it both go forwards, so that the wheels' ratio bends
  /// them to either side in turn and the robot stays in the corridor).
  void face(double heading_rad);

  /// Turns in place to face the centre of cell (column, row) (no run) and returns how far it is,
  /// m: a line aimed so keeps the robot on its corridor's centre line, whatever the lines before
  /// left it off it.
  double aim_at(std::uint32_t column, std::uint32_t row, bool backwards = false);

  /// The calibration's `n`-th line (0-based): from the start cell up the corridor to its far
  /// cell, or back down from there, aimed at the other end's centre. The four in turn: up
  /// forwards, down in reverse, up in reverse, down forwards (the robot turned round in place
  /// before the third and fifth, no run). Each end's walls reflect a little differently, which
  /// puts the same small error on every stop in that cell; over the four it cancels from what
  /// bends the lines (the wheels' ratio): forwards and in reverse it shows with opposite signs
  /// across the run, up and down with opposite signs in its heading. `what` says it for the log.
  Motion corridor_line(std::size_t n, double cruise_mps, double& expected_s, std::string& what);

  /// The second corridor of the calibration's route: from the far end of the start cell's
  /// corridor, the longest one to a side (two cells or more, ending in a corner); `turn_rad` the
  /// turn into it from the start heading. nullopt: the maze has none.
  [[nodiscard]] std::optional<Corridor> second_corridor(double& turn_rad) const;

  /// The calibration's run along the route, when the maze has a second corridor: up the start
  /// cell's corridor, a quarter turn at its end, along the second corridor to its far corner (or
  /// the same way back from there), one run measured at its end. The quarter turn carries the
  /// first leg's heading error, bent by the wheels' ratio, into the second leg, which multiplies
  /// what the run shows of that ratio; the turn is timed at the rate the calibration saw, so the
  /// second leg keeps to its corridor. `then` receives the turn and the second leg.
  Motion route_run(double cruise_mps, double spin_radps, std::vector<Motion>& then,
                   double& expected_s, std::string& what);

  /// A timed turn in place of about `turn_rad` (the robot's own, as the calibration saw it turn)
  /// at `w_radps` (the rate asked of the firmware, whose wheelbase may be off).
  Motion turn_in_place(double turn_rad, double w_radps);

  /// A move that is no run (getting to the verification's corridor): `command` driven from
  /// odometry zero, then a look. `expected_s`: its nominal duration.
  void move_and_look(const std::string& command, double expected_s);

  [[nodiscard]] const MazeKnowledge& maze() const { return maze_; }
  /// The corridor the calibration's lines drive: from the start cell, along the start heading.
  [[nodiscard]] Corridor calibration_corridor() const {
    return corridor_from(maze_.maze, maze_.start_column, maze_.start_row, maze_.start_heading_rad);
  }

  /// What the walls found, for session.json's result: the sensors learnt and every look.
  [[nodiscard]] nlohmann::json json() const;

  /// Where the walls cannot tell the wheels' scale: from now on the runs are driven on an open
  /// floor and the tape measures them (the robot leaves the maze; no look again). False when the
  /// session has no tape to ask.
  bool to_the_floor();
  [[nodiscard]] bool on_the_floor() const { return on_floor_; }
  [[nodiscard]] bool has_tape() const { return tape_ != nullptr; }

  // MeasurementSource: the walls', or on the floor the tape's.
  bool check_next(const ReadingCheck& check, bool heading_needed) override;
  std::optional<std::string> ask(const std::string& question) override;
  std::optional<SessionPose> retype(const RunRecord& run, std::size_t number,
                                    const ReadingCheck& check, bool heading_needed) override;
  [[nodiscard]] bool by_hand() const override { return on_floor_ && tape_->by_hand(); }
  [[nodiscard]] bool is_tape() const override { return on_floor_; }
  [[nodiscard]] std::size_t tape_readings(std::size_t runs) const override;
  [[nodiscard]] bool resumable() const override { return false; }
  [[nodiscard]] bool retypable(std::size_t index) const override;
  /// The looks drive between runs, and the calibration turn and the first round's turns before
  /// the first floor run.
  [[nodiscard]] bool drives_between_runs() const override { return true; }
  SessionPose take(const RunRecord& run, std::size_t index, std::size_t planned) override;
  [[nodiscard]] std::size_t available(std::size_t) const override { return SIZE_MAX; }
  [[nodiscard]] std::string describe() const override {
    return on_floor_ ? tape_->describe() : "the walls of " + maze_.name;
  }
  void set_tape(std::unique_ptr<MeasurementSource> tape) { tape_ = std::move(tape); }

 private:
  /// Turns in place in steps (`drive 0 w ms`, each a trial), reading the trial's counts and the
  /// walls at rest after each, until about `turn_rad` (at rate_), and with `and_back` back again;
  /// the samples' turn coordinate is the right wheel's counts minus the left's, summed.
  std::vector<walls::TurnSample> turn_and_read(double turn_rad, bool and_back);
  /// The last trial's turn: its right wheel's counts minus its left's (raw counts).
  double trial_turn_counts();
  /// Radians turned per turn count by the nominal geometry (wheel diameter, counts per turn,
  /// wheelbase as the robot holds them).
  double nominal_radians_per_count();
  /// A look from `guess` (where the robot is thought to be): the pose at its start, and pose_ at
  /// its end.
  sim::MazePose look(const sim::MazePose& guess, const std::string& why);
  /// Turns to the nearest quarter of the maze (pose_ follows the odometry's heading through the
  /// last look's angle per radian).
  void square_up();
  /// Turns in place by about `turn_rad` and follows it in pose_.
  void turn_by(double turn_rad);
  void wait_done(double expected_s);
  /// The maze's walls as segments [x1, y1, x2, y2], mm (report.html draws them).
  [[nodiscard]] nlohmann::json wall_segments() const;

  RobotClient& robot_;
  MazeKnowledge maze_;
  std::ostream& log_;
  std::optional<walls::TurnCalibration> calibration_;
  sim::MazePose pose_{};
  /// Radians the robot turns in place per turn count (right counts minus left), the calibration's.
  double rate_ = 0.0;
  /// The same by the nominal geometry, when the calibration began (rate_ over it: the ratio).
  double nominal_rate_ = 1.0;
  nlohmann::json looks_ = nlohmann::json::array();
  /// Per run (with MazeKnowledge::simulator): the walls' reading minus the simulator's tape.
  std::vector<std::array<double, 3>> errors_;
  std::unique_ptr<MeasurementSource> tape_;  ///< for what the walls cannot tell (to_the_floor)
  bool on_floor_ = false;
  std::vector<std::size_t> taped_;  ///< the runs (0-based session index) the tape measured
};

}  // namespace odocal::host::session
