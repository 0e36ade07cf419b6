#pragma once
// Shared by the session's procedures (not installed): the run loop, parameters, output files.

#include <cstdint>
#include <exception>
#include <istream>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/drive/drive_config.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/session.hpp"
#include "odocal/params/param_table.hpp"

namespace odocal::host::session {

/// A robot parameter, by its stored id (drive/drive_config.hpp lists them): the session asks for
/// parameters by id, so that a misspelt one does not compile.
using params::ParamId;

// The members of Factors: the parameters of a factor group in the robot's parameter list.
#define ODOCAL_FACTOR_none(name, initial)
#define ODOCAL_FACTOR_wheel(name, initial) double name = initial;
#define ODOCAL_FACTOR_lateral(name, initial) double name = initial;
#define ODOCAL_FACTOR_MEMBER(type, name, initial, unit, min, max, group) \
  ODOCAL_FACTOR_##group(name, initial)
#define ODOCAL_FACTOR_EACH_none(name)
#define ODOCAL_FACTOR_EACH_wheel(name) fn(ParamId::name, self.name);
#define ODOCAL_FACTOR_EACH_lateral(name) fn(ParamId::name, self.name);
#define ODOCAL_FACTOR_EACH(type, name, initial, unit, min, max, group) \
  ODOCAL_FACTOR_EACH_##group(name)

/// The factors in force on the robot: one member per parameter of a factor group (wheel, lateral)
/// in the robot's parameter list (drive/drive_config.hpp), its default the robot's. A new factor
/// there is a new member here, read, set, compared and written to session.json with the others.
/// wheelbase_arc_mm 0: the same as wheelbase_mm (also what firmware without it has).
struct Factors {
  ODOCAL_DRIVE_PARAMETERS(ODOCAL_FACTOR_MEMBER)

  /// Calls fn(id, value) for each factor, in the list's order.
  /// Equal factor by factor (exactly).
  friend bool operator==(const Factors& a, const Factors& b) {
    bool same = true;
    const Factors* other = &b;
    a.each([&](ParamId id, double value) {
      double theirs = 0.0;
      other->each([&](ParamId i, double v) { theirs = i == id ? v : theirs; });
      same = same && value == theirs;
    });
    return same;
  }

  template <class Fn>
  void each(Fn&& fn) {
    each_of(*this, fn);
  }
  template <class Fn>
  void each(Fn&& fn) const {
    each_of(*this, fn);
  }

 private:
  template <class Self, class Fn>
  static void each_of(Self& self, Fn& fn) {
    ODOCAL_DRIVE_PARAMETERS(ODOCAL_FACTOR_EACH)
  }
};

/// What a procedure hands back to the engine.
struct Outcome {
  nlohmann::json result = nlohmann::json::object();
  std::string text;      ///< the result for people (with intervals)
  bool applied = false;  ///< new factors are in force on the robot
};

class RunJury;

/// The session's state and the steps every procedure uses.
class Context {
 public:
  Context(RobotClient& robot, MeasurementSource& source, const SessionOptions& options,
          std::ostream& log)
      : robot(robot), source(source), options(options), log(log) {}

  RobotClient& robot;
  MeasurementSource& source;
  const SessionOptions& options;
  std::ostream& log;
  std::vector<RunRecord> runs;
  std::vector<std::string> files;  ///< written into out_dir, in order
  std::size_t planned = 0;         ///< runs planned so far (for "Run 3/10")
  /// What was in force when the session started (put back on an interruption).
  Factors initial;
  double initial_cruise_mps = 0.0;
  bool initial_unsaved = false;
  /// `wiring_fix` when the session started, noted by the self-test (the one step that changes
  /// it); unset: not changed.
  std::optional<double> initial_wiring_fix;
  /// The result so far: procedures fill it as they go, so that an interrupted session's
  /// session.json shows what was computed (e.g. the passes done).
  nlohmann::json partial = nlohmann::json::object();
  /// The factors in force as last read from the robot (session.json's `factors`).
  std::optional<Factors> last_factors;
  /// The jury of the runs being measured (run_jury.hpp; nullptr: runs checked alone and against
  /// their repeats). A run it judges is checked at typing time against what the others predict.
  RunJury* jury = nullptr;
  /// The factors in force during each run of `runs` (unset: a run taken over on --resume).
  std::vector<std::optional<Factors>> run_factors;

