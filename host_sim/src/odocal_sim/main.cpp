// odocal-sim: the robot firmware (control loop + console) on the simulated robot, on the host.
// Console on stdio or a pty, parameters in a file, simulated time at X times real time.

#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "odocal/console/console.hpp"
#include "odocal/host/sim_robot.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/posix/file_block_store.hpp"
#include "odocal/sim/ram_block_store.hpp"
#include "odocal/toolkit/cli_checks.hpp"
#include "sim_app.hpp"

namespace odocal::sim_app {
namespace {

struct Options {
  bool use_pty = false;
  std::string store_file;
  std::string robot_file;
  double speed = 1.0;
  std::uint64_t seed = 1;
  std::string protocol = "odocal";
  double reset_after_s = 0.0;  ///< a reset of the MCU after this much robot time (0: none)
  double corrupt_rate = 0.0;   ///< share of the bytes sent that are lost or garbled
};

/// @return -1 to go on, else the exit status (2 for a refused command line, 0 for --help).
int parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"odocal-sim: the odocal firmware on a simulated robot"};
  app.add_flag("--pty", o.use_pty,
               "console on a pseudo-terminal (prints its path) instead of stdio");
  app.add_option("--store", o.store_file, "parameter store file (kept across restarts)");
  app.add_option("--robot", o.robot_file,
                 "robot file (flat JSON, see docs/simulation.md): the real robot, and what the "
                 "firmware is told (wheel_diameter_mm, wheelbase_mm, counts_per_rev) when the "
                 "store holds no saved parameters; a saved set wins");
  app.add_option("--speed", o.speed,
                 "simulated time per real time: 0 = as fast as possible, else 0.01 to 1000000 "
                 "(default 1)")
      ->check(toolkit::zero_or_range_check(0.01, 1.0e6, ""));
  app.add_option("--seed", o.seed, "seed of the simulated robot's random terms")
      ->check(toolkit::whole_check(0u, UINT64_MAX));
  app.add_option("--protocol", o.protocol,
                 "the robot's firmware: odocal (default), or ros-arduino-bridge (a robot running "
                 "ROSArduinoBridge: its commands, a line ended by CR, and the tape's `measure`; "
                 "docs/simulation.md)")
      ->check(CLI::IsMember({"odocal", "ros-arduino-bridge"}));
  app.add_option("--reset-after", o.reset_after_s,
                 "fault injection: the robot's MCU resets once after this many seconds of robot "
                 "time (a brown-out: odometry, trials and unsaved parameters gone, the saved ones "
                 "loaded, the start-up line due again before the next odocal reply); SIGUSR1 "
                 "resets it at once (docs/simulation.md)")
      ->check(toolkit::range_check(0.001, 1.0e7, "s"));
  app.add_option("--corrupt", o.corrupt_rate,
                 "fault injection: this share of the bytes the robot sends is damaged on the line, "
                 "half lost, half with one bit flipped, from a stream seeded by --seed (0 to 0.5; "
                 "docs/simulation.md)")
      ->check(toolkit::range_check(0.0, 0.5, ""));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? 0 : 2;
  }
  return -1;
}

/// Parameters in a file (kept across restarts) or in RAM (forgotten at exit).
struct Storage {
  std::unique_ptr<posix::FileBlockStore> file;
  std::unique_ptr<sim::StaticRamBlockStore<4096u, 2u, 4u>> ram;
  hal::BlockStore* flash = nullptr;
};

