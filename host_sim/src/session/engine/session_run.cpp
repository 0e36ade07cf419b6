// The session's measured run: the user's moment, `odom reset`, the drive, `# done`, `trial`, the
// tick log, the measurement and its journal.

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "model_in_force.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "reading_check.hpp"
#include "run_jury.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

std::int64_t whole(const Reply& reply, const std::string& key) {
  const std::optional<std::int64_t> value = toolkit::parse_integer(reply.text(key));
  if (!value) {
    throw LinkError("robot reply '" + reply.line + "': " + key + " is not a whole number");
  }
  return *value;
}

/// Waits until `samples` has grown past `count` (a `# ticks` line that reads arrived). A robot in
/// lockstep sends its lines only as the host gives it time: when a second passes without one (the
/// lines it sent came damaged on the line and were dropped), `ask_again` asks for the stream
/// again (a question would not do: it takes no robot time). `dropped` counts the tick lines that
/// came damaged so far.
void wait_tick(RobotClient& robot, const std::vector<TickSample>& samples, std::size_t count,
               const std::function<std::size_t()>& dropped,
               const std::function<void()>& ask_again) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  auto asked = std::chrono::steady_clock::now();
  while (samples.size() <= count) {
    const auto now = std::chrono::steady_clock::now();
    if (now > deadline) {
      const std::size_t damaged = dropped();
      throw LinkError(damaged > 0
                          ? fmt::format("no '# ticks' line came whole within 10 s after 'stream "
                                        "ticks': {} came damaged on the line (a noisy line: check "
                                        "the cable and the baud rate)",
                                        damaged)
                          : std::string("no '# ticks' line within 10 s after 'stream ticks' (does "
                                        "the firmware have it?)"));
    }
    if (now - asked > std::chrono::seconds(1)) {
      ask_again();
      asked = now;
    }
    static_cast<void>(robot.pump(200));
  }
}

/// `# ticks` lines into a run's record for as long as the run lasts: however the run ends (an
/// interruption included), the handler is gone with it, so that no line read afterwards (while
/// the robot is stopped and its factors put back) is written into a record that no longer
/// exists. The engine's way out turns the stream off on the robot.
class TickLogging {
 public:
  explicit TickLogging(RobotClient& robot) : robot_(robot) {}
  ~TickLogging() { stop(); }
  TickLogging(const TickLogging&) = delete;
  TickLogging& operator=(const TickLogging&) = delete;

  /// Logs into `r` every `# ticks` line that reads (read_tick_line, checked with its CRC while
  /// checked(): the robot streams `stream ticks <hz> crc`); any other is damaged and dropped
  /// (counted). Unchecked, what a damaged digit left readable is for drop_damaged() to find once
  /// the run is over.
  void start(RunRecord& r) {
    robot_.on_ticks([this, &r](const std::string& line) {
      const std::optional<TickSample> sample = read_tick_line(line, checked_);
      if (!sample) {
        ++dropped_;
        return;
      }
      r.ticks.push_back(*sample);
    });
  }
  void stop() { robot_.on_ticks(nullptr); }
  [[nodiscard]] std::size_t dropped() const { return dropped_; }
  /// Asks for the checked stream at 50 Hz (`stream ticks 50 crc`); a robot whose firmware has no
  /// such form (err) streams unchecked lines (`stream ticks 50`).
  void stream() {
    checked_ = true;
    if (!robot_.command("stream ticks 50 crc").ok) {
      checked_ = false;
      robot_.expect_ok("stream ticks 50");
    }
  }
  /// The same stream asked for again: more lines from a robot in lockstep, whose clock a
  /// question does not move (its lines start again one period later; nothing else changes).
  void ask_again() { robot_.expect_ok(checked_ ? "stream ticks 50 crc" : "stream ticks 50"); }
  [[nodiscard]] bool checked() const { return checked_; }

 private:
  RobotClient& robot_;
  std::size_t dropped_ = 0;
  bool checked_ = false;
};

