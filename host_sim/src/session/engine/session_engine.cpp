// The session engine: the robot's parameters, the start of a session, its procedure, the save
// and the files of a complete session (the run: session_run.cpp; the files: session_files.cpp;
// the way out: session_exit.cpp).

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "odocal/host/csv.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"

namespace odocal::host {

const char* to_string(Procedure procedure) {
  return info_of(procedure).name;
}

std::optional<Procedure> procedure_named(std::string_view name) {
  for (const ProcedureInfo& p : procedures) {
    if (name == p.name) {
      return p.procedure;
    }
  }
  return std::nullopt;
}

std::string procedure_names() {
  // auto first: the one command most owners want.
  std::string text = info_of(Procedure::automatic).name;
  std::size_t left = std::size(procedures) - 1;
  for (const ProcedureInfo& p : procedures) {
    if (p.procedure != Procedure::automatic) {
      text += (--left == 0 ? " or " : ", ") + std::string(p.name);
    }
  }
  return text;
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
  return session::procedure_steps[static_cast<std::size_t>(options.procedure)].planned(options);
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

double Context::get(ParamId id) {
  const std::string name = params::param_info(id).name;
  const Reply reply = robot.query("get " + name);
  if (!reply.ok) {
    throw LinkError("robot refused 'get " + name + "': err " + reply.code + " " + reply.message);
  }
  return reply.number(name);
}

double Context::set(ParamId id, double value) {
  const std::string name = params::param_info(id).name;
  char line[96];
  std::snprintf(line, sizeof line, "set %s %.6f", name.c_str(), value);
  // The reply is the value as stored: one that is not what was sent came damaged on the line
  // (or the robot stored something else): asked again, then read back to be sure.
  for (int attempt = 0; attempt < 3; ++attempt) {
    const double stored = robot.expect_ok(line).number(name);
    if (std::fabs(stored - value) <= 1e-5 * std::max(1.0, std::fabs(value))) {
      robot.remember(name, stored);
      return stored;
    }
  }
  return get(id);
}

Factors Context::factors() {
  Factors f;
  f.each([this](ParamId id, double& value) {
    // A factor the firmware does not have (one added after it, as the arc wheelbase) is in force
    // at its default: what the robot does without it.
    const std::string name = params::param_info(id).name;
    const Reply reply = robot.query("get " + name);
    if (!reply.ok && reply.code == "unknown_parameter") {
      return;
    }
    value = reply.ok ? reply.number(name) : get(id);
  });
  last_factors = f;
  return f;
}

void Context::set_factors(const Factors& f) {
  // The arc wheelbase must stay within 20 % of wheelbase_mm at every step: cleared first (0, one
  // wheelbase), set last.
  const bool has_arc = robot.query("get wheelbase_arc_mm").ok;
  if (has_arc) {
    set(ParamId::wheelbase_arc_mm, 0.0);
  }
  f.each([&](ParamId id, double value) {
    if (id != ParamId::wheelbase_arc_mm) {
      set(id, value);
    }
  });
  if (has_arc && f.wheelbase_arc_mm != 0.0) {
    set(ParamId::wheelbase_arc_mm, f.wheelbase_arc_mm);
  }
}

nlohmann::json factors_json(const Factors& f) {
  nlohmann::json j = nlohmann::json::object();
  f.each([&j](ParamId id, double value) { j[params::param_info(id).name] = value; });
  return j;
}

double plain(double value, int decimals) {
  return std::fabs(value) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : value;
}

std::string count_of(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

double Context::path_seconds(double length_m, double turn_rad, int segments) {
  const double v = get(ParamId::v_max_mps);
  const double w = get(ParamId::w_max_radps);
  const double settle_s = get(ParamId::settle_ms) / 1000.0;
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

std::uint64_t Context::date() const {
  return options.started_unix_s;
}

namespace {

/// A quiet, idle console: no echo, no streams, no motion from before. A board that resets when
/// its port opens (USB serial) may miss the first line: asked up to three times.
void open_console(RobotClient& robot, MeasurementSource& measurements,
                  const SessionOptions& options, std::ostream& log) {
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
  robot.watch_restarts(true);  // a start-up line from now on is a reset in the session
  const Reply version = robot.query("version");
  if (!version.ok || version.pairs.count("name") == 0u) {
    throw LinkError("robot answered 'version' with '" + version.line +
                    "' (is it an odocal console?)");
  }
  log << "odocal session " << to_string(options.procedure) << ": robot " << version.pairs.at("name")
      << " "
      << (version.pairs.count("version") != 0u ? version.pairs.at("version") : std::string("?"))
      << ", measurements from " << measurements.describe() << ", files in " << options.out_dir
      << "\n";
}

/// What is in force when the session starts: what an interruption puts back.
void note_initial(Context& c) {
  c.initial = c.factors();
  c.initial_cruise_mps = c.get(ParamId::v_max_mps);
  c.initial_unsaved = c.robot.status().text("unsaved") != "0";
  // wiring_fix: noted by the self-test, the one step that changes it.
}

session::Outcome run_procedure(Context& c) {
  return session::procedure_steps[static_cast<std::size_t>(c.options.procedure)].run(c);
}

/// The files of a complete session, and what it says at the end.
SessionReport finish(Context& c, const session::Outcome& outcome, bool saved) {
  const SessionOptions& options = c.options;
  const session::Factors f = c.factors();
  c.write_file("runs.csv", session::runs_csv(c.runs));
  session::write_report(c, outcome.result, outcome.text, true, saved, "");
  c.write_file("runs.svg", session::runs_svg(c.runs, std::string("odocal session ") +
                                                         to_string(options.procedure)));
  SessionReport report;
  report.json = c.write_session_json(true, outcome.result, outcome.applied, saved);
  report.result_text = outcome.text;
  std::ostringstream text;
  text << fmt::format(
              "Factors in force: c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} f_lat={:.6f} "
              "f_lon={:.6f}",
              f.c_l, f.c_r, f.wheelbase_mm, f.f_lat, f.f_lon)
       << (f.wheelbase_arc_mm != 0.0 ? fmt::format(" wheelbase_arc_mm={:.3f}", f.wheelbase_arc_mm)
                                     : std::string())
       << (outcome.applied && options.bridge != nullptr
               ? " (on the host: diff_drive_controller.yaml; nothing written to the robot)"
           : outcome.applied ? (saved ? " (applied, saved)" : " (applied, NOT saved)")
                             : " (unchanged)")
       << fmt::format("\nConsole: {} lines sent to the robot, {} of them `get` ({:.1f} per run)",
                      c.robot.lines_sent(), c.robot.gets_sent(),
                      static_cast<double>(c.robot.gets_sent()) /
                          static_cast<double>(std::max<std::size_t>(c.runs.size(), 1u)))
       << "\nFiles: " << options.out_dir
       << "/ (report.html, session.json, measurements.csv, runs.csv, runs.svg"
       << (outcome.result.contains("ros") ? ", diff_drive_controller.yaml" : "") << ", ...)\n"
       << "Report: " << options.out_dir << "/report.html (open it in a browser)\n";
  report.text = text.str();
  return report;
}

}  // namespace

}  // namespace session

SessionReport run_session(RobotClient& robot, MeasurementSource& measurements,
                          const SessionOptions& options) {
  std::ostream& log = options.log != nullptr ? *options.log : std::cerr;
  if (const char* chatter = std::getenv("ODOCAL_TEST_CHATTER"); chatter != nullptr) {
    // Tests only (session_chatter_test.cpp): a harmless question after every command, to show
    // that what a simulated session measures does not depend on how much it talks.
    robot.chatter(chatter);
  }
  session::Context context(robot, measurements, options, log);
  session::open_console(robot, measurements, options, log);
  session::note_initial(context);
  if (!options.replay.empty()) {
    // The journal starts again from the runs taken over, so that a row written just before the
    // interruption for a run that is driven again does not stand twice.
    context.rewrite_journal();
  }
  session::Outcome outcome;
  bool saved = false;
  try {
    outcome = session::run_procedure(context);
    if (options.bridge != nullptr &&
        (options.procedure == Procedure::automatic || options.procedure == Procedure::fit)) {
      // Nothing is saved on such a robot: the geometry goes to the controller's configuration,
      // also when the runs found nothing to change (the multipliers then confirm it).
      session::write_ros_yaml(context, outcome, false);
    } else {
      if (outcome.applied && session::confirmed(context)) {
        const Reply reply = robot.expect_ok("save");
        saved = true;
        log << "Saved on the robot (save: " << reply.line << ").\n";
      }
      // What ROS needs to drive this robot and read its odometry with the factors in force.
      session::write_ros_yaml(context, outcome, saved);
    }
  } catch (const std::exception& e) {
    session::end_early(context, e);
  }
  return session::finish(context, outcome, saved);
}

}  // namespace odocal::host
