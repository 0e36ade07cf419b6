// The session engine: the measured-run loop, parameters, output files, apply / save.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "odocal/host/csv.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"

namespace odocal::host {

const char* to_string(Procedure procedure) {
  switch (procedure) {
    case Procedure::umbmark:
      return "umbmark";
    case Procedure::lateral:
      return "lateral";
    case Procedure::fit:
      return "fit";
    case Procedure::verify:
      return "verify";
    case Procedure::extended:
      return "extended";
    case Procedure::selftest:
      return "selftest";
    case Procedure::automatic:
      return "auto";
  }
  return "?";
}

std::string default_out_dir(Procedure procedure) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &utc);
  const std::string base = std::string("odocal-session-") + to_string(procedure) + "-" + stamp;
  // Two sessions in the same second get -2, -3, ...: a default never collides with a session.
  std::string name = base;
  struct stat info {};
  for (int n = 2; ::stat(name.c_str(), &info) == 0; ++n) {
    name = base + "-" + std::to_string(n);
  }
  return name;
}

std::size_t planned_runs(const SessionOptions& options) {
  switch (options.procedure) {
    case Procedure::umbmark:
      return 2 * options.runs.value_or(5);
    case Procedure::lateral:
      return options.runs.value_or(10) + session::lateral_arcs;
    case Procedure::fit:
      return options.runs.value_or(6);
    case Procedure::verify:
      return 2 * options.runs.value_or(5);
    case Procedure::extended:
      return 4 * options.runs.value_or(5);
    case Procedure::selftest:
      return 0;  // a measured run only for a fault the encoders cannot tell apart
    case Procedure::automatic:
      // The first round and the verification; more only when the precision asks for them.
      return session::auto_first_round + session::auto_verify_runs;
  }
  return 0;
}

void prepare_out_dir(const std::string& dir, bool create) {
  if (dir.empty()) {
    throw InputError("--out", 0, "", "empty directory name");
  }
  struct stat info {};
  if (!create) {
    if (::stat(dir.c_str(), &info) == 0 && !S_ISDIR(info.st_mode)) {
      throw InputError(dir, 0, "", "--out: exists and is not a directory");
    }
    if (::stat((dir + "/session.json").c_str(), &info) == 0) {
      throw InputError(dir, 0, "",
                       "--out: already holds a session (session.json); choose a new directory");
    }
    return;
  }
  std::string partial;
  std::size_t at = 0;
  while (at != std::string::npos) {
    at = dir.find('/', at + 1);
    partial = dir.substr(0, at);
    if (partial.empty()) {
      continue;
    }
    if (::mkdir(partial.c_str(), 0777) != 0 && errno != EEXIST) {
      throw InputError(partial, 0, "",
                       std::string("cannot create directory: ") + std::strerror(errno));
    }
  }
  if (::stat(dir.c_str(), &info) != 0 || !S_ISDIR(info.st_mode)) {
    throw InputError(dir, 0, "", "--out: not a directory");
  }
}