/// Whether the last two samples show the wheels at rest: the same counts, and (unchecked lines,
/// whose time may have come damaged) at most 100 ms apart in time order, so that a sample damaged
/// into a later time is never the start row every other must come after.
bool at_rest(const std::vector<TickSample>& ticks, bool checked) {
  if (ticks.size() < 2u) {
    return false;
  }
  const TickSample& a = ticks[ticks.size() - 2];
  const TickSample& b = ticks.back();
  return a.count_l == b.count_l && a.count_r == b.count_r &&
         (checked || (b.t_ms > a.t_ms && b.t_ms - a.t_ms <= 100.0));
}

/// Whether the run is over although its `# done` did not come (lost or damaged on the line): the
/// robot idle and its latest trial a new one.
bool over_without_done(Context& c) {
  const Reply status = c.robot.status();
  if (!status.ok || status.pairs.count("mode") == 0u || status.pairs.at("mode") != "idle") {
    return false;
  }
  const Reply trial = c.robot.query("trial");
  const auto number = trial.ok && trial.pairs.count("trial") != 0u
                          ? toolkit::parse_integer(trial.pairs.at("trial"))
                          : std::nullopt;
  return number && *number > c.last_trial;
}

/// Waits for the run's `# done` (within `timeout_s`), showing progress on a terminal. Every few
/// seconds without it, asks whether the run is over (its `# done` may have been lost).
std::map<std::string, std::string> wait_done(Context& c, double expected_s) {
  const double timeout_s = 30.0 + 3.0 * expected_s;
  const auto started = std::chrono::steady_clock::now();
  std::map<std::string, std::string> done;
  int polls = 0;
  for (;;) {
    done = c.robot.poll_done(c.options.progress ? 2000 : 500);
    if (!done.empty()) {
      break;
    }
    if (++polls % (c.options.progress ? 2 : 6) == 0 && over_without_done(c)) {
      done = {{"done", "1"}};
      break;
    }
    const double elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (elapsed_s > timeout_s) {
      throw LinkError(fmt::format("the run did not end (no '# done') within {:.0f} s", timeout_s));
    }
    if (c.options.progress) {
      c.log << fmt::format("\r  driving: {:.0f} s of about {:.0f} s ", elapsed_s, expected_s)
            << std::flush;
    }
  }
  if (c.options.progress) {
    c.log << "\r" << std::string(40, ' ') << "\r";
  }
  return done;
}

/// Whether a run's measurement needs its heading: the self-test's (which way the robot turned
/// tells the fault) and a turn in place's (the heading is all it shows).
bool heading_needed(const RunRecord& r, const std::optional<drive::Path>& path) {
  if (r.label.rfind("selftest", 0) == 0) {
    return true;
  }
  return path && path->count == 1 && path->segments[0].distance_m == 0.0f &&
         path->segments[0].angle_rad != 0.0f;
}

/// A logged run's end row: the start row's counts plus what the trial moved, at `t_ms`.
TickSample end_row(const TickSample& first, const RunRecord& r, double t_ms) {
  TickSample end{t_ms, 0, 0};
  if (__builtin_add_overflow(first.count_l, r.count_l, &end.count_l) ||
      __builtin_add_overflow(first.count_r, r.count_r, &end.count_r)) {
    throw LinkError(
        fmt::format("the run's counts go beyond 64 bits (start row {} {}, trial {} "
                    "{}): damaged replies?",
                    first.count_l, first.count_r, r.count_l, r.count_r));
  }
  return end;
}

}  // namespace

void check_replayed_ticks(const RunRecord& r, std::size_t number, const std::string& file) {
  bool in_order = r.ticks.size() >= 2u && std::isfinite(r.ticks.front().t_ms);
  for (std::size_t i = 1; in_order && i < r.ticks.size(); ++i) {
    in_order = std::isfinite(r.ticks[i].t_ms) && r.ticks[i - 1].t_ms <= r.ticks[i].t_ms;
  }
  if (!in_order) {
    throw InputError(file, 0, "runs",
                     fmt::format("run {} ({}) is a logged run without a tick log in time order "
                                 "(its `ticks` need two or more [t_ms, count_l, count_r] rows, "
                                 "t_ms never decreasing)",
                                 number, r.label));
  }
}

