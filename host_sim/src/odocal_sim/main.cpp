// odocal-sim: the robot firmware (control loop + console) on the simulated robot, on the host.
// Console on stdio or a pty, parameters in a file, simulated time at X times real time.

#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "odocal/console/console.hpp"
#include "odocal/host/sim_robot.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/params/param_table.hpp"
#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/posix/file_block_store.hpp"
#include "odocal/sim/ram_block_store.hpp"

namespace {

std::atomic<bool> stop_requested{false};
void on_signal(int) {
  stop_requested.store(true);
}

/// The console's view of a stream whose input the program feeds itself (scripted stdin): it
/// writes through, and reads nothing.
class OutputOnly final : public odocal::hal::ByteStream {
 public:
  explicit OutputOnly(odocal::hal::ByteStream& inner) : inner_(inner) {}

 private:
  std::size_t do_read(std::uint8_t*, std::size_t) override { return 0u; }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return inner_.write(data, size);
  }
  odocal::hal::ByteStream& inner_;
};

/// The console's stream with a hold switch: while held, the console reads nothing and what it
/// writes is kept aside instead of sent (odocal-sim types its own start-up `set` lines).
class HoldableStream final : public odocal::hal::ByteStream {
 public:
  explicit HoldableStream(odocal::hal::ByteStream& inner) : inner_(inner) {}
  void hold(bool on) {
    held_ = on;
    kept_.clear();
  }
  /// What the console wrote since `hold(true)`.
  [[nodiscard]] const std::string& kept() const { return kept_; }
  /// Writes past the console (a `#` comment line of the program's own).
  void write_through(const std::string& text) {
    static_cast<void>(
        inner_.write(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    return held_ ? 0u : inner_.read(out, capacity);
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    if (held_) {
      kept_.append(reinterpret_cast<const char*>(data), size);
      return size;
    }
    return inner_.write(data, size);
  }
  odocal::hal::ByteStream& inner_;
  bool held_ = false;
  std::string kept_;
};

/// Types `line` into the console and runs it until it has answered; returns the reply.
std::string type_line(odocal::console::Console& console, HoldableStream& stream,
                      odocal::host::SimulatedRobot& robot, const std::string& line) {
  stream.hold(true);
  for (char c : line) {
    while (!console.receive_from_isr(static_cast<std::uint8_t>(c))) {
      console.poll(robot.plant().clock().now_us());
    }
  }
  do {
    console.poll(robot.plant().clock().now_us());
  } while (!console.idle());
  std::string reply = stream.kept();
  stream.hold(false);
  return reply;
}

/// With no usable saved set, the firmware starts from what the robot file says it is told
/// (wheel_diameter_mm, wheelbase_mm, counts_per_rev), as if it had been built for that robot:
/// each value that differs from the parameter in force is `set` through the console (in force,
/// not saved). @return false, with `error`, when the firmware refuses one.
bool apply_robot_nominal(odocal::console::Console& console, HoldableStream& stream,
                         odocal::host::SimulatedRobot& robot, const odocal::host::RobotSpec& spec,
                         std::string& applied, std::string& error) {
  using odocal::params::ParamId;
  const odocal::drive::DriveConfig& told = spec.nominal;
  struct Told {
    ParamId id;
    float value;
  };
  // Keep the loop's check wheelbase > diameter/4 true after each step: a larger wheel first
  // while the old wheelbase allows it, otherwise the wheelbase first.
  const float old_wheelbase = console.params().get(ParamId::wheelbase_mm);
  const bool diameter_first = old_wheelbase > told.wheel_diameter_mm * 0.25f;
  const Told order[3] = {{diameter_first ? ParamId::wheel_diameter_mm : ParamId::wheelbase_mm,
                          diameter_first ? told.wheel_diameter_mm : told.wheelbase_mm},
                         {diameter_first ? ParamId::wheelbase_mm : ParamId::wheel_diameter_mm,
                          diameter_first ? told.wheelbase_mm : told.wheel_diameter_mm},
                         {ParamId::counts_per_rev, told.counts_per_rev}};
  for (const Told& t : order) {
    if (console.params().get(t.id) == t.value) {
      continue;
    }
    char line[96];
    const char* name = odocal::params::param_info(t.id).name;
    std::snprintf(line, sizeof line, "set %s %.9g\n", name, static_cast<double>(t.value));
    const std::string reply = type_line(console, stream, robot, line);
    if (reply.rfind("ok", 0) != 0) {
      error = std::string(name) + ": the firmware refused it: " + reply;
      while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) {
        error.pop_back();
      }
      return false;
    }
    char pair[64];
    std::snprintf(pair, sizeof pair, " %s=%.9g", name, static_cast<double>(t.value));
    applied += pair;
  }
  return true;
}

/// Reads whole lines from a non-blocking stream (waiting with poll), one at a time.
class LineReader {
 public:
  LineReader(odocal::posix::FdByteStream& stream) : stream_(stream) {}
  /// Next line including its terminator; false at end of input (a last unterminated line is
  /// returned with a LF added).
  bool next(std::string& line) {
    for (;;) {
      const std::size_t end = buffer_.find_first_of("\r\n");
      if (end != std::string::npos) {
        std::size_t stop = end + 1;
        if (buffer_[end] == '\r' && stop < buffer_.size() && buffer_[stop] == '\n') {
          ++stop;
        }
        line = buffer_.substr(0, stop);
        buffer_.erase(0, stop);
        return true;
      }
      if (stream_.end_of_input() || stop_requested.load()) {
        if (buffer_.empty()) {
          return false;
        }
        line = buffer_ + "\n";
        buffer_.clear();
        return true;
      }
      std::uint8_t chunk[512];
      const std::size_t n = stream_.read(chunk, sizeof chunk);
      if (n == 0u && !stream_.end_of_input()) {
        pollfd wait{stream_.input_fd(), POLLIN, 0};
        static_cast<void>(::poll(&wait, 1, 20));
      }
      buffer_.append(reinterpret_cast<const char*>(chunk), n);
    }
  }