namespace session {

double Context::get(const std::string& name) {
  return robot.expect_ok("get " + name).number(name);
}

double Context::set(const std::string& name, double value) {
  char line[96];
  std::snprintf(line, sizeof line, "set %s %.6f", name.c_str(), value);
  return robot.expect_ok(line).number(name);
}

Factors Context::factors() {
  Factors f;
  f.c_l = get("c_l");
  f.c_r = get("c_r");
  f.wheelbase_mm = get("wheelbase_mm");
  f.f_lat = get("f_lat");
  f.f_lon = get("f_lon");
  // Firmware from before the arc wheelbase has no such parameter: 0, one wheelbase.
  const Reply arc = robot.command("get wheelbase_arc_mm");
  f.wheelbase_arc_mm = arc.ok ? arc.number("wheelbase_arc_mm") : 0.0;
  last_factors = f;
  return f;
}

void Context::set_factors(const Factors& f) {
  const bool has_arc = robot.command("get wheelbase_arc_mm").ok;
  if (has_arc) {
    set("wheelbase_arc_mm", 0.0);
  }
  set("c_l", f.c_l);
  set("c_r", f.c_r);
  set("wheelbase_mm", f.wheelbase_mm);
  set("f_lat", f.f_lat);
  set("f_lon", f.f_lon);
  if (has_arc && f.wheelbase_arc_mm != 0.0) {
    set("wheelbase_arc_mm", f.wheelbase_arc_mm);
  }
}

nlohmann::json factors_json(const Factors& f) {
  return {{"c_l", f.c_l},     {"c_r", f.c_r},     {"wheelbase_mm", f.wheelbase_mm},
          {"f_lat", f.f_lat}, {"f_lon", f.f_lon}, {"wheelbase_arc_mm", f.wheelbase_arc_mm}};
}

double plain(double value, int decimals) {
  return std::fabs(value) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : value;
}

std::string count_of(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

double Context::path_seconds(double length_m, double turn_rad, int segments) {
  const double v = get("v_max_mps");
  const double w = get("w_max_radps");
  const double settle_s = get("settle_ms") / 1000.0;
  return length_m / v + turn_rad / w + segments * (settle_s + 1.0);
}

void Context::need_measurements(std::size_t count, const std::string& what) {
  const std::size_t have = source.available(runs.size());
  if (have < count) {
    throw InputError(source.describe(), 0, "",
                     "too few rows: " + what + " need " + std::to_string(count) +
                         " more measurements, the file has " + std::to_string(have) +
                         (runs.empty() ? "" : " left") + " (nothing was run or saved)");
  }
}

namespace {

std::int64_t whole(const Reply& reply, const std::string& key) {
  const std::optional<std::int64_t> value = toolkit::parse_integer(reply.text(key));
  if (!value) {
    throw LinkError("robot reply '" + reply.line + "': " + key + " is not a whole number");
  }
  return *value;
}

/// Waits until `samples` has grown past `count` (a `# ticks` line arrived).
void wait_tick(RobotClient& robot, const std::vector<TickSample>& samples, std::size_t count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (samples.size() <= count) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw LinkError(
          "no '# ticks' line within 10 s after 'stream ticks' (does the firmware "
          "have it?)");
    }
    static_cast<void>(robot.pump(200));
  }
}

}  // namespace

std::uint64_t Context::date() const {
  return options.started_unix_s;
}

