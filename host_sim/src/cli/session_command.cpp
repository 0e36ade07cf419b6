#include "odocal/host/session_command.hpp"

#include <signal.h>
#include <unistd.h>

#include <csignal>

#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "odocal/host/csv.hpp"
#include "odocal/host/robot_link.hpp"
#include "odocal/host/session.hpp"
#include "odocal/toolkit/cli_checks.hpp"

namespace odocal::host {
namespace {

/// The robot's console, for the interrupt handler: Ctrl-C stops the robot before odocal exits.
volatile std::sig_atomic_t console_fd = -1;

extern "C" void stop_robot_and_exit(int) {
  static const char stop[] = "\x03stop\n";
  if (console_fd >= 0) {
    static_cast<void>(::write(console_fd, stop, sizeof stop - 1));
  }
  static const char note[] =
      "\nodocal session: interrupted; sent 'stop' to the robot, nothing saved\n";
  static_cast<void>(::write(STDERR_FILENO, note, sizeof note - 1));
  ::_exit(130);
}

struct SessionFlags {
  std::string port;
  std::uint64_t baud = 115200;
  std::string sim_robot;
  std::uint64_t seed = 1;
  std::string store;
  std::string procedure;
  std::optional<double> side_m;
  std::optional<std::uint64_t> runs;
  std::string measurements;
  bool yes = false;
  bool json = false;
  std::string out;
};

Procedure procedure_of(const std::string& name) {
  if (name == "umbmark") {
    return Procedure::umbmark;
  }
  if (name == "lateral") {
    return Procedure::lateral;
  }
  if (name == "fit") {
    return Procedure::fit;
  }
  return Procedure::verify;
}

/// --runs bounds per procedure: UMBmark runs per direction (the robot keeps 16 per direction,
/// the solver needs 2); lateral straight trials (the bootstrap needs 5 rows with the arcs);
/// fit runs; verify runs per scenario.
void check_runs(Procedure procedure, std::uint64_t runs) {
  std::uint64_t lo = 1;
  std::uint64_t hi = 32;
  switch (procedure) {
    case Procedure::umbmark:
      lo = 2;
      hi = 16;
      break;
    case Procedure::lateral:
      lo = 2;
      hi = 28;
      break;
    case Procedure::fit:
      lo = 3;
      hi = 30;
      break;
    case Procedure::verify:
      lo = 1;
      hi = 16;
      break;
  }
  if (runs < lo || runs > hi) {
    throw InputError("--runs", 0, "",
                     "must be a whole number from " + std::to_string(lo) + " to " +
                         std::to_string(hi) + " for --procedure " + to_string(procedure) +
                         ", got " + std::to_string(runs));
  }
}

int run(const SessionFlags& f, const CLI::App& cmd) {
  SessionOptions options;
  options.procedure = procedure_of(f.procedure);
  if (cmd.count("--side-m") != 0u) {
    options.side_m = f.side_m;
  }
  if (f.runs) {
    check_runs(options.procedure, *f.runs);
    options.runs = static_cast<std::size_t>(*f.runs);
  }
  if (!f.store.empty() && f.sim_robot.empty()) {
    throw InputError("--store", 0, "", "only with --sim (a real robot keeps its own store)");
  }
  options.yes = f.yes;
  options.json = f.json;
  options.seed = f.seed;
  options.out_dir = f.out.empty() ? default_out_dir(options.procedure) : f.out;
  options.log = &std::cerr;
  const bool terminal = ::isatty(STDIN_FILENO) == 1;
  options.confirm_in = terminal ? &std::cin : nullptr;

  // Everything that can be checked is checked before anything moves or is written.
  prepare_out_dir(options.out_dir, false);
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
  if (!f.sim_robot.empty()) {
    if (::access(f.sim_robot.c_str(), R_OK) != 0) {
      throw InputError(f.sim_robot, 0, "", "--sim: cannot read the robot file");
    }
    sim = std::make_unique<SimProcess>(sibling_program("odocal-sim"), f.sim_robot, f.seed, f.store);
    channel = &sim->channel();
  } else {
    port = open_serial_port(f.port, static_cast<std::uint32_t>(f.baud));
    channel = port.get();
  }
  console_fd = channel->fd();
  struct sigaction action {};
  action.sa_handler = stop_robot_and_exit;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  RobotClient robot(*channel);
  std::unique_ptr<MeasurementSource> source;
  if (file_source) {
    source = std::move(file_source);
  } else if (sim) {
    source = robot_measurements(robot);
  } else {
    source = prompt_measurements(std::cin, std::cerr, !terminal);
  }
  prepare_out_dir(options.out_dir, true);
  const SessionReport report = run_session(robot, *source, options);
  if (f.json) {
    std::cout << report.json.dump(2) << "\n";
  } else {
    std::cout << report.text;
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
  cmd->add_option("--procedure", flags->procedure, "umbmark, lateral, fit or verify")
      ->required()
      ->check(CLI::IsMember({"umbmark", "lateral", "fit", "verify"}));
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
                  "CSV x_mm,y_mm[,theta_deg]: the measured stop point of each run, in order "
                  "(default: --sim measures, else you are asked)");
  cmd->add_flag("--yes", flags->yes, "save the result on the robot without asking");
  cmd->add_flag("--json", flags->json, "print the session JSON on stdout");
  cmd->add_option("--out", flags->out,
                  "directory for the CSVs, tick logs, session.json and runs.svg (created; one "
                  "that already holds a session.json is refused)");
  cmd->callback([flags, cmd, &exit_code] {
    if (flags->port.empty() && flags->sim_robot.empty()) {
      std::cerr << "odocal session: give --port DEV (a robot) or --sim ROBOT.json (odocal-sim)\n";
      exit_code = 2;
      return;
    }
    try {
      exit_code = run(*flags, *cmd);
    } catch (const std::exception& e) {
      std::cerr << "odocal session: " << e.what() << '\n';
      exit_code = 2;
    }
  });
}

}  // namespace odocal::host
