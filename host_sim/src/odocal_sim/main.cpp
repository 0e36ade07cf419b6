// odocal-sim: the robot firmware (control loop + console) on the simulated robot, on the host.
// Console on stdio or a pty, parameters in a file, simulated time at X times real time.

#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <thread>

#include "odocal/console/console.hpp"
#include "odocal/console/text.hpp"
#include "odocal/host/sim_robot.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/params/param_table.hpp"
#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/posix/file_block_store.hpp"
#include "odocal/sim/ram_block_store.hpp"
#include "odocal/toolkit/cli_checks.hpp"

namespace {

std::atomic<bool> stop_requested{false};
void on_signal(int) {
  stop_requested.store(true);
}

/// The console's view of a stream whose input the program feeds itself (scripted stdin): it
/// writes through, and gives the console the script's bytes as they are fed.
class ScriptedStream final : public odocal::hal::ByteStream {
 public:
  explicit ScriptedStream(odocal::hal::ByteStream& inner) : inner_(inner) {}
  /// Queues script bytes for the console to read.
  void feed(const std::string& bytes) { pending_ += bytes; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    const std::size_t n = std::min(capacity, pending_.size() - taken_);
    std::memcpy(out, pending_.data() + taken_, n);
    taken_ += n;
    if (taken_ == pending_.size()) {
      pending_.clear();
      taken_ = 0u;
    }
    return n;
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return inner_.write(data, size);
  }
  odocal::hal::ByteStream& inner_;
  std::string pending_;
  std::size_t taken_ = 0u;
};

/// The console's view of the pty in lockstep: passes bytes through and counts the input lines
/// the console has read (a CR, or a LF not right after a CR), so that the simulation can give
/// each line the same quantum of robot time whatever the host's timing.
class LineCountingStream final : public odocal::hal::ByteStream {
 public:
  explicit LineCountingStream(odocal::hal::ByteStream& inner) : inner_(inner) {}
  [[nodiscard]] std::uint64_t lines() const { return lines_; }
  /// While false, nothing is read: input waits in the pty until the robot time a line is given
  /// has passed, whenever the host sent it.
  void accept_input(bool accept) { accepting_ = accept; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t /*capacity*/) override {
    if (!accepting_) {
      return 0u;
    }
    // One line at a time: the bytes after a line end stay in the pty until its quantum is over.
    const std::size_t n = inner_.read(out, 1u);
    for (std::size_t i = 0; i < n; ++i) {
      if (out[i] == '\r' || (out[i] == '\n' && !after_cr_)) {
        ++lines_;
        accepting_ = false;
      }
      after_cr_ = out[i] == '\r';
    }
    return n;
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return inner_.write(data, size);
  }
  odocal::hal::ByteStream& inner_;
  std::uint64_t lines_ = 0u;
  bool after_cr_ = false;
  bool accepting_ = true;
};

/// The firmware's parameter defaults on this simulated robot: the built-in ones, with the robot
/// file's nominal keys (wheel_diameter_mm, wheelbase_mm, counts_per_rev) as if the firmware had
/// been built for that robot. They are in force when the store holds no usable saved set, and
/// `defaults` restores them. @return false, with `error`, when the firmware would refuse them.
bool robot_defaults(const odocal::host::RobotSpec& spec, odocal::params::ParamSet& set,
                    std::string& error) {
  set = odocal::params::default_params();
  odocal::drive::DriveConfig told = odocal::params::to_drive_config(set);
  told.wheel_diameter_mm = spec.nominal.wheel_diameter_mm;
  told.wheelbase_mm = spec.nominal.wheelbase_mm;
  told.counts_per_rev = spec.nominal.counts_per_rev;
  odocal::params::from_drive_config(told, set);
  if (!odocal::params::all_in_range(set) || !odocal::drive::valid(told)) {
    error = "wheel_diameter_mm, wheelbase_mm or counts_per_rev outside the firmware's ranges";
    return false;
  }
  return true;
}

/// The simulator's own console command, in the console's one target slot (`measure`): the tape
/// measure, and the floor the extended UMBmark needs (docs/simulation.md, "odocal-sim"). Real
/// targets have neither: they answer `err unknown_command`.
class SimCommand {
 public:
  /// @param default_cable_height_m the height `measure cables` lays when it is not given.
  SimCommand(odocal::host::SimulatedRobot& robot, double default_cable_height_m)
      : robot_(robot), default_cable_height_m_(default_cable_height_m) {}