RunRecord Context::run(const std::string& label, const std::string& command, double expected_s,
                       bool log_ticks) {
  const std::size_t index = runs.size();
  planned = std::max(planned, index + 1);
  if (index < options.replay.size()) {
    // --resume: this run was driven and measured before the interruption.
    RunRecord r = options.replay[index];
    if (r.command != command || r.label != label) {
      throw InputError(options.out_dir + "/session.json", 0, "runs",
                       fmt::format("run {} was '{}' ({}), this session would drive '{}' ({}): "
                                   "the interrupted session ran with other settings",
                                   index + 1, r.command, r.label, command, label));
    }
    r.replayed = true;
    log << fmt::format("Run {}/{}: {} - measured before the interruption, not driven again\n",
                       index + 1, planned, label);
    runs.push_back(r);
    return r;
  }
  if (options.start_in != nullptr) {
    // The user's moment: nothing that moves the robot is sent before this line.
    log << fmt::format(
               "\nRun {}/{} ({}): put the robot on the start mark, aligned with the start "
               "line, hands off; press Enter to start (Ctrl-C ends the session): ",
               index + 1, planned, label)
        << std::flush;
    std::string line;
    const bool got = static_cast<bool>(std::getline(*options.start_in, line));
    check_interrupt();
    if (got && options.confirm_in == nullptr) {
      log << "\n";  // input from a pipe: the Enter did not show
    }
    if (!got) {
      throw InputError(
          "standard input", 0, "",
          fmt::format("end of input while waiting for Enter before run {}", index + 1));
    }
  }
  RunRecord r;
  r.label = label;
  r.command = command;
  robot.expect_ok("odom reset");
  if (log_ticks) {
    robot.on_ticks([&r](const std::string& line) {
      const auto pairs = hash_line_pairs(line);
      const auto t = pairs.find("t_ms"), l = pairs.find("count_l"), c = pairs.find("count_r");
      if (t == pairs.end() || l == pairs.end() || c == pairs.end()) {
        return;
      }
      const auto tv = toolkit::parse_real(t->second);
      const auto lv = toolkit::parse_integer(l->second), cv = toolkit::parse_integer(c->second);
      if (tv && lv && cv) {
        r.ticks.push_back(TickSample{*tv, *lv, *cv});
      }
    });
    robot.expect_ok("stream ticks 50");
    wait_tick(robot, r.ticks, 0);  // the start row: counts before the motion
  }
  log << fmt::format("Run {}/{}: {} ({})\n", index + 1, planned, label, command);
  robot.expect_ok(command);
  const double timeout_s = 30.0 + 3.0 * expected_s;
  const auto started = std::chrono::steady_clock::now();
  std::map<std::string, std::string> done;
  for (;;) {
    done = robot.poll_done(options.progress ? 2000 : 500);
    if (!done.empty()) {
      break;
    }
    const double elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (elapsed_s > timeout_s) {
      throw LinkError(fmt::format("the run did not end (no '# done') within {:.0f} s", timeout_s));
    }
    if (options.progress) {
      log << fmt::format("\r  driving: {:.0f} s of about {:.0f} s ", elapsed_s, expected_s)
          << std::flush;
    }
  }
  if (options.progress) {
    log << "\r" << std::string(40, ' ') << "\r";
  }
  if (log_ticks) {
    robot.expect_ok("stream off");
    robot.on_ticks(nullptr);
  }
  const Reply trial = robot.expect_ok("trial");
  r.trial = whole(trial, "trial");
  r.path = trial.text("path");
  const auto done_trial = done.find("trial");
  if (done_trial != done.end() && done_trial->second != std::to_string(r.trial)) {
    throw LinkError("'# done trial=" + done_trial->second + "' but 'trial' reports trial " +
                    std::to_string(r.trial));
  }
  r.duration_ms = trial.number("duration_ms");
  r.count_l = whole(trial, "count_l");
  r.count_r = whole(trial, "count_r");
  r.odom.x_mm = trial.number("x_mm");
  r.odom.y_mm = trial.number("y_mm");
  r.odom.theta_deg = trial.number("theta_deg");
  if (log_ticks) {
    // The end row at rest: the start row's counts plus what the trial moved (the robot stood
    // still from the start row to the motion), so no wait for a stream line after `# done`.
    const TickSample first = r.ticks.front();
    const double end_ms = std::max(r.ticks.back().t_ms + 20.0, first.t_ms + r.duration_ms);
    r.ticks.push_back(TickSample{end_ms, first.count_l + r.count_l, first.count_r + r.count_r});
  }
  r.measured = source.take(r, runs.size(), planned);
  log << fmt::format(
      "  run {} {} (trial {}, {:.1f} s): odometry {:.1f}, {:.1f} mm; measured {:.1f}, {:.1f} mm\n",
      runs.size() + 1, label, r.trial, r.duration_ms / 1000.0, plain(r.odom.x_mm),
      plain(r.odom.y_mm), plain(r.measured.x_mm), plain(r.measured.y_mm));
  runs.push_back(r);
  journal(r);
  write_session_json(false, partial, false, false);
  return r;
}