/// `trial` into `r` (asked until two answers agree), checked against the `# done` line: a `trial`
/// that is not newer than the last run's is another run's; a `# done` whose number differs from a
/// newer one's was damaged on the line.
void read_trial(RobotClient& robot, const std::map<std::string, std::string>& done, RunRecord& r,
                std::int64_t last_trial) {
  const Reply trial = robot.query("trial");
  if (!trial.ok) {
    throw LinkError("robot refused 'trial': err " + trial.code + " " + trial.message);
  }
  r.trial = whole(trial, "trial");
  r.path = trial.text("path");
  // A path is a name the robot gives (letters, digits, '-' and '_'): anything else came damaged.
  for (const char ch : r.path) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') {
      throw LinkError("'trial' reply with a damaged path name: '" + trial.line + "'");
    }
  }
  const auto done_trial = done.find("trial");
  if (done_trial != done.end() && done_trial->second != std::to_string(r.trial) &&
      r.trial <= last_trial) {
    throw LinkError("'# done trial=" + done_trial->second + "' but 'trial' reports trial " +
                    std::to_string(r.trial));
  }
  r.duration_ms = trial.number("duration_ms");
  r.count_l = whole(trial, "count_l");
  r.count_r = whole(trial, "count_r");
  r.odom.x_mm = trial.number("x_mm");
  r.odom.y_mm = trial.number("y_mm");
  r.odom.theta_deg = trial.number("theta_deg");
}

SessionPose Context::measure(const RunRecord& r, std::size_t index, const Factors& in_force) {
  ReadingFacts facts;
  facts.odom = r.odom;
  const std::optional<drive::Path> path = r.motion.path();
  if (path) {
    const drive::model::Geometry<double> g =
        geometry_in_force(in_force, get(ParamId::wheel_diameter_mm));
    facts.allowance = allowance_of(*path, g);
    facts.extent = extent_of(*path);
    facts.extent.wheelbase_mm = g.wheelbase;
  }
  facts.heading_needed = heading_needed(r, path);
  // Runs a jury judges are checked against what all the others predict (run_jury.hpp); the
  // others against the repeats of their command.
  for (std::size_t i = 0; i < runs.size() && jury == nullptr; ++i) {
    // The same run: the same command for the same purpose (the extended UMBmark's runs over
    // cables repeat its bump-free squares' command, not their conditions).
    if (runs[i].motion == r.motion && runs[i].label == r.label && path) {
      const std::optional<Factors>& then = i < run_factors.size() ? run_factors[i] : std::nullopt;
      const bool same = then && *then == in_force;
      facts.earlier.push_back(EarlierReading{runs[i].odom, runs[i].measured, same});
    }
  }
  ReadingCheck check = [facts](const SessionPose& pose, const std::string& typed) {
    return judge_reading(facts, pose, typed);
  };
  if (jury != nullptr) {
    check = jury->check_for(r, check);
  }
  const bool checked = source.check_next(check, facts.heading_needed);
  const SessionPose pose = source.take(r, index, planned);
  if (checked) {
    return pose;
  }
  const ReadingVerdict verdict = check(pose, std::string());
  if (verdict.plausible) {
    return pose;
  }
  if (!source.by_hand()) {
    log << fmt::format("  (note: the reading check questions {}'s reading of run {}: {})\n",
                       source.describe(), index + 1, verdict.problem);
    return pose;
  }
  log << fmt::format("Run {}'s reading from {}:\n", index + 1, source.describe())
      << verdict.explained();
  if (!ask_yes_no(*this, fmt::format("Take run {}'s reading from {} as it is?", index + 1,
                                     source.describe()))) {
    throw InputError(source.describe(), 0, "",
                     fmt::format("run {}: {} (correct the reading and give the file again, or "
                                 "--resume with measurements.csv corrected)",
                                 index + 1, verdict.problem));
  }
  return pose;
}

