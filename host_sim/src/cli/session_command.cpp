#include "odocal/host/session_command.hpp"

#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <csignal>

#include <cstdint>
#include <ctime>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "odocal/host/bridge_console.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/robot_client.hpp"
#include "odocal/host/serial_port.hpp"
#include "odocal/host/session.hpp"
#include "odocal/host/sim_process.hpp"
#include "odocal/toolkit/cli_checks.hpp"
#include "session_flags.hpp"

namespace odocal::host {
namespace {

/// The robot's console, for the interrupt handler: Ctrl-C stops the robot at once.
volatile std::sig_atomic_t console_fd = -1;
/// The console is ROSArduinoBridge's: its stop is `m 0 0` ended by a CR.
volatile std::sig_atomic_t bridge_console = 0;

extern "C" void on_interrupt(int signal_number) {
  static const char stop[] = "\x03stop\n";
  static const char bridge_stop[] = "\rm 0 0\r";
  if (console_fd >= 0 && bridge_console != 0) {
    static_cast<void>(::write(console_fd, bridge_stop, sizeof bridge_stop - 1));
  } else if (console_fd >= 0) {
    static_cast<void>(::write(console_fd, stop, sizeof stop - 1));
  }
  if (interrupt_signal() != 0) {
    // A second Ctrl-C while the first is being handled: quit now.
    static const char note[] =
        "\nodocal session: interrupted again; quitting at once (the robot was sent 'stop'; "
        "nothing was saved)\n";
    static_cast<void>(::write(STDERR_FILENO, note, sizeof note - 1));
    ::_exit(130);
  }
  // The session notices at its next read or wait, stops the robot and puts its factors back.
  note_interrupt(signal_number);
}

struct SessionFlags {
  std::string resume;
  bool no_wait = false;
  bool exact = false;
  std::optional<std::uint64_t> passes;
  std::string port;
  std::uint64_t baud = 115200;
  std::string sim_robot;
  std::uint64_t seed = 1;
  std::string store;
  std::string procedure;
  std::optional<double> side_m;
  std::optional<double> target_mm;
  std::optional<std::uint64_t> max_measurements;
  std::optional<std::uint64_t> runs;
  std::string measurements;
  bool yes = false;
  bool json = false;
  std::string out;
  std::string protocol = "odocal";
  std::optional<double> wheel_diameter_mm;
  std::optional<double> wheelbase_mm;
  std::optional<double> counts_per_rev;
  RosFlags ros;
  std::string truth =
      "tape";        ///< --truth: tape (a person, a file or odocal-sim's measure) or walls
  std::string maze;  ///< --maze: with --truth walls and --port (practice or a file)
};

bool bridge_protocol(const SessionFlags& f) {
  return f.protocol == kBridgeProtocol;
}

/// An absolute form of a path given on the command line (session.json keeps these, so that
/// --resume works from another directory).
std::string absolute(const std::string& path) {
  if (path.empty() || path[0] == '/') {
    return path;
  }
  char here[4096];
  if (::getcwd(here, sizeof here) == nullptr) {
    return path;
  }
  return std::string(here) + "/" + path;
}

/// What session.json records of the options, for --resume.
nlohmann::json recorded_options(const SessionFlags& f) {
  nlohmann::json recorded = {
      {"procedure", f.procedure},
      {"side_m", f.side_m ? nlohmann::json(*f.side_m) : nlohmann::json(nullptr)},
      {"target_mm", f.target_mm ? nlohmann::json(*f.target_mm) : nlohmann::json(nullptr)},
      {"runs", f.runs ? nlohmann::json(*f.runs) : nlohmann::json(nullptr)},
      {"max_measurements",
       f.max_measurements ? nlohmann::json(*f.max_measurements) : nlohmann::json(nullptr)},
      {"passes", f.passes ? nlohmann::json(*f.passes) : nlohmann::json(nullptr)},
      {"exact", f.exact},
      {"seed", f.seed},
      {"sim", absolute(f.sim_robot)},
      {"store", absolute(f.store)},
      {"measurements", absolute(f.measurements)},
      {"port", f.port},
      {"baud", f.baud},
      {"no_wait", f.no_wait},
      {"protocol", f.protocol},
      {"wheel_diameter_mm",
       f.wheel_diameter_mm ? nlohmann::json(*f.wheel_diameter_mm) : nlohmann::json(nullptr)},
      {"wheelbase_mm", f.wheelbase_mm ? nlohmann::json(*f.wheelbase_mm) : nlohmann::json(nullptr)},
      {"counts_per_rev",
       f.counts_per_rev ? nlohmann::json(*f.counts_per_rev) : nlohmann::json(nullptr)}};
  record_ros_flags(f.ros, recorded);
  recorded["truth"] = f.truth;
  recorded["maze"] = absolute(f.maze);
  return recorded;
}

/// --resume DIR: the options of the interrupted session, with the command line's where they
/// agree. A conflicting option is refused: the result must be the one session's.
SessionFlags resumed_flags(const SessionFlags& given, const CLI::App& cmd,
                           nlohmann::json& session) {
  const std::string file = given.resume + "/session.json";
  session = interrupted_session(file);
  const nlohmann::json& o = session["options"];
  SessionFlags f = given;
  const auto conflict = [&](const char* flag, const std::string& recorded,
                            const std::string& typed) {
    throw InputError(flag, 0, "",
                     "conflicts with the interrupted session in " + given.resume +
                         " (it ran with " + (recorded.empty() ? std::string("none") : recorded) +
                         ", given " + typed + "); leave it out to resume");
  };
  try {
    const auto text = [&](const char* flag, const char* key, std::string& value) {
      const std::string recorded = o.at(key).get<std::string>();
      if (cmd.count(flag) != 0u && absolute(value) != recorded && value != recorded) {
        conflict(flag, recorded, value);
      }
      value = recorded;
    };
    text("--procedure", "procedure", f.procedure);
    static_cast<void>(procedure_of(f.procedure, file, "options.procedure"));
    text("--sim", "sim", f.sim_robot);
    text("--store", "store", f.store);
    text("--measurements", "measurements", f.measurements);
    if (o.value("truth", std::string("tape")) == "walls") {
      throw InputError(file, 0, "options.truth",
                       "a session calibrated by the walls is not resumed: the robot's place in "
                       "the maze went with it; start a new one (nothing was saved)");
    }
    // The port may be another device name after a replug: taken as given.
    if (cmd.count("--port") == 0u) {
      f.port = o.at("port").get<std::string>();
    }
    if (cmd.count("--baud") == 0u) {
      f.baud = count_in(o, "baud", file);
    }
    const auto real = [&](const char* flag, const char* key, std::optional<double>& value) {
      // Sessions from before --target have no target_mm: none was given.
      const std::optional<double> recorded = !o.contains(key) || o.at(key).is_null()
                                                 ? std::nullopt
                                                 : std::optional<double>(o.at(key).get<double>());
      if (cmd.count(flag) != 0u && value != recorded) {
        conflict(flag, recorded ? std::to_string(*recorded) : "", std::to_string(*value));
      }
      value = recorded;
    };
    real("--side-m", "side_m", f.side_m);
    real("--target", "target_mm", f.target_mm);
    real("--wheel-diameter-mm", "wheel_diameter_mm", f.wheel_diameter_mm);
    real("--wheelbase-mm", "wheelbase_mm", f.wheelbase_mm);
    real("--counts-per-rev", "counts_per_rev", f.counts_per_rev);
    // Sessions from before --protocol ran on odocal firmware.
    const std::string protocol = o.value("protocol", std::string("odocal"));
    if (cmd.count("--protocol") != 0u && f.protocol != protocol) {
      conflict("--protocol", protocol, f.protocol);
    }
    f.protocol = protocol;
    resume_ros_flags(o, given.resume, cmd, f.ros);
    const auto whole = [&](const char* flag, const char* key, std::optional<std::uint64_t>& value) {
      // Sessions from before --max-measurements have no such key: none was given.
      const std::optional<std::uint64_t> recorded =
          !o.contains(key) || o.at(key).is_null()
              ? std::nullopt
              : std::optional<std::uint64_t>(count_in(o, key, file));
      if (cmd.count(flag) != 0u && value != recorded) {
        conflict(flag, recorded ? std::to_string(*recorded) : "", std::to_string(*value));
      }
      value = recorded;
    };
    whole("--runs", "runs", f.runs);
    whole("--passes", "passes", f.passes);
    whole("--max-measurements", "max_measurements", f.max_measurements);
    const std::uint64_t seed = count_in(o, "seed", file);
    if (cmd.count("--seed") != 0u && f.seed != seed) {
      conflict("--seed", std::to_string(seed), std::to_string(f.seed));
    }
    f.seed = seed;
    const bool exact = o.at("exact").get<bool>();
    if (cmd.count("--exact") != 0u && !exact) {
      conflict("--exact", "no --exact", "--exact");
    }
    f.exact = exact;
    if (cmd.count("--no-wait") == 0u) {
      f.no_wait = o.at("no_wait").get<bool>();
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, 0, "options", e.what());
  }
  if (cmd.count("--out") != 0u && f.out != given.resume) {
    throw InputError(
        "--out", 0, "",
        "--resume continues in its own directory (" + given.resume + "); leave --out out");
  }
  f.out = given.resume;
  return f;
}

/// The session's options from its flags, each checked against the procedure (InputError).
SessionOptions options_of(const SessionFlags& f) {
  if (f.port.empty() && f.sim_robot.empty()) {
    throw InputError("--port", 0, "", "give --port DEV (a robot) or --sim ROBOT.json (odocal-sim)");
  }
  if (f.procedure.empty()) {
    throw InputError("--procedure", 0, "",
                     "--procedure is required (" + procedure_names() + "), or --resume DIR");
  }
  SessionOptions options;
  options.procedure = procedure_of(f.procedure);
  options.side_m = f.side_m;
  if (f.side_m && options.procedure == Procedure::verify) {
    throw InputError("--side-m", 0, "",
                     "verify drives the fixed unseen path (100 cm square, triangle, 80 cm "
                     "semicircle); --side-m does not apply");
  }
  if (f.runs && options.procedure == Procedure::automatic) {
    throw InputError("--runs", 0, "",
                     "--procedure auto chooses its runs; use --target to ask for more or less "
                     "precision and --max-measurements to bound them");
  }
  if (f.runs) {
    check_runs(options.procedure, *f.runs);
    options.runs = static_cast<std::size_t>(*f.runs);
  }
  if (f.passes) {
    if (options.procedure != Procedure::umbmark) {
      throw InputError("--passes", 0, "", "only for --procedure umbmark");
    }
    options.passes = static_cast<std::size_t>(*f.passes);
  }
  if (f.max_measurements) {
    if (options.procedure != Procedure::automatic) {
      throw InputError("--max-measurements", 0, "", "only for --procedure auto");
    }
    options.max_measurements = static_cast<std::size_t>(*f.max_measurements);
  }
  if (f.target_mm) {
    if (options.procedure != Procedure::automatic) {
      throw InputError("--target", 0, "", "only for --procedure auto");
    }
    options.target_mm = f.target_mm;
  }
  if (f.exact) {
    if (options.procedure != Procedure::umbmark) {
      throw InputError("--exact", 0, "", "only for --procedure umbmark");
    }
    options.exact = true;
  }
  if (!f.store.empty() && f.sim_robot.empty()) {
    throw InputError("--store", 0, "", "only with --sim (a real robot keeps its own store)");
  }
  check_bridge_flags(BridgeFlags{f.protocol, f.sim_robot, f.store, f.wheel_diameter_mm,
                                 f.wheelbase_mm, f.counts_per_rev},
                     options.procedure);
  if (bridge_protocol(f) && options.procedure == Procedure::automatic && !f.max_measurements) {
    options.max_measurements = kBridgeMaxMeasurements;
  }
  options.yes = f.yes;
  options.json = f.json;
  options.seed = f.seed;
  options.out_dir = f.out.empty() ? default_out_dir(options.procedure) : f.out;
  options.log = &std::cerr;
  options.recorded = recorded_options(f);
  options.ros_velocity = ros_estimate(f.ros);
  if (check_walls_flags(WallsFlags{f.truth, f.maze, f.sim_robot}, options.procedure,
                        !f.measurements.empty(), bridge_protocol(f))) {
    options.walls.emplace();  // filled in by run(), once the robot file is known
  }
  options.started_unix_s = static_cast<std::uint64_t>(std::time(nullptr));
  const bool terminal = ::isatty(STDIN_FILENO) == 1;
  options.confirm_in = terminal ? &std::cin : nullptr;
  options.start_in = f.sim_robot.empty() && !f.no_wait ? &std::cin : nullptr;
  options.progress = ::isatty(STDERR_FILENO) == 1;
  return options;
}

int run(const SessionFlags& given, const CLI::App& cmd) {
  nlohmann::json interrupted;
  const SessionFlags f = given.resume.empty() ? given : resumed_flags(given, cmd, interrupted);
  SessionOptions options = options_of(f);
  const bool terminal = options.confirm_in != nullptr;
  // Everything that can be checked is checked before anything moves or is written.
  if (given.resume.empty()) {
    prepare_out_dir(options.out_dir, false);
  } else {
    options.replay = recorded_runs(interrupted, options.out_dir);
    for (const std::string& line : take_edited_journal(options.replay, options.out_dir)) {
      std::cerr << "Resume: " << line << "\n";
    }
    if (interrupted.contains("result") && interrupted["result"].is_object()) {
      options.resumed_result = interrupted["result"];
    }
    if (interrupted.contains("date") && interrupted["date"].is_number_unsigned()) {
      options.started_unix_s = interrupted["date"].get<std::uint64_t>();
    }
  }
  std::unique_ptr<MeasurementSource> file_source;
  if (!f.measurements.empty()) {
    file_source = file_measurements(f.measurements);
    const std::size_t needed = planned_runs(options);
    if (file_source->available(0) < needed) {
      throw InputError(f.measurements, 0, "",
                       "too few rows: --procedure " + f.procedure + " needs " +
                           std::to_string(needed) + " measurements, the file has " +
                           std::to_string(file_source->available(0)) + " (nothing was run)");
    }
  }
  std::unique_ptr<SimProcess> sim;
  std::unique_ptr<FdChannel> port;
  FdChannel* channel = nullptr;
  std::string sim_file = f.sim_robot;
  if (!f.sim_robot.empty() && ::access(f.sim_robot.c_str(), R_OK) != 0) {
    throw InputError(f.sim_robot, 0, "", "--sim: cannot read the robot file");
  }
  if (options.walls) {
    if (!f.sim_robot.empty()) {
      prepare_out_dir(options.out_dir, true);
      sim_file = walls_robot_file(f.sim_robot, options.out_dir);
    }
    options.walls = maze_knowledge(WallsFlags{f.truth, f.maze, f.sim_robot}, sim_file);
  }
  if (!f.sim_robot.empty()) {
    sim = std::make_unique<SimProcess>(sibling_program("odocal-sim"), sim_file, f.seed, f.store,
                                       bridge_protocol(f) ? f.protocol : std::string());
    channel = &sim->channel();
  } else {
    port = open_serial_port(f.port, static_cast<std::uint32_t>(f.baud));
    channel = port.get();
  }
  console_fd = channel->fd();
  bridge_console = bridge_protocol(f) ? 1 : 0;
  std::unique_ptr<BridgeConsole> bridge;
  if (bridge_protocol(f)) {
    bridge = std::make_unique<BridgeConsole>(
        *channel,
        bridge_nominal(BridgeFlags{f.protocol, f.sim_robot, f.store, f.wheel_diameter_mm,
                                   f.wheelbase_mm, f.counts_per_rev}),
        sim != nullptr);
    options.bridge = bridge.get();
  }
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  action.sa_flags = 0;  // no SA_RESTART: a blocking read returns, and the session notices
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  RobotClient robot(bridge ? static_cast<LineChannel&>(*bridge) : *channel);
  std::unique_ptr<MeasurementSource> source;
  if (options.walls) {
    // The tape for what the walls cannot tell (the session says when it needs it).
    source = wall_measurements(
        robot, *options.walls, std::cerr,
        sim ? robot_measurements(robot) : prompt_measurements(std::cin, std::cerr, !terminal));
  } else if (file_source) {
    source = std::move(file_source);
  } else if (sim) {
    source = robot_measurements(robot);
  } else {
    source = prompt_measurements(std::cin, std::cerr, !terminal);
  }
  prepare_out_dir(options.out_dir, true);
  const SessionReport report = run_session(robot, *source, options);
  if (f.json) {
    std::cout << report.json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  } else {
    // The result was shown on stderr as it came; on a terminal showing both, once is enough.
    const bool same_screen = ::isatty(STDOUT_FILENO) == 1 && ::isatty(STDERR_FILENO) == 1;
    std::cout << (same_screen ? std::string() : report.result_text) << report.text;
  }
  return 0;
}

}  // namespace

void register_session_command(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<SessionFlags>();
  auto* cmd = app.add_subcommand(
      "session", "run a whole calibration through the robot's console (or odocal-sim)");
  auto* port = cmd->add_option("--port", flags->port, "serial port of the robot's console");
  cmd->add_option("--baud", flags->baud, "baud rate (default 115200)")
      ->check(toolkit::whole_check(9600, 921600))
      ->needs(port);
  auto* sim = cmd->add_option("--sim", flags->sim_robot,
                              "rehearse on odocal-sim with this robot file (JSON; {} for the "
                              "default robot)");
  port->excludes(sim);
  cmd->add_option("--seed", flags->seed, "seed of the simulated robot and the bootstrap")
      ->check(toolkit::whole_check(0u, UINT64_MAX));
  cmd->add_option("--store", flags->store, "odocal-sim's parameter store file (with --sim)");
  cmd->add_option("--protocol", flags->protocol,
                  "the robot's firmware: odocal (default), or ros-arduino-bridge (a ROS robot "
                  "running ROSArduinoBridge: the host drives it, nothing is written to it, the "
                  "result is OUT/diff_drive_controller.yaml; docs/ros.md)")
      ->check(CLI::IsMember({"odocal", "ros-arduino-bridge"}));
  cmd->add_option("--wheel-diameter-mm", flags->wheel_diameter_mm,
                  "ros-arduino-bridge: the robot's nominal wheel diameter, mm")
      ->check(toolkit::range_check(5.0, 1000.0, "mm"));
  cmd->add_option("--wheelbase-mm", flags->wheelbase_mm,
                  "ros-arduino-bridge: the robot's nominal wheelbase (wheel_separation), mm")
      ->check(toolkit::range_check(10.0, 5000.0, "mm"));
  cmd->add_option("--counts-per-rev", flags->counts_per_rev,
                  "ros-arduino-bridge: encoder counts per wheel turn (enc_counts_per_rev)")
      ->check(toolkit::range_check(4.0, 1.0e6, "counts"));
  add_ros_flags(*cmd, flags->ros);
  cmd->add_option("--procedure", flags->procedure,
                  "auto (the one command: self-test, the runs it needs, verify, save), umbmark, "
                  "lateral, fit, verify, extended or selftest")
      ->check(CLI::IsMember(procedure_words()));
  cmd->add_option("--target", flags->target_mm,
                  "auto: measure until the factors leave at most this end error on the unseen "
                  "path, mm (1 sigma; default 2: one tape measurement's error)")
      ->check(toolkit::range_check(0.1, 1000.0, "mm"));
  cmd->add_option("--max-measurements", flags->max_measurements,
                  "auto: every tape measurement the session may take, self-test and "
                  "verification included (default 20; 10 with --truth walls where a tape gives "
                  "the scale; at least 10)")
      ->check(toolkit::whole_check(10u, 1000u));
  cmd->add_option("--resume", flags->resume,
                  "continue the interrupted session in this directory: runs already measured "
                  "are not driven again; options come from its session.json");
  cmd->add_flag("--no-wait", flags->no_wait,
                "with --port: start each run at once instead of waiting for Enter (a rig "
                "that puts the robot back by itself, scripts)");
  cmd->add_flag("--exact", flags->exact,
                "umbmark: always solve the exact square geometry (default: whenever the "
                "small-angle formulas differ from it by more than the measurement noise)");
  cmd->add_option("--passes", flags->passes,
                  "umbmark: passes at most (default 3); another pass runs while E_max,syst >= "
                  "3 SEM")
      ->check(toolkit::whole_check(1u, 10u));
  cmd->add_option(
         "--side-m", flags->side_m,
         "UMBmark square side (default 4), lateral line length (1) or fit line length (1.5), "
         "metres")
      ->check(toolkit::range_check(0.1, 20.0, "m"));
  cmd->add_option("--runs", flags->runs,
                  "runs per direction (umbmark, default 5), straight trials (lateral, 10), runs "
                  "(fit, 6), runs per scenario (verify, 5)")
      ->check(toolkit::whole_check(0u, 1000u));
  cmd->add_option("--measurements", flags->measurements,
                  "CSV x_mm,y_mm[,theta_deg] (or a session's measurements.csv, "
                  "run,x_mm,y_mm,theta_deg): the measured stop point of each run, in order "
                  "(default: --sim measures, else you are asked)");
  add_walls_flags(*cmd, flags->truth, flags->maze, port);
  cmd->add_flag("--yes", flags->yes, "save the result on the robot without asking");
  cmd->add_flag("--json", flags->json, "print the session JSON on stdout");
  cmd->add_option("--out", flags->out,
                  "directory for the CSVs, tick logs, session.json and runs.svg (created; one "
                  "that already holds a session.json is refused)");
  cmd->callback([flags, cmd, &exit_code] {
    try {
      exit_code = run(*flags, *cmd);
    } catch (const SessionEnded& e) {
      exit_code = e.exit_status();  // said on stderr already, with what was put back
    } catch (const Interrupted& e) {
      std::cerr << "odocal session: " << e.what() << " (nothing was running yet)\n";
      exit_code = 130;
    } catch (const std::exception& e) {
      std::cerr << "odocal session: " << e.what() << '\n';
      exit_code = 2;
    }
  });
}

}  // namespace odocal::host