void Context::journal(const RunRecord& r) {
  const std::string path = options.out_dir + "/measurements.csv";
  struct stat info {};
  const bool fresh = ::stat(path.c_str(), &info) != 0 || info.st_size == 0;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  std::string text = fresh ? "run,x_mm,y_mm,theta_deg\n" : "";
  text += fmt::format("{},{:.3f},{:.3f},", runs.size(), r.measured.x_mm, r.measured.y_mm);
  if (r.measured.theta_deg) {
    text += fmt::format("{:.3f}", *r.measured.theta_deg);
  }
  text += "\n";
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  if (std::find(files.begin(), files.end(), "measurements.csv") == files.end()) {
    files.push_back("measurements.csv");
  }
}

void Context::write_session_json(bool complete, const nlohmann::json& result, bool applied,
                                 bool saved, const std::string& interruption) {
  nlohmann::json doc = {{"procedure", to_string(options.procedure)},
                        {"complete", complete},
                        {"date", options.started_unix_s},
                        {"options", options.recorded},
                        {"runs", runs_json(runs)},
                        {"measurements", runs.size()},
                        {"result", result},
                        {"applied", applied},
                        {"saved", saved}};
  if (!interruption.empty()) {
    doc["interrupted"] = interruption;
  }
  if (last_factors) {
    doc["factors"] = factors_json(*last_factors);
  }
  write_file("session.json", doc.dump(2) + "\n");
}

void Context::write_file(const std::string& name, const std::string& content) {
  const std::string path = options.out_dir + "/" + name;
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << content;
    out.close();
    if (!out) {
      throw InputError(path, 0, "", "cannot write");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  if (std::find(files.begin(), files.end(), name) == files.end()) {
    files.push_back(name);
  }
}

std::string runs_csv(const std::vector<RunRecord>& runs) {
  std::ostringstream out;
  out << "trial,label,path,duration_ms,count_l,count_r,odom_x_mm,odom_y_mm,odom_theta_deg,"
         "measured_x_mm,measured_y_mm,measured_theta_deg\n";
  for (const RunRecord& r : runs) {
    char line[512];
    std::snprintf(line, sizeof line, "%lld,%s,%s,%.0f,%lld,%lld,%.3f,%.3f,%.3f,%.3f,%.3f,",
                  static_cast<long long>(r.trial), r.label.c_str(), r.path.c_str(), r.duration_ms,
                  static_cast<long long>(r.count_l), static_cast<long long>(r.count_r), r.odom.x_mm,
                  r.odom.y_mm, r.odom.theta_deg.value_or(0.0), r.measured.x_mm, r.measured.y_mm);
    out << line;
    if (r.measured.theta_deg) {
      std::snprintf(line, sizeof line, "%.3f", *r.measured.theta_deg);
      out << line;
    }
    out << "\n";
  }
  return out.str();
}

nlohmann::json runs_json(const std::vector<RunRecord>& runs) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunRecord& r : runs) {
    const auto theta = [](const std::optional<double>& t) {
      return t ? nlohmann::json(*t) : nlohmann::json(nullptr);
    };
    nlohmann::json ticks = nullptr;
    if (!r.ticks.empty()) {
      ticks = nlohmann::json::array();
      for (const TickSample& t : r.ticks) {
        ticks.push_back({t.t_ms, t.count_l, t.count_r});
      }
    }
    out.push_back(
        {{"label", r.label},
         {"command", r.command},
         {"ticks", ticks},
         {"trial", r.trial},
         {"path", r.path},
         {"duration_ms", static_cast<std::int64_t>(std::llround(r.duration_ms))},
         {"count_l", r.count_l},
         {"count_r", r.count_r},
         {"odom",
          {{"x_mm", r.odom.x_mm}, {"y_mm", r.odom.y_mm}, {"theta_deg", theta(r.odom.theta_deg)}}},
         {"measured",
          {{"x_mm", r.measured.x_mm},
           {"y_mm", r.measured.y_mm},
           {"theta_deg", theta(r.measured.theta_deg)}}}});
  }
  return out;
}