/// The store file appears at the first `save`: a directory it cannot be created in is refused
/// now, not after a session's work. @return false, with `error`, when it cannot be used.
bool open_storage(const std::string& store_file, Storage& s, std::string& error) {
  if (store_file.empty()) {
    s.ram = std::make_unique<sim::StaticRamBlockStore<4096u, 2u, 4u>>();
    s.flash = s.ram.get();
    return true;
  }
  std::error_code ec;
  const std::filesystem::path parent = std::filesystem::path(store_file).parent_path();
  const std::string directory = parent.empty() ? std::string(".") : parent.string();
  if (std::filesystem::is_directory(store_file, ec)) {
    error = store_file + ": is a directory, not a store file";
    return false;
  }
  if (!std::filesystem::is_directory(directory, ec)) {
    error = store_file + ": directory " + directory + " does not exist";
    return false;
  }
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    error = store_file + ": cannot create files in " + directory;
    return false;
  }
  s.file = std::make_unique<posix::FileBlockStore>(store_file);
  if (!s.file->open(error)) {
    return false;  // the store's message names its file already
  }
  s.flash = s.file.get();
  return true;
}

/// The console's stream: a pty (in lockstep when as fast as possible), a terminal on stdio, or
/// scripted stdin fed one line at a time.
struct ConsoleIo {
  std::unique_ptr<posix::PtyByteStream> pty;
  std::unique_ptr<posix::FdByteStream> stdio;
  std::unique_ptr<ScriptedStream> scripted;
  std::unique_ptr<LineReader> script;
  std::unique_ptr<LineCountingStream> counting;
  hal::ByteStream* stream = nullptr;
  bool terminal = false;
  bool lockstep = false;
};

bool open_console_io(const Options& o, ConsoleIo& io, std::string& error) {
  // On a pty as fast as possible, the robot runs in lockstep with its host: simulated time
  // advances only while a motion or its trial runs, and by a fixed quantum after each input
  // line, never while the host thinks; so the same seed and the same lines give the same robot
  // on any machine and under any load.
  io.lockstep = o.use_pty && o.speed == 0.0;
  if (o.use_pty) {
    io.pty = std::make_unique<posix::PtyByteStream>();
    if (!io.pty->open(error)) {
      error = "pty: " + error;
      return false;
    }
    std::printf("%s\n", io.pty->slave_name().c_str());
    std::fflush(stdout);
    io.stream = io.pty.get();
    io.terminal = true;
    if (io.lockstep) {
      io.counting = std::make_unique<LineCountingStream>(*io.pty);
      io.stream = io.counting.get();
    }
    return true;
  }
  io.stdio = std::make_unique<posix::FdByteStream>(STDIN_FILENO, STDOUT_FILENO);
  io.terminal = isatty(STDIN_FILENO) == 1;
  if (io.terminal) {
    io.stream = io.stdio.get();
  } else {
    // Scripted input: one line at a time, each answered (and its motion finished) before the
    // next is read.
    io.scripted = std::make_unique<ScriptedStream>(*io.stdio);
    io.script = std::make_unique<LineReader>(*io.stdio);
    io.stream = io.scripted.get();
  }
  return true;
}

/// One tick of the simulated robot and what follows it (the control rate every 100 ticks, the
/// odometry frame of `measure`, the cables of the extended UMBmark).
class Stepper {
 public:
  Stepper(host::SimulatedRobot& robot, SimCommand& command) : robot_(robot), command_(command) {}
  void step() {
    if (++since_rate_check_ >= 100u) {
      since_rate_check_ = 0u;
      robot_.follow_control_rate();  // `set control_hz` took effect: tick at the new rate
    }
    robot_.tick_once();
    robot_.follow_odometry_frame();
    command_.follow_resets();
  }

 private:
  host::SimulatedRobot& robot_;
  SimCommand& command_;
  std::uint32_t since_rate_check_ = 0u;
};

/// A reset asked for: SIGUSR1, or the robot time of --reset-after reached (0: none).
bool reset_due(const host::SimulatedRobot& robot, double reset_after_s) {
  return take_reset_request() || (reset_after_s > 0.0 && robot.simulated_s() >= reset_after_s);
}

