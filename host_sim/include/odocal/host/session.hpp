#pragma once
/// @file
/// `odocal session`: a whole calibration driven through the robot's console (DESIGN "Host
/// program: sessions and fits"). For every run: `odom reset`, `run ...` (or a timed `drive`),
/// wait for `# done`, read `trial`, take the measurement (the simulator's `measure`, a CSV file,
/// or a person at the terminal); then compute, show, apply, and save only when allowed.

#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/motion.hpp"
#include "odocal/host/robot_client.hpp"
#include "odocal/host/ros2_yaml.hpp"
#include "odocal/sim/maze.hpp"
#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::host {

class BridgeConsole;

/// A pose in the start frame (x ahead, y left), mm and degrees; theta may be unknown.
struct SessionPose {
  double x_mm = 0.0;
  double y_mm = 0.0;
  std::optional<double> theta_deg;
};

/// One cumulative tick sample of `stream ticks`.
struct TickSample {
  double t_ms = 0.0;
  std::int64_t count_l = 0;
  std::int64_t count_r = 0;
};

/// One run as the robot recorded it, and where it was measured to stop.
struct RunRecord {
  std::string label;  ///< what the run is for: "cw", "ccw", "line", "arc", "before", "after", ...
  std::int64_t trial = 0;
  std::string path;
  double duration_ms = 0.0;
  std::int64_t count_l = 0;
  std::int64_t count_r = 0;
  SessionPose odom;
  SessionPose measured;
  std::vector<TickSample> ticks;  ///< only when the run was logged (fit)
  Motion motion;                  ///< what it told the robot to do
  /// Motions driven after `motion` in the same run, each once the one before is over (`--truth
  /// walls`: up one corridor, a quarter turn, along the next): one tick log, one measured end.
  std::vector<Motion> then;
  bool replayed = false;  ///< taken from the session being resumed, not driven again
};

/// A session that ended early: its reason is on the log already, with what was put back on the
/// robot and where the measurements are. `exit_status` is 130 after a signal, 2 otherwise.
class SessionEnded : public std::runtime_error {
 public:
  SessionEnded(const std::string& what, int exit_status)
      : std::runtime_error(what), exit_status_(exit_status) {}
  [[nodiscard]] int exit_status() const { return exit_status_; }

 private:
  int exit_status_;
};

/// How a reading compares with what the run can have done (docs/calibration.md, "Readings are
/// checked").
struct ReadingVerdict {
  bool plausible = true;
  std::string problem;                    ///< what is off, by how much, and what it can be
  std::string likely;                     ///< the slip that explains it ("" when none does)
  std::optional<SessionPose> suggestion;  ///< the reading that slip would have been
  std::string comma;                      ///< a note on a comma typed between digits
  int decimals = 1;                       ///< the suggestion keeps the decimals typed
  /// The lines that show it back to the person who typed it ("" when plausible).
  [[nodiscard]] std::string explained() const;
};

/// Judges a reading of the run being measured: the pose as read, and the line as typed ("" when
/// it did not come from a keyboard).
using ReadingCheck = std::function<ReadingVerdict(const SessionPose&, const std::string&)>;

/// `--truth walls` (DESIGN "No tape measure"): what the session knows of the maze before the
/// robot moves: the maze's plan, the start cell and heading the owner put the robot down in, and
/// where the robot's drawing puts its four wall sensors. Nothing here is measured.
struct MazeKnowledge {
  sim::Maze maze{};
  std::uint32_t start_column = 0u;
  std::uint32_t start_row = 0u;
  double start_heading_rad = 1.5707963267948966;  ///< maze frame (counter-clockwise from east)
  std::array<sim::SensorMount, sim::WallSensorLayout::count> mounts{};
  std::string name = "the practice maze";  ///< for the log and session.json
  /// The robot is odocal-sim (--sim): after every run its tape (`measure`, the simulator's truth
  /// plus the robot file's measure_sigma_mm) is read beside the walls, and what the walls got
  /// wrong is reported (result.walls.against_simulator). Never used by the calibration.
  bool simulator = false;
};