namespace {

/// --yes, or a typed "yes" at the terminal.
bool confirmed(const SessionOptions& options, std::ostream& log) {
  if (options.yes) {
    return true;
  }
  if (options.confirm_in == nullptr) {
    log << "Not saved: no --yes and no terminal to confirm. The factors are in force until the "
           "robot restarts; type 'save' on its console to keep them.\n";
    return false;
  }
  for (;;) {
    log << "Save these factors on the robot? [y/n]: " << std::flush;
    std::string answer;
    const bool got = static_cast<bool>(std::getline(*options.confirm_in, answer));
    check_interrupt();
    if (!got) {
      // No answer is not a yes, and not a no to keep them unsaved: the session ends as if
      // interrupted, and what it applied is taken back.
      throw InputError("standard input", 0, "",
                       "end of input at the question 'Save these factors'");
    }
    while (!answer.empty() && (answer.back() == '\r' || answer.back() == ' ')) {
      answer.pop_back();
    }
    if (answer == "y" || answer == "yes" || answer == "Y") {
      return true;
    }
    if (answer == "n" || answer == "no" || answer == "N") {
      log << "Not saved. The factors are in force until the robot restarts.\n";
      return false;
    }
    log << "Please answer y or n (got '" << answer << "').\n";
  }
}

bool same_value(double a, double b) {
  return std::fabs(a - b) <= 1e-6 * std::max(1.0, std::fabs(b));
}

/// After an interruption: the robot stopped, and every factor the session changed put back to
/// what was in force when it started (the saved set reloaded when nothing was unsaved then, so
/// that its provenance comes back too). Says on `log` what it did; never throws.
void put_back(Context& c, std::ostream& log) {
  try {
    // Replies still on their way (to the interrupted command, to the handler's `stop`) must not
    // be taken for the replies below.
    c.robot.drain(300);
    static_cast<void>(c.robot.command("stop", 2000));
    static_cast<void>(c.robot.command("stream off", 2000));
    c.robot.on_ticks(nullptr);
    Factors now = c.factors();
    const double cruise = c.get("v_max_mps");
    const auto unchanged = [&c](const Factors& f) {
      return same_value(f.c_l, c.initial.c_l) && same_value(f.c_r, c.initial.c_r) &&
             same_value(f.wheelbase_mm, c.initial.wheelbase_mm) &&
             same_value(f.f_lat, c.initial.f_lat) && same_value(f.f_lon, c.initial.f_lon) &&
             same_value(f.wheelbase_arc_mm, c.initial.wheelbase_arc_mm);
    };
    if (unchanged(now) && same_value(cruise, c.initial_cruise_mps)) {
      log << "The robot is stopped; its factors are as they were when the session started.\n";
      return;
    }
    bool reloaded = false;
    if (!c.initial_unsaved) {
      reloaded = c.robot.command("load", 5000).ok;
    }
    if (!reloaded) {
      c.set_factors(c.initial);
      c.set("v_max_mps", c.initial_cruise_mps);
    }
    now = c.factors();
    if (!unchanged(now)) {
      log << "WARNING: could not put the factors back exactly; in force now: "
          << factors_json(now).dump() << "\n";
      return;
    }
    log << fmt::format(
        "The robot is stopped. The factors this session applied and did not save were put back "
        "to what was in force when it started{}: c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} "
        "f_lat={:.6f} f_lon={:.6f}\n",
        reloaded ? " (its saved set, reloaded)" : "", now.c_l, now.c_r, now.wheelbase_mm, now.f_lat,
        now.f_lon);
  } catch (const std::exception& e) {
    log << "WARNING: the robot did not answer while stopping it and putting its factors back ("
        << e.what()
        << "). Nothing was saved: restarting the robot brings back its saved factors.\n";
  }
}

}  // namespace