  /// The session's UNIX time (provenance `date`).
  [[nodiscard]] std::uint64_t date() const;

  /// `get NAME` as a number.
  double get(ParamId id);
  /// `set NAME VALUE`; returns the value as stored.
  double set(ParamId id, double value);
  [[nodiscard]] Factors factors();
  /// Puts `f` in force: the arc wheelbase cleared first and set last, so that no step breaks
  /// the firmware's rule that it stays within 20 % of wheelbase_mm.
  void set_factors(const Factors& f);

  /// One measured run: `odom reset`, `command` (a `run ...` or timed `drive`), `# done` within a
  /// timeout from `expected_s` (the run's nominal duration), `trial`, then the measurement.
  /// With `log_ticks` the run is logged through `stream ticks`.
  RunRecord run(const std::string& label, const Motion& motion, double expected_s,
                bool log_ticks = false, const std::vector<Motion>& then = {});

  /// Nominal duration of a path of `length_m` metres and `turn_rad` radians of turning on the
  /// spot, in `segments` segments, at the robot's cruise speed, turn rate and settle time.
  double path_seconds(double length_m, double turn_rad, int segments);

  /// Sends a run's motion command; a reply damaged on the line is judged by what the robot then
  /// does (moving, or a newer trial): sent again only when it did not take it.
  void start_motion(const Motion& motion);
  /// The robot's tick count at the last check (unset: none yet).
  std::optional<std::int64_t> last_ticks;
  /// The trial number of the last run driven (0: none yet).
  std::int64_t last_trial = 0;
  /// Before a run where the measurement source drives the robot itself between runs (the walls'
  /// looks: trials of their own): the robot's latest trial into `last_trial`, so that the run's
  /// own trial, and no look's, is the one taken as its end (a robot in real time answers `trial`
  /// with the look's last step until the run's trial is over).
  void note_latest_trial();
  /// Before run `index` (0-based) moves the robot: `status`; a tick count that went back since the
  /// last check throws RobotRestarted (the robot restarted while it waited for the run).
  void check_still_up(std::size_t index);

  /// The user's moment (with --port, without --no-wait): says `prompt`, asks for Enter and waits
  /// for it; nothing that moves the robot may be sent before it returns. `before` names what
  /// comes ("run 3", "the self-test") in the message for the end of the input.
  void wait_for_enter(const std::string& prompt, const std::string& before);

  /// Refuses to start when the measurement source has fewer than `count` more rows.
  void need_measurements(std::size_t count, const std::string& what);

  /// Writes `content` to out_dir/name (whole, through a temporary file and a rename: a power cut
  /// leaves the old or the new file).
  void write_file(const std::string& name, const std::string& content);

  /// session.json: `complete` false while the session runs and after an interruption.
  /// @return what it wrote.
  nlohmann::json write_session_json(bool complete, const nlohmann::json& result, bool applied,
                                    bool saved, const std::string& interruption = std::string());

  /// The runs session.json keeps while the session is not complete: this session's, then those
  /// of the interrupted session being resumed that it has not taken over yet (a session that
  /// stops early, or refuses to resume, never loses a run).
  [[nodiscard]] std::vector<RunRecord> kept_runs() const;

  /// measurements.csv written whole from kept_runs() (on --resume, and when a run's measurement
  /// changed after it was journalled).
  void rewrite_journal();