 private:
  odocal::posix::FdByteStream& stream_;
  std::string buffer_;
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

bool busy(const odocal::drive::LoopStatus& status) {
  return status.mode == odocal::drive::Mode::path || status.mode == odocal::drive::Mode::drive;
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
  app.add_option("--speed", speed, "simulated time per real time; 0 = as fast as possible")
      ->check(CLI::Range(0.0, 1.0e6));
  app.add_option("--seed", seed, "seed of the simulated robot's random terms");
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

  // Parameters: a file (kept across restarts) or RAM (forgotten at exit).
  std::unique_ptr<posix::FileBlockStore> file_store;
  std::unique_ptr<sim::StaticRamBlockStore<4096u, 2u, 4u>> ram_store;
  hal::BlockStore* flash = nullptr;
  if (!store_file.empty()) {
    file_store = std::make_unique<posix::FileBlockStore>(store_file);
    if (!file_store->open(error)) {
      std::fprintf(stderr, "odocal-sim: %s: %s\n", store_file.c_str(), error.c_str());
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
  std::unique_ptr<OutputOnly> output_only;
  std::unique_ptr<LineReader> script;
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
  } else {
    stdio = std::make_unique<posix::FdByteStream>(STDIN_FILENO, STDOUT_FILENO);
    terminal = isatty(STDIN_FILENO) == 1;
    if (terminal) {
      console_stream = stdio.get();
    } else {
      // Scripted input: one line at a time, each answered (and its motion finished) before the
      // next is read.
      output_only = std::make_unique<OutputOnly>(*stdio);
      script = std::make_unique<LineReader>(*stdio);
      console_stream = output_only.get();
    }
  }
  HoldableStream holdable(*console_stream);
  console::Console console(
      holdable, robot.loop(), store,
      console::ConsoleOptions{terminal ? console::EchoMode::automatic : console::EchoMode::off,
                              terminal, terminal});

  struct sigaction action {};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);

  robot.tick_once();
  const params::StoreResult stored = console.start(robot.plant().clock().now_us());
  while (!console.idle()) {  // the banner goes out first
    console.poll(robot.plant().clock().now_us());
  }
  if (!robot_file.empty() && stored != params::StoreResult::ok) {
    std::string applied;
    if (!apply_robot_nominal(console, holdable, robot, spec, applied, error)) {
      std::fprintf(stderr, "odocal-sim: %s: %s\n", robot_file.c_str(), error.c_str());
      return 2;
    }
    if (!applied.empty()) {
      holdable.write_through("# robot file" + applied + " (in force, not saved)" +
                             (terminal ? "\r\n" : "\n"));
    }
  }
  Pacer pacer(speed);
  std::string line;
  bool input_done = false;
  std::uint32_t since_rate_check = 0u;
  while (!stop_requested.load()) {
    if (script) {
      // Feed the next line only when the previous one is answered and its motion is over.
      if (!input_done && console.idle() && !busy(robot.loop().status())) {
        if (script->next(line)) {
          for (char c : line) {
            while (!console.receive_from_isr(static_cast<std::uint8_t>(c))) {
              console.poll(robot.plant().clock().now_us());
            }
          }
          pacer.rebase(robot.simulated_s());
        } else {
          input_done = true;
        }
      }
      if (input_done && console.idle() && !busy(robot.loop().status())) {
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
    pacer.wait_for(robot.simulated_s());
    if (terminal && speed == 0.0 && console.idle() && !busy(robot.loop().status())) {
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