void write_report(Context& c, const nlohmann::json& result, const std::string& summary,
                  bool complete, bool saved, const std::string& interruption) {
  ReportInput in;
  in.title = std::string("odocal session ") + to_string(c.options.procedure);
  in.date_unix_s = c.date();
  in.complete = complete;
  in.interruption = interruption;
  in.saved = saved;
  in.runs = c.runs;
  in.result = result;
  in.summary = summary;
  in.side_m = c.options.side_m.value_or(4.0);
  try {
    // From the robot when it still answers (after an interruption it may not).
    in.factors = c.last_factors.value_or(c.initial);
    in.wheel_diameter_mm = c.get("wheel_diameter_mm");
    // The wheelbase in force when the session started: the geometry the runs were driven and
    // their odometry computed with (the fit's "before").
    in.wheelbase_mm = c.initial.wheelbase_mm;
    in.counts_per_rev = c.get("counts_per_rev");
    const Reply provenance = c.robot.command("provenance", 2000);
    if (provenance.ok) {
      in.provenance = provenance.pairs;
    }
  } catch (const std::exception&) {
    in.wheelbase_mm = in.factors.wheelbase_mm > 0.0 ? in.factors.wheelbase_mm : in.wheelbase_mm;
  }
  c.write_file("report.html", report_html(in));
}

}  // namespace session

std::vector<RunRecord> recorded_runs(const nlohmann::json& session, const std::string& dir) {
  const std::string file = dir + "/session.json";
  std::vector<RunRecord> runs;
  if (!session.contains("runs") || !session["runs"].is_array()) {
    throw InputError(file, 0, "runs", "missing or not an array");
  }
  std::size_t index = 0;
  for (const nlohmann::json& run : session["runs"]) {
    ++index;
    try {
      RunRecord r;
      r.label = run.at("label").get<std::string>();
      r.command = run.at("command").get<std::string>();
      r.trial = run.at("trial").get<std::int64_t>();
      r.path = run.at("path").get<std::string>();
      r.duration_ms = run.at("duration_ms").get<double>();
      r.count_l = run.at("count_l").get<std::int64_t>();
      r.count_r = run.at("count_r").get<std::int64_t>();
      const auto pose = [](const nlohmann::json& j) {
        SessionPose p;
        p.x_mm = j.at("x_mm").get<double>();
        p.y_mm = j.at("y_mm").get<double>();
        if (!j.at("theta_deg").is_null()) {
          p.theta_deg = j.at("theta_deg").get<double>();
        }
        return p;
      };
      r.odom = pose(run.at("odom"));
      r.measured = pose(run.at("measured"));
      if (run.contains("ticks") && run["ticks"].is_array()) {
        for (const nlohmann::json& t : run["ticks"]) {
          r.ticks.push_back(TickSample{t.at(0).get<double>(), t.at(1).get<std::int64_t>(),
                                       t.at(2).get<std::int64_t>()});
        }
      }
      runs.push_back(r);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file, 0, "runs", "run " + std::to_string(index) + ": " + e.what());
    }
  }
  return runs;
}

