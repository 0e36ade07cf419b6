// The session engine: the measured-run loop, parameters, output files, apply / save.

#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
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
  return f;
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

RunRecord Context::run(const std::string& label, const std::string& command, double expected_s,
                       bool log_ticks) {
  RunRecord r;
  r.label = label;
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
  robot.expect_ok(command);
  const double timeout_s = 30.0 + 3.0 * expected_s;
  const auto done = robot.wait_done(static_cast<int>(timeout_s * 1000.0));
  const std::size_t before_end = r.ticks.size();
  if (log_ticks) {
    wait_tick(robot, r.ticks, before_end);  // the end row: counts at rest
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
  planned = std::max(planned, runs.size() + 1);
  r.measured = source.take(r, runs.size(), planned);
  log << fmt::format(
      "  run {} {} (trial {}, {:.1f} s): odometry {:.1f}, {:.1f} mm; measured {:.1f}, {:.1f} mm\n",
      runs.size() + 1, label, r.trial, r.duration_ms / 1000.0, r.odom.x_mm, r.odom.y_mm,
      r.measured.x_mm, r.measured.y_mm);
  runs.push_back(r);
  return r;
}

void Context::write_file(const std::string& name, const std::string& content) {
  const std::string path = options.out_dir + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  out.close();
  if (!out) {
    throw InputError(path, 0, "", "cannot write");
  }
  files.push_back(name);
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
    out.push_back(
        {{"trial", r.trial},
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

std::string measurements_csv(const std::vector<RunRecord>& runs) {
  std::ostringstream out;
  out << "# the measured stop points of this session, in run order (--measurements replays them)\n"
         "x_mm,y_mm,theta_deg\n";
  for (const RunRecord& r : runs) {
    char line[160];
    std::snprintf(line, sizeof line, "%.3f,%.3f,", r.measured.x_mm, r.measured.y_mm);
    out << line;
    if (r.measured.theta_deg) {
      std::snprintf(line, sizeof line, "%.3f", *r.measured.theta_deg);
      out << line;
    }
    out << "\n";
  }
  return out.str();
}

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
    if (!std::getline(*options.confirm_in, answer)) {
      log << "\nNot saved (no answer).\n";
      return false;
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

}  // namespace

}  // namespace session

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

  session::Outcome outcome;
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
  }

  bool saved = false;
  if (outcome.applied) {
    if (session::confirmed(options, log)) {
      const Reply reply = robot.expect_ok("save");
      saved = true;
      log << "Saved on the robot (save: " << reply.line << ").\n";
    }
  }
  const session::Factors f = context.factors();
  SessionReport report;
  report.json = {{"procedure", to_string(options.procedure)},
                 {"runs", session::runs_json(context.runs)},
                 {"result", outcome.result},
                 {"applied", outcome.applied},
                 {"saved", saved},
                 {"factors",
                  {{"c_l", f.c_l},
                   {"c_r", f.c_r},
                   {"wheelbase_mm", f.wheelbase_mm},
                   {"f_lat", f.f_lat},
                   {"f_lon", f.f_lon}}}};
  context.write_file("runs.csv", session::runs_csv(context.runs));
  context.write_file("measurements.csv", session::measurements_csv(context.runs));
  context.write_file("runs.svg", session::runs_svg(context.runs, std::string("odocal session ") +
                                                                     to_string(options.procedure)));
  context.write_file("session.json", report.json.dump(2) + "\n");
  std::ostringstream text;
  text << outcome.text
       << fmt::format(
              "Factors in force: c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} f_lat={:.6f} "
              "f_lon={:.6f}",
              f.c_l, f.c_r, f.wheelbase_mm, f.f_lat, f.f_lon)
       << (outcome.applied ? (saved ? " (applied, saved)" : " (applied, NOT saved)")
                           : " (unchanged)")
       << "\nFiles: " << options.out_dir << "/ (session.json, runs.csv, runs.svg, ...)\n";
  report.text = text.str();
  return report;
}

}  // namespace odocal::host