 private:
  /// The measurement of the run `r` (index: 0-based over the session), checked before it is
  /// taken (reading_check.hpp) against the factors `in_force` and the repeats of its command.
  SessionPose measure(const RunRecord& r, std::size_t index, const Factors& in_force);
  /// Before run `index` (0-based) with a tape: the user's moment to put the robot on the mark.
  void ask_to_place(std::size_t index, const std::string& label);
  /// A run's motions after its first (`then`), each started once the one before is `done`;
  /// returns their trials' counts and time summed, `done` the last one's `# done`.
  RunRecord drive_legs(const std::vector<Motion>& then, double expected_s,
                       std::map<std::string, std::string>& done);
  /// Appends `r`'s measurement (run `number`) to measurements.csv and flushes it to the disk.
  void journal(const RunRecord& r, std::size_t number);
};

/// One line typed at a prompt. False at the end of the input; a signal that cut the wait short
/// throws Interrupted (so that it is never taken for the end of the input).
[[nodiscard]] bool read_typed_line(std::istream& in, std::string& line);

/// Asks `question` [y/n] on the log until the answer is one: --yes is a yes; without a terminal
/// (confirm_in) a no. The end of the input throws InputError naming the question.
[[nodiscard]] bool ask_yes_no(Context& c, const std::string& question);

/// The save question after a procedure applied its result: --yes, or "y" typed at the terminal;
/// without a terminal it says that nothing is saved.
[[nodiscard]] bool confirmed(Context& c);

/// The way out of every procedure (SIGINT, SIGTERM, the end of the input at a prompt, a lost
/// robot, a refused result): the robot stopped and its stream off, every setting the session
/// changed and did not save put back, session.json (`"complete": false`, no run lost) and
/// report.html written, the reason and how to resume said. Throws SessionEnded (exit status 130
/// after a signal, 2 otherwise).
[[noreturn]] void end_early(Context& c, const std::exception& why);

/// The console lines of a run: its motion's, and those it drove after it, joined by "; ".
std::string command_of(const RunRecord& r);

/// `{c_l, c_r, wheelbase_mm, f_lat, f_lon}`.
nlohmann::json factors_json(const Factors& f);

/// `value` for printing with `decimals` decimals: no "-0.0" for what rounds to zero.
double plain(double value, int decimals = 1);

/// "1 run", "2 runs".
std::string count_of(std::size_t n, const char* singular, const char* plural);

/// Gentle arcs the lateral procedure drives besides its straight trials.
inline constexpr std::size_t lateral_arcs = 4;

// The procedures (one file each).
Outcome run_umbmark(Context& context);
Outcome run_lateral(Context& context);
Outcome run_verify(Context& context);
Outcome run_fit(Context& context);
/// The extended UMBmark (a measurement: applies nothing).
Outcome run_extended(Context& context);
Outcome run_selftest(Context& context);
/// Self-test, the runs the factors need (chosen by what each adds), verification, save.
Outcome run_auto(Context& context);

/// What the engine does for each procedure beside its row in `procedures` (session.hpp: name,
/// --runs' bounds): how many measured runs it plans (for "Run 3/10" and the measurement file's
/// check) and the function that runs it. One row per Procedure, in its order (checked below): a
/// new procedure is its row here and in `procedures`, and its file (docs/architecture.md).
struct ProcedureSteps {
  Procedure procedure;
  std::size_t (*planned)(const SessionOptions& options);
  Outcome (*run)(Context& context);
};

inline constexpr ProcedureSteps procedure_steps[] = {
    {Procedure::umbmark, [](const SessionOptions& o) { return 2 * o.runs.value_or(5); },
     run_umbmark},
    {Procedure::lateral, [](const SessionOptions& o) { return o.runs.value_or(10) + lateral_arcs; },
     run_lateral},
    {Procedure::fit, [](const SessionOptions& o) { return o.runs.value_or(6); }, run_fit},
    {Procedure::verify, [](const SessionOptions& o) { return 2 * o.runs.value_or(5); }, run_verify},
    {Procedure::extended, [](const SessionOptions& o) { return 4 * o.runs.value_or(5); },
     run_extended},
    // A measured run only for a fault the encoders cannot tell apart.
    {Procedure::selftest, [](const SessionOptions&) { return std::size_t{0}; }, run_selftest},
    // The first round and the verification; more only when the precision asks for them.
    {Procedure::automatic,
     [](const SessionOptions&) { return auto_first_round + auto_verify_runs; }, run_auto},
};

constexpr bool steps_in_procedure_order() {
  std::size_t k = 0;
  for (const ProcedureSteps& s : procedure_steps) {
    if (static_cast<std::size_t>(s.procedure) != k++ || s.planned == nullptr || s.run == nullptr) {
      return false;
    }
  }
  return k == std::size(procedures);
}
static_assert(steps_in_procedure_order(), "procedure_steps: one row per Procedure, in its order");

/// The session's result as diff_drive_controller parameters in out_dir/diff_drive_controller.yaml,
/// and as `result.ros` (session_ros.cpp): a ROSArduinoBridge robot's factors in force on the host
/// as multipliers; an odocal robot's factors in force on it (`saved`: the session saved them) as
/// the wheel separation, multipliers 1.
void write_ros_yaml(Context& c, Outcome& outcome, bool saved);

/// A logged run as a tick log (`t_s,count_l,count_r,x_mm,y_mm,theta_deg`; the measured stop point
/// on its last row): what `odocal fit` reads.
std::string tick_log_csv(const RunRecord& r);
/// The same log in memory (no file in between); `with_reading`: the measured stop on its last row.
TickLog tick_log_of(const RunRecord& r, bool with_reading = true);

/// One `# ticks t_ms=T count_l=L count_r=R` line as a sample, or nothing when it does not read
/// exactly so. `checked`: the line must end with ` crc=N`, N the CRC-16 (console::crc16) of the
/// bytes before it (what `stream ticks <hz> crc` sends); a damaged line does not read.
std::optional<TickSample> read_tick_line(const std::string& line, bool checked);

/// Removes the samples of an unchecked tick log that a line damaging bytes left readable but
/// wrong: out of time order, or off the path their neighbours draw (tick_lines.cpp). The first
/// and last rows stay. Returns how many.
std::size_t drop_damaged(std::vector<TickSample>& ticks);

/// Throws InputError naming `file` unless the replayed run `r` (run `number`, from session.json)
/// has a tick log a fit can read: two or more rows, their times finite and never decreasing.
void check_replayed_ticks(const RunRecord& r, std::size_t number, const std::string& file);

/// Reads the run's `trial` reply (asked until two answers agree) into `r`: trial, path, duration
/// and counts, the odometry at its end. LinkError when the reply does not read, names a path that
/// is no name, or is for another trial than `# done` announced (`done`, empty when it was lost).
void read_trial(RobotClient& robot, const std::map<std::string, std::string>& done, RunRecord& r,
                std::int64_t last_trial);
/// What report.html shows.
struct ReportInput {
  std::string title;
  std::uint64_t date_unix_s = 0;
  bool complete = true;
  std::string interruption;
  bool saved = false;
  std::vector<RunRecord> runs;
  std::size_t tape_readings = 0;  ///< of the runs, those a tape measured (session.json's count)
  nlohmann::json result = nlohmann::json::object();
  Factors factors;
  std::map<std::string, std::string> provenance;  ///< the console's `provenance` pairs
  std::string summary;                            ///< the procedure's result for people
  double wheel_diameter_mm = 60.0;                ///< nominal geometry (odometry traces)
  double wheelbase_mm = 150.0;
  double counts_per_rev = 1440.0;
  double side_m = 4.0;  ///< UMBmark square side (paths of runs without a tick log)
};
/// Writes out_dir/report.html for the session so far (never throws for a robot that does not
/// answer: the page then shows what the host knows).
void write_report(Context& c, const nlohmann::json& result, const std::string& summary,
                  bool complete, bool saved, const std::string& interruption);
/// `text` with HTML's special characters escaped.
std::string html_escape(const std::string& text);
/// report.html's table and picture of every run against what the others predict
/// (`result.run_checks`; "" without it), session_report_checks.cpp.
std::string run_checks_section(const nlohmann::json& result);
/// report.html's evidence of `--truth walls` (`result.walls`; "" without it): the sensors learnt,
/// the maze with every look's place, each run's stop as the walls saw it
/// (session_report_walls.cpp).
std::string walls_section(const nlohmann::json& result);
/// report.html's line of the unseen path before and after (`result.verify.before_rms_mm`; "").
std::string before_after_line(const nlohmann::json& result);
/// report.html: one self-contained page (inline SVG, no script, nothing from the network).
std::string report_html(const ReportInput& input);

/// `trial,label,path,duration_ms,count_l,count_r,odom_x_mm,...,measured_theta_deg` of every run.
std::string runs_csv(const std::vector<RunRecord>& runs);
/// The runs' end points (odometry and measured) and, for logged runs, their odometry traces.
std::string runs_svg(const std::vector<RunRecord>& runs, const std::string& title);
/// The same panels, `columns` to an SVG document (one per row).
std::vector<std::string> runs_svg_rows(const std::vector<RunRecord>& runs, const std::string& title,
                                       std::size_t columns);
/// The `runs` array of the session JSON.
nlohmann::json runs_json(const std::vector<RunRecord>& runs);

}  // namespace odocal::host::session