  static void handle(void* context, const odocal::console::Token* words, std::size_t count,
                     odocal::console::Reply& reply) {
    auto& self = *static_cast<SimCommand*>(context);
    if (count == 1u) {
      self.measure(reply);
    } else if (words[1].is("cables")) {
      self.cables(words, count, reply);
    } else {
      reply.text("err wrong_arity usage: ").text(usage);
    }
  }

  /// Call after each tick: at every odometry reset (a new run from the start mark) laid cables
  /// lie ahead of the robot again, as they do on a real floor for a robot put back on its mark.
  void follow_resets() {
    if (!laid_) {
      return;
    }
    const std::uint32_t resets = robot_.loop().status().pose_resets;
    if (resets != resets_seen_) {
      resets_seen_ = resets;
      lay();
    }
  }

  static constexpr const char* usage =
      "measure [cables off | cables FIRST_MM SPACING_MM COUNT left|right [HEIGHT_MM]] (sim only)";

 private:
  /// `measure` (DESIGN "Trials, logs and the simulated tape measure"): the true pose of the
  /// robot in the odometry frame, plus the robot file's measurement noise.
  void measure(odocal::console::Reply& reply) {
    const odocal::sim::WorldPose pose = robot_.measure_in_odometry_frame();
    reply.text("ok")
        .pair("x_mm", pose.x_m * 1000.0, 3)
        .pair("y_mm", pose.y_m * 1000.0, 3)
        .pair("theta_deg", pose.theta_rad * 180.0 / std::numbers::pi, 3);
  }

  /// `measure cables off`: a smooth floor. `measure cables FIRST SPACING COUNT WHEEL [HEIGHT]`:
  /// COUNT cables of HEIGHT mm (default: the robot file's bump_height_mm, else 10 mm) under one
  /// wheel only, the first FIRST mm of floor from the start of each run, then every SPACING mm
  /// (sim::Plant::lay_cables). A refused line changes nothing.
  void cables(const odocal::console::Token* words, std::size_t count,
              odocal::console::Reply& reply) {
    if (count == 3u && words[2].is("off")) {
      laid_ = false;
      robot_.plant().set_bumps(0.0, 0.0);
      reply.text("ok cables=0");
      return;
    }
    if (count != 6u && count != 7u) {
      reply.text("err wrong_arity usage: ").text(usage);
      return;
    }
    float first_mm = 0.0f;
    float spacing_mm = 0.0f;
    float height_mm = static_cast<float>(default_cable_height_m_ * 1000.0);
    std::uint32_t cables = 0u;
    const bool right = words[5].is("right");
    if (!odocal::console::parse_number(words[2], first_mm) || !(first_mm >= 0.0f) ||
        first_mm > 100000.0f || !odocal::console::parse_number(words[3], spacing_mm) ||
        !(spacing_mm > 0.0f) || spacing_mm > 100000.0f ||
        !odocal::console::parse_unsigned(words[4], cables) || cables == 0u || cables > 1000u ||
        (!right && !words[5].is("left")) ||
        (count == 7u && !odocal::console::parse_number(words[6], height_mm))) {
      reply.text("err bad_argument usage: ").text(usage);
      return;
    }
    const odocal::sim::RobotModel& truth = robot_.spec().truth;
    const double radius_mm = 500.0 * (right ? truth.right_diameter_m : truth.left_diameter_m);
    if (!(height_mm > 0.0f) || !(height_mm < radius_mm)) {
      reply.text("err bad_argument cable height must be above 0 and below the wheel radius");
      return;
    }
    laid_ = true;
    right_ = right;
    height_m_ = static_cast<double>(height_mm) * 1e-3;
    first_m_ = static_cast<double>(first_mm) * 1e-3;
    spacing_m_ = static_cast<double>(spacing_mm) * 1e-3;
    count_ = cables;
    resets_seen_ = robot_.loop().status().pose_resets;
    lay();
    reply.text("ok")
        .pair_u("cables", count_)
        .pair("height_mm", height_mm, 3)
        .pair("first_mm", first_mm, 3)
        .pair("spacing_mm", spacing_mm, 3)
        .pair_s("wheel", right_ ? "right" : "left");
  }

  void lay() { robot_.plant().lay_cables(right_, height_m_, first_m_, spacing_m_, count_); }