void Context::start_motion(const Motion& motion) {
  const std::string command = motion.command();
  for (int attempt = 0; attempt < 3; ++attempt) {
    const Reply reply = robot.command(command);
    if (reply.ok) {
      return;
    }
    if (reply.code != "garbled") {
      throw LinkError("robot refused '" + command + "': err " + reply.code + " " + reply.message);
    }
    // The reply came damaged: the robot moving, or a new trial already over, says it took it.
    const Reply status = robot.status();
    if (status.ok && status.pairs.count("mode") != 0u && status.pairs.at("mode") != "idle") {
      return;
    }
    const Reply trial = robot.query("trial");
    const auto number = trial.ok && trial.pairs.count("trial") != 0u
                            ? toolkit::parse_integer(trial.pairs.at("trial"))
                            : std::nullopt;
    if (number && *number > last_trial) {
      return;
    }
  }
  throw LinkError("the replies to '" + command + "' kept coming damaged on the line");
}

void Context::note_latest_trial() {
  if (!source.drives_between_runs()) {
    return;  // nothing drives between runs: the last run's trial is the latest
  }
  const Reply trial = robot.query("trial");
  if (!trial.ok && trial.code == "no_trial") {
    return;  // none yet
  }
  const auto number = trial.ok && trial.pairs.count("trial") != 0u
                          ? toolkit::parse_integer(trial.pairs.at("trial"))
                          : std::nullopt;
  if (!number) {
    // Without it a look's trial could be taken for the run's own: no run on a guess.
    throw LinkError("the robot's latest trial before a run: '" + trial.line + "'");
  }
  last_trial = std::max(last_trial, *number);
}

void Context::check_still_up(std::size_t index) {
  // The control tick counts up from power-up (1 kHz: 49 days to wrap its 32 bits); between two
  // runs it has moved on. Back or still: the robot restarted, if the count says so again (a
  // digit lost on the line can make it look smaller once).
  std::optional<std::int64_t> ticks;
  for (int asked = 0; asked < 3; ++asked) {
    const Reply status = robot.status();
    ticks = status.pairs.count("ticks") != 0u ? toolkit::parse_integer(status.text("ticks"))
                                              : std::nullopt;
    if (!ticks || !last_ticks || *ticks > *last_ticks || *last_ticks >= 4000000000LL) {
      break;
    }
    if (asked == 2) {
      robot.forget_parameters();  // what it held in RAM is gone
      throw RobotRestarted(
          fmt::format("the robot restarted before run {}: its tick count went back from {} to {}",
                      index + 1, *last_ticks, *ticks));
    }
  }
  if (ticks) {
    last_ticks = *ticks;  // firmware that does not count its ticks: the start-up line alone
  }
}

RunRecord Context::drive_legs(const std::vector<Motion>& then, double expected_s,
                              std::map<std::string, std::string>& done) {
  // Each after the one before is over; the counts and the time of their trials add up (the
  // odometry runs on from the one `odom reset`).
  RunRecord legs;
  for (const Motion& next : then) {
    RunRecord leg;
    read_trial(robot, done, leg, last_trial);
    last_trial = leg.trial;
    legs.count_l += leg.count_l;
    legs.count_r += leg.count_r;
    legs.duration_ms += leg.duration_ms;
    start_motion(next);
    done = wait_done(*this, expected_s);
  }
  return legs;
}

std::string command_of(const RunRecord& r) {
  std::string out = r.motion.command();
  for (const Motion& next : r.then) {
    out += "; " + next.command();
  }
  return out;
}