SessionReport run_session(RobotClient& robot, MeasurementSource& measurements,
                          const SessionOptions& options) {
  std::ostream& log = options.log != nullptr ? *options.log : std::cerr;
  session::Context context(robot, measurements, options, log);
  // Start from a quiet, idle console: no echo, no streams, no motion from before. A board that
  // resets when its port opens (USB serial) may miss the first line: ask up to three times.
  robot.drain(200);
  for (int attempt = 1;; ++attempt) {
    try {
      static_cast<void>(robot.command("echo off", 2000));
      break;
    } catch (const LinkError&) {
      if (attempt == 3) {
        throw;
      }
      robot.drain(500);
    }
  }
  robot.expect_ok("stop");
  robot.expect_ok("stream off");
  robot.drain(100);
  const Reply version = robot.expect_ok("version");
  log << "odocal session " << to_string(options.procedure) << ": robot " << version.pairs.at("name")
      << " "
      << (version.pairs.count("version") != 0u ? version.pairs.at("version") : std::string("?"))
      << ", measurements from " << measurements.describe() << ", files in " << options.out_dir
      << "\n";
  context.initial = context.factors();
  context.initial_cruise_mps = context.get("v_max_mps");
  context.initial_unsaved = robot.expect_ok("status").text("unsaved") != "0";
  if (!options.replay.empty()) {
    // The journal starts again from the runs taken over, so that a row written just before the
    // interruption for a run that is driven again does not stand twice.
    std::string journal = "run,x_mm,y_mm,theta_deg\n";
    for (std::size_t i = 0; i < options.replay.size(); ++i) {
      const SessionPose& m = options.replay[i].measured;
      journal += fmt::format("{},{:.3f},{:.3f},", i + 1, m.x_mm, m.y_mm);
      if (m.theta_deg) {
        journal += fmt::format("{:.3f}", *m.theta_deg);
      }
      journal += "\n";
    }
    context.write_file("measurements.csv", journal);
  }

  session::Outcome outcome;
  bool saved = false;
  try {
    switch (options.procedure) {
      case Procedure::umbmark:
        outcome = session::run_umbmark(context);
        break;
      case Procedure::lateral:
        outcome = session::run_lateral(context);
        break;
      case Procedure::verify:
        outcome = session::run_verify(context);
        break;
      case Procedure::fit:
        outcome = session::run_fit(context);
        break;
      case Procedure::extended:
        outcome = session::run_extended(context);
        break;
      case Procedure::selftest:
        outcome = session::run_selftest(context);
        break;
      case Procedure::automatic:
        outcome = session::run_auto(context);
        break;
    }
    if (outcome.applied) {
      if (session::confirmed(options, log)) {
        const Reply reply = robot.expect_ok("save");
        saved = true;
        log << "Saved on the robot (save: " << reply.line << ").\n";
      }
    }
  } catch (const std::exception& e) {
    log << "\nodocal session: " << e.what() << "\n";
    session::put_back(context, log);
    try {
      context.write_session_json(false, context.partial, false, false, e.what());
      session::write_report(context, context.partial, "", false, false, e.what());
      log << "What was measured is in " << options.out_dir
          << "/measurements.csv and session.json; continue with: odocal session --resume "
          << options.out_dir << "\n";
    } catch (const std::exception& write_error) {
      log << "WARNING: " << write_error.what() << "\n";
    }
    throw SessionEnded(e.what(), dynamic_cast<const Interrupted*>(&e) != nullptr ? 130 : 2);
  }
  const session::Factors f = context.factors();
  context.write_file("runs.csv", session::runs_csv(context.runs));
  session::write_report(context, outcome.result, outcome.text, true, saved, "");
  context.write_file("runs.svg", session::runs_svg(context.runs, std::string("odocal session ") +
                                                                     to_string(options.procedure)));
  context.write_session_json(true, outcome.result, outcome.applied, saved);
  SessionReport report;
  report.json = nlohmann::json::parse(read_text_file(options.out_dir + "/session.json"));
  report.result_text = outcome.text;
  std::ostringstream text;
  text << fmt::format(
              "Factors in force: c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} f_lat={:.6f} "
              "f_lon={:.6f}",
              f.c_l, f.c_r, f.wheelbase_mm, f.f_lat, f.f_lon)
       << (f.wheelbase_arc_mm != 0.0 ? fmt::format(" wheelbase_arc_mm={:.3f}", f.wheelbase_arc_mm)
                                     : std::string())
       << (outcome.applied ? (saved ? " (applied, saved)" : " (applied, NOT saved)")
                           : " (unchanged)")
       << "\nFiles: " << options.out_dir
       << "/ (report.html, session.json, measurements.csv, runs.csv, runs.svg, ...)\n";
  report.text = text.str();
  return report;
}

}  // namespace odocal::host