  odocal::host::SimulatedRobot& robot_;
  double default_cable_height_m_;
  bool laid_ = false;
  bool right_ = true;
  double height_m_ = 0.0;
  double first_m_ = 0.0;
  double spacing_m_ = 0.0;
  std::uint32_t count_ = 0u;
  std::uint32_t resets_seen_ = 0u;
};

/// Reads scripted input from a non-blocking stream (waiting with poll) in pieces: each piece is
/// the rest of a line up to and including its end (CR, LF or CRLF), or, while no line end has
/// come, the bytes read so far. Pieces go to the console as they come, and its line editor takes
/// them exactly as from a terminal: a line longer than it keeps is refused whole, however long.
/// Every byte is looked at once and the memory is one fixed buffer, so a long line or endless
/// input without a line end (/dev/zero) costs linear time and constant memory.
class LineReader {
 public:
  LineReader(odocal::posix::FdByteStream& stream) : stream_(stream) {}
  /// Next piece; `line_end` says whether it ends a line. False at end of input (a last
  /// unterminated line is ended with a LF).
  bool next(std::string& piece, bool& line_end) {
    for (;;) {
      if (begin_ < end_) {
        std::size_t stop = begin_;
        while (stop < end_ && chunk_[stop] != '\r' && chunk_[stop] != '\n') {
          ++stop;
        }
        line_end = stop < end_;
        if (line_end) {
          // A CRLF split over two reads gives a lone LF next: the console takes it as the end of
          // the same line.
          ++stop;
        }
        piece.assign(reinterpret_cast<const char*>(chunk_ + begin_), stop - begin_);
        begin_ = stop;
        in_line_ = !line_end;
        return true;
      }
      if (stream_.end_of_input() || stop_requested.load()) {
        if (!in_line_) {
          return false;
        }
        piece = "\n";
        line_end = true;
        in_line_ = false;
        return true;
      }
      begin_ = 0u;
      end_ = stream_.read(chunk_, sizeof chunk_);
      if (end_ == 0u && !stream_.end_of_input()) {
        pollfd wait{stream_.input_fd(), POLLIN, 0};
        static_cast<void>(::poll(&wait, 1, 20));
      }
    }
  }

 private:
  odocal::posix::FdByteStream& stream_;
  std::uint8_t chunk_[512] = {};
  std::size_t begin_ = 0u;
  std::size_t end_ = 0u;
  bool in_line_ = false;  ///< bytes of an unterminated line were handed out
};

/// Paces simulated time against the wall clock (speed X), or not at all (speed 0).
class Pacer {
 public:
  explicit Pacer(double speed) : speed_(speed), start_(std::chrono::steady_clock::now()) {}
  void rebase(double simulated_s) {
    start_ = std::chrono::steady_clock::now();
    base_s_ = simulated_s;
  }
  void wait_for(double simulated_s) const {
    if (!(speed_ > 0.0)) {
      return;
    }
    const double due_wall_s = (simulated_s - base_s_) / speed_;
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(due_wall_s));
    if (due > std::chrono::steady_clock::now()) {
      std::this_thread::sleep_until(due);
    }
  }

 private:
  double speed_;
  std::chrono::steady_clock::time_point start_;
  double base_s_ = 0.0;
};