/// The pty in lockstep: each input line that changes something gets a fixed quantum of robot
/// time (enough for a reply, a `stream` line at 20 Hz or more, and a stop to settle), a question
/// (`get`, `status`, `trial`, `measure`: ConsoleCounters::questions) none, so that how often a host
/// asks never moves the robot's clock; motions run to their end, and time waits while the host
/// thinks or has not taken what the robot wrote.
bool run_lockstep(host::SimulatedRobot& robot, console::Console& console, ConsoleIo& io,
                  Stepper& stepper, const SimCommand& sim_command, double reset_after_s) {
  constexpr double lockstep_quantum_s = 0.05;
  const auto questions = [&console, &sim_command] {
    return console.counters().questions + sim_command.questions();
  };
  std::uint64_t lines_seen = io.counting->lines();
  std::uint32_t questions_seen = questions();
  double quantum_end_s = 0.0;
  while (!stop_requested()) {
    if (reset_due(robot, reset_after_s)) {
      return true;
    }
    console.poll(robot.plant().clock().now_us());
    if (io.counting->lines() != lines_seen) {
      // The console reads one line at a time and answers it in the same poll.
      const std::uint64_t lines = io.counting->lines() - lines_seen;
      const std::uint32_t asked = questions() - questions_seen;  // modulo 2^32
      lines_seen = io.counting->lines();
      questions_seen = questions();
      if (lines > asked) {
        quantum_end_s = robot.simulated_s() + lockstep_quantum_s;
      }
      io.counting->accept_input(false);
    }
    if (!console.idle()) {
      // A line still arriving, a reply or stream line not yet taken by the host: time waits, so
      // no stream line is ever dropped for a slow reader.
      pollfd wait{io.pty->input_fd(), POLLIN | POLLOUT, 0};
      static_cast<void>(::poll(&wait, 1, 1));
      continue;
    }
    const bool in_quantum = robot.simulated_s() < quantum_end_s;
    io.counting->accept_input(!in_quantum);
    if (busy(robot.loop().status(), console) || in_quantum) {
      stepper.step();
      continue;
    }
    pollfd wait{io.pty->input_fd(), POLLIN, 0};
    static_cast<void>(::poll(&wait, 1, 50));
  }
  return false;
}

/// Feeds the next scripted line when the previous one is answered and its motion is over; a
/// whole line goes in before the robot ticks again, however many pieces it comes in.
/// @return false once the input has ended and everything is answered.
bool feed_script(host::SimulatedRobot& robot, console::Console& console, ConsoleIo& io,
                 Pacer& pacer, bool& input_done) {
  if (!input_done && console.idle() && !busy(robot.loop().status(), console)) {
    std::string line;
    bool line_end = false;
    bool fed = false;
    while (!line_end && io.script->next(line, line_end)) {
      fed = true;
      io.scripted->feed(line);
      // The console takes each piece before the next is read: endless input without a line end
      // (/dev/zero) stays in constant memory, a piece at a time.
      while (io.scripted->pending() > 0u) {
        console.poll(robot.plant().clock().now_us());
      }
    }
    if (fed) {
      pacer.rebase(robot.simulated_s());
    }
    input_done = !line_end;
  }
  return !(input_done && console.idle() && !busy(robot.loop().status(), console));
}

/// Stdio (scripted or a terminal) or a pty at a set speed: simulated time paced by the wall
/// clock (or as fast as possible), input read as it comes.
bool run_paced(host::SimulatedRobot& robot, console::Console& console, ConsoleIo& io,
               Stepper& stepper, double speed, double reset_after_s) {
  Pacer pacer(speed);
  bool input_done = false;
  while (!stop_requested()) {
    if (reset_due(robot, reset_after_s)) {
      return true;
    }
    if (io.script) {
      if (!feed_script(robot, console, io, pacer, input_done)) {
        break;
      }
    } else if (io.stdio && (io.stdio->end_of_input() || io.stdio->output_broken()) &&
               console.idle()) {
      break;
    }
    console.poll(robot.plant().clock().now_us());
    stepper.step();
    pacer.wait_for(robot.simulated_s());
    if (io.terminal && speed == 0.0 && console.idle() && !busy(robot.loop().status(), console)) {
      // Nothing to simulate: wait for input instead of spinning.
      pollfd wait{io.pty ? io.pty->input_fd() : io.stdio->input_fd(), POLLIN, 0};
      static_cast<void>(::poll(&wait, 1, 5));
    }
  }
  return false;
}