/// Where the measurements come from.
class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  /// The check of the next take(), and whether that run needs a heading. A source that asks a
  /// person shows a questioned reading back and asks again (or takes it confirmed), and returns
  /// true; the others return false and the session judges what they return.
  virtual bool check_next(const ReadingCheck& check, bool heading_needed) {
    static_cast<void>(check);
    static_cast<void>(heading_needed);
    return false;
  }
  /// Asks the person at the robot `question` and returns the line typed (its end trimmed);
  /// nullopt when no person is there to answer (a file, the simulator's tape). The end of the
  /// input throws InputError (the session's way out).
  virtual std::optional<std::string> ask(const std::string& question) {
    static_cast<void>(question);
    return std::nullopt;
  }
  /// The reading of `run` (session run `number`, 1-based) typed again, checked by `check`;
  /// nullopt when no person is there to type it.
  virtual std::optional<SessionPose> retype(const RunRecord& run, std::size_t number,
                                            const ReadingCheck& check, bool heading_needed) {
    static_cast<void>(run);
    static_cast<void>(number);
    static_cast<void>(check);
    static_cast<void>(heading_needed);
    return std::nullopt;
  }
  /// Whether its readings are a person's (typed, or from a file): the simulator's tape is not.
  [[nodiscard]] virtual bool by_hand() const { return true; }
  /// Whether its readings are a tape's (a person's or the simulator's `measure`). False for the
  /// walls (`--truth walls`): no tape reading is taken (session.json's `measurements` counts
  /// none), and the robot is not put back on a start mark before each run: it is measured where
  /// it stops and starts the next run from there.
  [[nodiscard]] virtual bool is_tape() const { return true; }
  /// How many of the first `runs` runs' readings a tape gave (session.json's `measurements`).
  [[nodiscard]] virtual std::size_t tape_readings(std::size_t runs) const {
    return is_tape() ? runs : 0u;
  }
  /// Whether run `index`'s reading (0-based over the session) can be typed again (retype): a
  /// person's, not the walls'.
  [[nodiscard]] virtual bool retypable(std::size_t index) const {
    static_cast<void>(index);
    return by_hand();
  }
  /// Whether the robot drives between its runs for the measurements (the walls' looks): each run
  /// then first notes the robot's latest trial (Context::note_latest_trial).
  [[nodiscard]] virtual bool drives_between_runs() const { return !is_tape(); }
  /// Whether an interrupted session measured so can go on with --resume (the walls' cannot: the
  /// robot's place in the maze goes with the session).
  [[nodiscard]] virtual bool resumable() const { return is_tape(); }
  /// The measured stop pose of `run` (index: 0-based over the whole session). Throws
  /// InputError / LinkError when there is none.
  virtual SessionPose take(const RunRecord& run, std::size_t index, std::size_t planned) = 0;
  /// How many runs it can still serve (SIZE_MAX: unlimited).
  [[nodiscard]] virtual std::size_t available(std::size_t already_taken) const = 0;
  /// "odocal-sim measure", "FILE", "terminal".
  [[nodiscard]] virtual std::string describe() const = 0;
};

/// The walls of the maze as the measurements (`--truth walls`, DESIGN "No tape measure"): the
/// robot learns its sensors in the start cell and looks after every run (wall_truth.hpp). Log:
/// what it learnt and found. `tape`: what measures the runs the walls cannot (the lines that
/// give the wheels' scale in a maze without a corridor for them, on an open floor): a person's
/// tape on a port, the simulator's `measure` with --sim.
[[nodiscard]] std::unique_ptr<MeasurementSource> wall_measurements(
    RobotClient& robot, const MazeKnowledge& maze, std::ostream& log,
    std::unique_ptr<MeasurementSource> tape);

/// The simulator's tape measure: `measure` on the console.
[[nodiscard]] std::unique_ptr<MeasurementSource> robot_measurements(RobotClient& robot);