// Scripted input waits for the motion and for its trial to close (so `# done` comes first).
bool busy(const odocal::drive::LoopStatus& status, const odocal::console::Console& console) {
  return status.mode == odocal::drive::Mode::path || status.mode == odocal::drive::Mode::drive ||
         status.trial_open || console.selftest_running();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace odocal;
  CLI::App app{"odocal-sim: the odocal firmware on a simulated robot"};
  bool use_pty = false;
  std::string store_file;
  std::string robot_file;
  double speed = 1.0;
  std::uint64_t seed = 1;
  app.add_flag("--pty", use_pty, "console on a pseudo-terminal (prints its path) instead of stdio");
  app.add_option("--store", store_file, "parameter store file (kept across restarts)");
  app.add_option("--robot", robot_file,
                 "robot file (flat JSON, see docs/simulation.md): the real robot, and what the "
                 "firmware is told (wheel_diameter_mm, wheelbase_mm, counts_per_rev) when the "
                 "store holds no saved parameters; a saved set wins");
  app.add_option("--speed", speed,
                 "simulated time per real time: 0 = as fast as possible, else 0.01 to 1000000 "
                 "(default 1)")
      ->check(toolkit::zero_or_range_check(0.01, 1.0e6, ""));
  app.add_option("--seed", seed, "seed of the simulated robot's random terms")
      ->check(toolkit::whole_check(0u, UINT64_MAX));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? 0 : 2;
  }

  host::RobotSpec spec = host::default_robot();
  std::string error;
  if (!robot_file.empty() && !host::load_robot_file(robot_file, spec, error)) {
    std::fprintf(stderr, "odocal-sim: %s\n", error.c_str());
    return 2;
  }
  host::SimulatedRobot robot(spec, seed);
  robot.measure_tick_time(true);  // `status` reports the tick's host time

  // Parameters: a file (kept across restarts) or RAM (forgotten at exit).
  std::unique_ptr<posix::FileBlockStore> file_store;
  std::unique_ptr<sim::StaticRamBlockStore<4096u, 2u, 4u>> ram_store;
  hal::BlockStore* flash = nullptr;
  if (!store_file.empty()) {
    // The store file appears at the first `save`: a directory it cannot be created in is refused
    // now, not after a session's work.
    std::error_code ec;
    const std::filesystem::path parent = std::filesystem::path(store_file).parent_path();
    const std::string directory = parent.empty() ? std::string(".") : parent.string();
    if (std::filesystem::is_directory(store_file, ec)) {
      std::fprintf(stderr, "odocal-sim: %s: is a directory, not a store file\n",
                   store_file.c_str());
      return 2;
    }
    if (!std::filesystem::is_directory(directory, ec)) {
      std::fprintf(stderr, "odocal-sim: %s: directory %s does not exist\n", store_file.c_str(),
                   directory.c_str());
      return 2;
    }
    if (::access(directory.c_str(), W_OK | X_OK) != 0) {
      std::fprintf(stderr, "odocal-sim: %s: cannot create files in %s\n", store_file.c_str(),
                   directory.c_str());
      return 2;
    }
    file_store = std::make_unique<posix::FileBlockStore>(store_file);
    if (!file_store->open(error)) {
      // The store's message names its file already.
      std::fprintf(stderr, "odocal-sim: %s\n", error.c_str());
      return 2;
    }
    flash = file_store.get();
  } else {
    ram_store = std::make_unique<sim::StaticRamBlockStore<4096u, 2u, 4u>>();
    flash = ram_store.get();
  }
  params::ParamStore store(*flash);

  // The console stream.
  std::unique_ptr<posix::PtyByteStream> pty;
  std::unique_ptr<posix::FdByteStream> stdio;
  std::unique_ptr<ScriptedStream> scripted;
  std::unique_ptr<LineReader> script;
  // On a pty as fast as possible, the robot runs in lockstep with its host: simulated time
  // advances only while a motion or its trial runs, and by a fixed quantum after each input
  // line, never while the host thinks; so the same seed and the same lines give the same robot
  // on any machine and under any load.
  const bool lockstep = use_pty && speed == 0.0;
  std::unique_ptr<LineCountingStream> counting;
  hal::ByteStream* console_stream = nullptr;
  bool terminal = false;
  if (use_pty) {
    pty = std::make_unique<posix::PtyByteStream>();
    if (!pty->open(error)) {
      std::fprintf(stderr, "odocal-sim: pty: %s\n", error.c_str());
      return 2;
    }
    std::printf("%s\n", pty->slave_name().c_str());
    std::fflush(stdout);
    console_stream = pty.get();
    terminal = true;
    if (lockstep) {
      counting = std::make_unique<LineCountingStream>(*pty);
      console_stream = counting.get();
    }
  } else {
    stdio = std::make_unique<posix::FdByteStream>(STDIN_FILENO, STDOUT_FILENO);
    terminal = isatty(STDIN_FILENO) == 1;
    if (terminal) {
      console_stream = stdio.get();
    } else {
      // Scripted input: one line at a time, each answered (and its motion finished) before the
      // next is read.
      scripted = std::make_unique<ScriptedStream>(*stdio);
      script = std::make_unique<LineReader>(*stdio);
      console_stream = scripted.get();
    }
  }
  params::ParamSet defaults;
  if (!robot_defaults(spec, defaults, error)) {
    std::fprintf(stderr, "odocal-sim: %s: %s\n", robot_file.c_str(), error.c_str());
    return 2;
  }
  console::ConsoleOptions console_options;
  console_options.echo = terminal ? console::EchoMode::automatic : console::EchoMode::off;
  console_options.crlf = terminal;
  console_options.banner = terminal;
  console_options.defaults = &defaults;
  // The published extended UMBmark lays 10 mm cables; a robot file's bump_height_mm replaces
  // that height, as in `odocal sim extended`.
  SimCommand sim_command(robot, spec.truth.bump_height_m > 0.0 ? spec.truth.bump_height_m : 0.010);
  console_options.extra.name = "measure";
  console_options.extra.usage = SimCommand::usage;
  console_options.extra.handler = SimCommand::handle;
  console_options.extra.context = &sim_command;
  console::Console console(*console_stream, robot.loop(), store, console_options);

  struct sigaction action {};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);

  if (pty) {
    // The banner waits for the first byte from the terminal side: printed at once, it would be
    // gone before picocom or screen attach.
    while (!stop_requested.load()) {
      pollfd wait{pty->input_fd(), POLLIN, 0};
      if (::poll(&wait, 1, 100) > 0) {
        break;
      }
    }
  }
  robot.tick_once();
  const params::StoreResult stored = console.start(robot.plant().clock().now_us());
  while (!console.idle()) {  // the banner goes out first
    console.poll(robot.plant().clock().now_us());
  }
  if (!robot_file.empty() && stored != params::StoreResult::ok && terminal) {
    char note[160];
    std::snprintf(note, sizeof note,
                  "# robot file: wheel_diameter_mm=%.9g wheelbase_mm=%.9g counts_per_rev=%.9g "
                  "(firmware defaults)\r\n",
                  static_cast<double>(spec.nominal.wheel_diameter_mm),
                  static_cast<double>(spec.nominal.wheelbase_mm),
                  static_cast<double>(spec.nominal.counts_per_rev));
    static_cast<void>(
        console_stream->write(reinterpret_cast<const std::uint8_t*>(note), std::strlen(note)));
  }
  Pacer pacer(speed);
  std::string line;
  bool input_done = false;
  std::uint32_t since_rate_check = 0u;
  /// Robot time each input line is given in lockstep: enough for a reply, a `stream` line at
  /// 20 Hz or more, and a stop to settle.
  constexpr double lockstep_quantum_s = 0.05;
  std::uint64_t lines_seen = 0u;
  double quantum_end_s = 0.0;
  while (lockstep && !stop_requested.load()) {
    console.poll(robot.plant().clock().now_us());
    if (counting->lines() != lines_seen) {
      lines_seen = counting->lines();
      quantum_end_s = robot.simulated_s() + lockstep_quantum_s;
      counting->accept_input(false);
    }
    if (!console.idle()) {
      // A line still arriving, a reply or stream line not yet taken by the host: time waits, so
      // no stream line is ever dropped for a slow reader.
      pollfd wait{pty->input_fd(), POLLIN | POLLOUT, 0};
      static_cast<void>(::poll(&wait, 1, 1));
      continue;
    }
    const bool in_quantum = robot.simulated_s() < quantum_end_s;
    counting->accept_input(!in_quantum);
    if (busy(robot.loop().status(), console) || in_quantum) {
      if (++since_rate_check >= 100u) {
        since_rate_check = 0u;
        robot.follow_control_rate();
      }
      robot.tick_once();
      robot.follow_odometry_frame();
      sim_command.follow_resets();
      continue;
    }
    pollfd wait{pty->input_fd(), POLLIN, 0};
    static_cast<void>(::poll(&wait, 1, 50));
  }
  while (!lockstep && !stop_requested.load()) {
    if (script) {
      // Feed the next line only when the previous one is answered and its motion is over.
      if (!input_done && console.idle() && !busy(robot.loop().status(), console)) {
        // A whole line goes in before the robot ticks again, however many pieces it comes in.
        bool line_end = false;
        bool fed = false;
        while (!line_end && script->next(line, line_end)) {
          fed = true;
          scripted->feed(line);
        }
        if (fed) {
          pacer.rebase(robot.simulated_s());
        }
        input_done = !line_end;
      }
      if (input_done && console.idle() && !busy(robot.loop().status(), console)) {
        break;
      }
    } else if (stdio && (stdio->end_of_input() || stdio->output_broken()) && console.idle()) {
      break;
    }
    console.poll(robot.plant().clock().now_us());
    if (++since_rate_check >= 100u) {
      since_rate_check = 0u;
      robot.follow_control_rate();  // `set control_hz` took effect: tick at the new rate
    }
    robot.tick_once();
    robot.follow_odometry_frame();
    sim_command.follow_resets();
    pacer.wait_for(robot.simulated_s());
    if (terminal && speed == 0.0 && console.idle() && !busy(robot.loop().status(), console)) {
      // Nothing to simulate: wait for input instead of spinning.
      pollfd wait{pty ? pty->input_fd() : stdio->input_fd(), POLLIN, 0};
      if (::poll(&wait, 1, 5) == 0) {
        continue;
      }
    }
  }
  // Let the last reply reach the output.
  for (int i = 0; i < 1000 && !console.idle(); ++i) {
    console.poll(robot.plant().clock().now_us());
  }
  return 0;
}