/// Starts the console (its banner waits for the first odocal command line: nothing reaches a
/// ROSArduinoBridge client that it did not ask for), and on a terminal notes on the simulator's
/// own standard error the robot file's nominal geometry when it is what the firmware starts with.
void start_console(host::SimulatedRobot& robot, console::Console& console, const ConsoleIo& io,
                   const Options& o, const host::RobotSpec& spec) {
  robot.tick_once();
  const params::StoreResult stored = console.start(robot.plant().clock().now_us());
  if (!o.robot_file.empty() && stored != params::StoreResult::ok && io.terminal) {
    std::fprintf(stderr,
                 "odocal-sim: robot file: wheel_diameter_mm=%.9g wheelbase_mm=%.9g "
                 "counts_per_rev=%.9g (firmware defaults)\n",
                 static_cast<double>(spec.nominal.wheel_diameter_mm),
                 static_cast<double>(spec.nominal.wheelbase_mm),
                 static_cast<double>(spec.nominal.counts_per_rev));
  }
  if (spec.walls.present() && io.terminal) {
    static constexpr const char* kFacing[] = {"north", "east", "south", "west"};
    std::fprintf(stderr,
                 "odocal-sim: in a %ux%u maze (%s), at the centre of cell (%u, %u) facing %s, with "
                 "four wall sensors ('walls' reads them)\n",
                 spec.walls.maze.width(), spec.walls.maze.height(),
                 spec.walls.maze_file.empty() ? "the practice maze" : spec.walls.maze_file.c_str(),
                 spec.walls.start_column, spec.walls.start_row,
                 kFacing[static_cast<unsigned>(spec.walls.start_heading) & 3u]);
  }
}

/// A robot running ROSArduinoBridge: no store, no wiring faults (its firmware has no fixes for
/// them, and a robot that cannot drive straight by counts is not one to calibrate).
int run_bridge_robot(const Options& o, const host::RobotSpec& spec) {
  if (!o.store_file.empty()) {
    std::fprintf(stderr,
                 "odocal-sim: --store: a ROSArduinoBridge robot keeps no parameters (leave "
                 "--store out with --protocol ros-arduino-bridge)\n");
    return 2;
  }
  if (spec.wiring != host::WiringFault::ok || spec.encoder_fault.wheel >= 0) {
    std::fprintf(stderr,
                 "odocal-sim: %s: wiring and encoder faults are simulated only for odocal's own "
                 "firmware, not with --protocol ros-arduino-bridge\n",
                 o.robot_file.c_str());
    return 2;
  }
  return run_bridge(spec, o.seed, o.use_pty, o.speed, o.reset_after_s);
}

/// What one boot of the simulated robot's firmware runs with.
struct Boot {
  const Options& o;
  const host::RobotSpec& spec;
  params::ParamStore& store;
  ConsoleIo& io;
  const params::ParamSet& defaults;
  std::uint64_t number;  ///< 0 at power-up, then one more per reset
};