/// CSV `x_mm,y_mm` or `x_mm,y_mm,theta_deg`, one row per run, read whole now (throws InputError
/// naming file, line and field).
[[nodiscard]] std::unique_ptr<MeasurementSource> file_measurements(const std::string& path);

/// Asks a person: prompts on `prompt`, reads lines from `in`, re-asks on bad input. With `echo`
/// (input not from a terminal) each line read is shown after its prompt.
[[nodiscard]] std::unique_ptr<MeasurementSource> prompt_measurements(std::istream& in,
                                                                     std::ostream& prompt,
                                                                     bool echo);

/// Parses "x y [theta]" (spaces and/or commas); on failure `why` says what was wrong.
[[nodiscard]] bool parse_measurement_line(const std::string& text, SessionPose& pose,
                                          std::string& why);

enum class Procedure { umbmark, lateral, fit, verify, extended, selftest, automatic };

/// A procedure as the command line, session.json and the help know it: declared once, in
/// `procedures` below (in the enum's order; a static_assert holds it).
struct ProcedureInfo {
  Procedure procedure;
  const char* name;       ///< --procedure's word and session.json's "procedure"
  std::uint64_t runs_lo;  ///< --runs' bounds (what --runs counts: docs/calibration.md)
  std::uint64_t runs_hi;
};

/// --runs: UMBmark runs per direction (the robot keeps 16 per direction, the solver needs 2);
/// lateral straight trials (the bootstrap needs 5 rows with the arcs); fit runs (3 give the
/// geometry); verify and extended runs per scenario (the figure's intervals need 2); auto and
/// selftest choose their own.
inline constexpr ProcedureInfo procedures[] = {
    {Procedure::umbmark, "umbmark", 2, 16},   {Procedure::lateral, "lateral", 2, 28},
    {Procedure::fit, "fit", 3, 30},           {Procedure::verify, "verify", 1, 16},
    {Procedure::extended, "extended", 2, 16}, {Procedure::selftest, "selftest", 1, 16},
    {Procedure::automatic, "auto", 1, 16},
};

constexpr bool procedures_in_enum_order() {
  int k = 0;
  for (const ProcedureInfo& p : procedures) {
    if (static_cast<int>(p.procedure) != k++) {
      return false;
    }
  }
  return k == static_cast<int>(Procedure::automatic) + 1;
}
static_assert(procedures_in_enum_order(), "procedures: one row per Procedure, in its order");

[[nodiscard]] constexpr const ProcedureInfo& info_of(Procedure procedure) {
  return procedures[static_cast<std::size_t>(procedure)];
}

/// The procedure named `name`; nullopt for a name no procedure has.
[[nodiscard]] std::optional<Procedure> procedure_named(std::string_view name);

/// The procedures' names: "auto, umbmark, ..., or selftest" (the help and the errors).
[[nodiscard]] std::string procedure_names();