RunRecord Context::run(const std::string& label, const Motion& motion, double expected_s,
                       bool log_ticks, const std::vector<Motion>& then) {
  const std::size_t index = runs.size();
  planned = std::max(planned, index + 1);
  if (index < options.replay.size()) {
    // --resume: this run was driven and measured before the interruption.
    RunRecord r = options.replay[index];
    if (r.motion != motion || r.label != label) {
      throw InputError(
          options.out_dir + "/session.json", 0, "runs",
          fmt::format("run {} was '{}' ({}), this session would drive '{}' ({}): "
                      "the interrupted session ran with other settings",
                      index + 1, r.motion.command(), r.label, motion.command(), label));
    }
    if (log_ticks) {
      check_replayed_ticks(r, index + 1, options.out_dir + "/session.json");
    }
    r.replayed = true;
    run_factors.emplace_back(std::nullopt);
    log << fmt::format("Run {}/{}: {} - measured before the interruption, not driven again\n",
                       index + 1, planned, label);
    runs.push_back(r);
    return r;
  }
  ask_to_place(index, label);
  check_still_up(index);
  note_latest_trial();
  RunRecord r;
  r.label = label;
  r.motion = motion;
  r.then = then;
  robot.expect_ok("odom reset");
  TickLogging logging(robot);
  if (log_ticks) {
    logging.start(r);
    logging.stream();
    // The start row: the counts before the motion, read twice alike (the robot stands still), so
    // that a sample damaged on the line is never the count every other rests on.
    wait_tick(
        robot, r.ticks, 0, [&logging] { return logging.dropped(); },
        [&logging] { logging.ask_again(); });
    int asked = 0;
    while (!at_rest(r.ticks, logging.checked())) {
      if (r.ticks.size() > 50u || ++asked > 200) {
        throw LinkError(
            "the robot's counts did not stand still before the run (50 tick lines, no two "
            "alike): is a wheel turning, or is the line that noisy?");
      }
      // Another sample: waited for, and asked for again when it does not come (a robot in
      // lockstep moves its clock only for lines that change something).
      const std::size_t have = r.ticks.size();
      if (!robot.pump(300) || r.ticks.size() == have) {
        logging.ask_again();
      }
    }
    r.ticks.erase(r.ticks.begin(), r.ticks.end() - 1);
  }
  log << fmt::format("Run {}/{}: {} ({})\n", index + 1, planned, label, command_of(r));
  start_motion(motion);
  std::map<std::string, std::string> done = wait_done(*this, expected_s);
  const RunRecord legs = drive_legs(then, expected_s, done);
  if (log_ticks) {
    robot.expect_ok("stream off");
    logging.stop();
  }
  read_trial(robot, done, r, last_trial);
  last_trial = r.trial;
  r.count_l += legs.count_l;
  r.count_r += legs.count_r;
  r.duration_ms += legs.duration_ms;
  if (log_ticks) {
    // The end row at rest: the start row's counts plus what the trial moved (the robot stood
    // still from the start row to the motion), so no wait for a stream line after `# done`.
    // On a line known to damage bytes (lines that did not read), the samples that still read are
    // checked for damage too, before the end row (which rests on the first) and again after it
    // (the last sample is then between two); on a clean line a stop's braking is not a jump.
    const bool noisy = !logging.checked() && (robot.garbled_lines() > 0u || logging.dropped() > 0u);
    std::size_t damaged = logging.dropped() + (noisy ? drop_damaged(r.ticks) : 0u);
    const TickSample first = r.ticks.front();
    const double end_ms = std::max(r.ticks.back().t_ms + 20.0, first.t_ms + r.duration_ms);
    r.ticks.push_back(end_row(first, r, end_ms));
    damaged += noisy ? drop_damaged(r.ticks) : 0u;
    if (damaged > 0u) {
      log << fmt::format("  ({} of the run's tick lines came damaged on the line: dropped)\n",
                         damaged);
    }
  }
  const Factors in_force = factors();
  r.measured = measure(r, index, in_force);
  run_factors.emplace_back(in_force);
  log << fmt::format(
      "  run {} {} (trial {}, {:.1f} s): odometry {:.1f}, {:.1f} mm; measured {:.1f}, {:.1f} mm\n",
      runs.size() + 1, label, r.trial, r.duration_ms / 1000.0, plain(r.odom.x_mm),
      plain(r.odom.y_mm), plain(r.measured.x_mm), plain(r.measured.y_mm));
  runs.push_back(r);
  journal(r, runs.size());
  write_session_json(false, partial, false, false);
  return r;
}

}  // namespace odocal::host::session