/// One boot: a fresh control loop and console (the robot's physics too: a run's measurement is
/// taken in its odometry frame, which a reset starts again), the saved parameters loaded.
/// @return whether it ended in a reset.
bool run_boot(const Boot& b) {
  const ConsoleIo& io = b.io;
  // A reset draws the robot's random terms afresh (another stretch of floor, another slip).
  host::SimulatedRobot robot(b.spec, b.o.seed + b.number);
  robot.measure_tick_time(true);  // `status` reports the tick's host time
  console::ConsoleOptions console_options;
  console_options.echo = io.terminal ? console::EchoMode::automatic : console::EchoMode::off;
  console_options.crlf = io.terminal;
  console_options.banner = io.terminal;
  console_options.defaults = &b.defaults;
  // A robot in a maze: `walls` reads its four sensors (none without a maze: `err no_sensors`).
  for (std::uint32_t i = 0u; i < robot.wall_sensor_count(); ++i) {
    console_options.wall_sensors[i] = &robot.wall_sensor(i);
  }
  // The published extended UMBmark lays 10 mm cables; a robot file's bump_height_mm replaces
  // that height, as in `odocal sim extended`.
  SimCommand sim_command(robot,
                         b.spec.truth.bump_height_m > 0.0 ? b.spec.truth.bump_height_m : 0.010);
  console_options.extra.name = "measure";
  console_options.extra.usage = SimCommand::usage;
  console_options.extra.handler = SimCommand::handle;
  console_options.extra.context = &sim_command;
  // --corrupt: the line between the robot and its host damages what the robot sends.
  std::optional<CorruptingStream> line_noise;
  hal::ByteStream* stream = io.stream;
  if (b.o.corrupt_rate > 0.0) {
    line_noise.emplace(*io.stream, b.o.corrupt_rate, b.o.seed + 7919u * (b.number + 1u));
    stream = &*line_noise;
  }
  console::Console console(*stream, robot.loop(), b.store, console_options);
  start_console(robot, console, b.io, b.o, b.spec);
  Stepper stepper(robot, sim_command);
  // --reset-after counts from power-up: the first boot only.
  const double reset_after_s = b.number == 0u ? b.o.reset_after_s : 0.0;
  const bool reset = io.lockstep
                         ? run_lockstep(robot, console, b.io, stepper, sim_command, reset_after_s)
                         : run_paced(robot, console, b.io, stepper, b.o.speed, reset_after_s);
  // Let the last reply reach the output (a reset cuts it off, as on the robot).
  for (int i = 0; i < 1000 && !reset && !console.idle(); ++i) {
    console.poll(robot.plant().clock().now_us());
  }
  return reset;
}

int run(const Options& o) {
  host::RobotSpec spec = host::default_robot();
  std::string error;
  if (!o.robot_file.empty() && !host::load_robot_file(o.robot_file, spec, error)) {
    std::fprintf(stderr, "odocal-sim: %s\n", error.c_str());
    return 2;
  }
  if (o.protocol == "ros-arduino-bridge") {
    return run_bridge_robot(o, spec);
  }
  Storage storage;
  if (!open_storage(o.store_file, storage, error)) {
    std::fprintf(stderr, "odocal-sim: %s\n", error.c_str());
    return 2;
  }
  params::ParamStore store(*storage.flash);
  ConsoleIo io;
  if (!open_console_io(o, io, error)) {
    std::fprintf(stderr, "odocal-sim: %s\n", error.c_str());
    return 2;
  }
  params::ParamSet defaults;
  if (!robot_defaults(spec, defaults, error)) {
    std::fprintf(stderr, "odocal-sim: %s: %s\n", o.robot_file.c_str(), error.c_str());
    return 2;
  }
  install_stop_handlers();
  // Each pass is one boot of the robot's MCU on the same pty and store; a reset (SIGUSR1,
  // --reset-after) ends it and the next one starts as the firmware does at power-up.
  for (std::uint64_t boot = 0;; ++boot) {
    const Boot b{o, spec, store, io, defaults, boot};
    if (!run_boot(b) || stop_requested()) {
      break;
    }
  }
  return 0;
}

}  // namespace
}  // namespace odocal::sim_app

int main(int argc, char** argv) {
  odocal::sim_app::Options options;
  const int status = odocal::sim_app::parse_options(argc, argv, options);
  return status >= 0 ? status : odocal::sim_app::run(options);
}