struct SessionOptions {
  Procedure procedure = Procedure::umbmark;
  std::optional<double> side_m;  ///< umbmark square side (default 4) / lateral line length (1)
  /// auto: stop measuring when the factors leave at most this much (mm, 1 sigma) of end error on
  /// the unseen path; unset: the documented default (docs/calibration.md).
  std::optional<double> target_mm;
  /// auto: every tape measurement the session may take (self-test, calibration, verification);
  /// unset: the documented default (docs/calibration.md, "The budget").
  std::optional<std::size_t> max_measurements;
  std::optional<std::size_t> runs;
  std::size_t passes = 3;     ///< UMBmark passes at most (--passes)
  std::optional<bool> exact;  ///< --exact: always the exact square solve; unset: when it matters
  bool yes = false;           ///< save without asking
  bool json = false;
  std::string out_dir;
  /// Asks "save?" when set (a terminal is there); nullptr: not saved without --yes.
  std::istream* confirm_in = nullptr;
  /// Waits for a line here (Enter) before each run that moves the robot; nullptr: no wait
  /// (--sim, --no-wait).
  std::istream* start_in = nullptr;
  bool progress = false;             ///< show progress while a run drives (a terminal is watching)
  std::ostream* log = nullptr;       ///< progress and prompts (stderr)
  std::uint64_t seed = 1;            ///< for the bootstraps
  std::uint64_t started_unix_s = 0;  ///< the session's date (provenance); 0: now
  /// The command line's options as session.json records them (for --resume).
  nlohmann::json recorded = nlohmann::json::object();
  /// Runs of the interrupted session being resumed, in order: taken, not driven again.
  std::vector<RunRecord> replay;
  /// A robot that runs ROSArduinoBridge (--protocol ros-arduino-bridge): the console the session
  /// talks to is this host-side one; nothing is saved on the robot, and a result is written to
  /// out_dir/diff_drive_controller.yaml instead. nullptr: an odocal robot.
  const BridgeConsole* bridge = nullptr;
  /// How the robot's diff_drive_controller estimates its velocity (the twist covariance of
  /// diff_drive_controller.yaml; --ros-update-rate-hz, --ros-velocity-window).
  RosVelocityEstimate ros_velocity;
  /// `--truth walls`: the walls are the measurements (the source is a WallTruth); unset: a tape.
  std::optional<MazeKnowledge> walls;
  /// The `result` the interrupted session being resumed recorded (e.g. its self-test, which is
  /// then not driven again).
  nlohmann::json resumed_result = nlohmann::json::object();
};

namespace session {
/// `--procedure auto`: the measured runs of its first round (its plan may add more, within
/// --max-measurements) and the verification runs after them.
inline constexpr std::size_t auto_first_round = 6;
inline constexpr std::size_t auto_verify_runs = 2;
}  // namespace session

/// What a session did: the JSON of DESIGN, plus a human summary.
struct SessionReport {
  nlohmann::json json;
  std::string result_text;  ///< the procedure's result (also shown on the log as it came)
  std::string text;         ///< the factors in force and where the files are
};

/// Measured runs the procedure needs at least (UMBmark: its first pass), from its options.
[[nodiscard]] std::size_t planned_runs(const SessionOptions& options);

/// Runs the whole session on a connected robot. Throws LinkError / InputError /
/// std::runtime_error / Interrupted with a message for the user. Before it throws, it stops the
/// robot, puts back every factor it changed and did not save (and says so on the log), and
/// writes out_dir/session.json with "complete": false; measurements.csv holds every measurement
/// taken.
[[nodiscard]] SessionReport run_session(RobotClient& robot, MeasurementSource& measurements,
                                        const SessionOptions& options);

/// The runs of an interrupted session's session.json, with the tick logs of its logged runs read
/// back from `dir` (for --resume). Throws InputError naming the file and what is wrong.
[[nodiscard]] std::vector<RunRecord> recorded_runs(const nlohmann::json& session,
                                                   const std::string& dir);

/// --resume: the measurements of `runs` (an interrupted session's, from recorded_runs) as the
/// owner may have corrected them in `dir`/measurements.csv, the record they may edit. Returns one
/// line per reading taken from it that differs from session.json's (empty: none, or no file);
/// throws InputError naming the file, line and field of a row it cannot read.
[[nodiscard]] std::vector<std::string> take_edited_journal(std::vector<RunRecord>& runs,
                                                           const std::string& dir);

/// Checks `dir` for a new session (refuses one that already holds a session.json, or a path that
/// is not a directory) and, with `create`, makes it and its parents. Throws InputError.
void prepare_out_dir(const std::string& dir, bool create);

/// The default --out: `odocal-session-<procedure>-YYYYMMDD-HHMMSS` (UTC), with `-2`, `-3`, ...
/// added when that already exists.
[[nodiscard]] std::string default_out_dir(Procedure procedure);

[[nodiscard]] const char* to_string(Procedure procedure);

}  // namespace odocal::host
