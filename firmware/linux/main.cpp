// odocal-linux: the robot process on a Linux single-board computer. The same core and console
// as the firmware; encoders, direction lines and PWM through libgpiod v1 and sysfs.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "config.hpp"
#include "odocal/console/console.hpp"
#include "odocal/console/version.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/posix/file_block_store.hpp"
#include "robot.hpp"

namespace {

using namespace odocal;
using namespace odocal::hal::linux_gpiod;
using odocal::linux_target::LinuxConfig;
using odocal::linux_target::Robot;

constexpr const char* kDefaultConfig = "/etc/odocal/odocal-linux.conf";
constexpr int kExitSetup = 1;  // hardware or file set-up failed
constexpr int kExitUsage = 2;  // bad command line or configuration

std::atomic<bool> stop_requested{false};

void on_signal(int) {
  stop_requested.store(true);
}

void print_help() {
  std::printf(
      "usage: odocal-linux [--config FILE] [--pty | --tty DEVICE] [--store FILE] [--check]\n"
      "\n"
      "The odocal robot process for a Linux board: encoders and motor lines through libgpiod,\n"
      "PWM through sysfs, the control tick on a timerfd thread, the console on stdin/stdout.\n"
      "\n"
      "  --config FILE   configuration (default %s)\n"
      "  --pty           console on a new pseudo-terminal (its path is printed on stderr)\n"
      "  --tty DEVICE    console on a serial port, 115200 8N1 raw (e.g. /dev/ttyS0)\n"
      "  --store FILE    parameter store file (overrides `store` in the configuration)\n"
      "  --check         request every line and PWM channel, print the wiring, exit\n"
      "  --help          this text\n"
      "  --version       the version\n"
      "\n"
      "Exit status: 0 at the end of the console input or on SIGINT/SIGTERM, 1 when a chip,\n"
      "line, PWM channel or file cannot be set up, 2 for a bad command line or configuration.\n"
      "\n%s",
      kDefaultConfig, linux_target::config_reference());
}

// ` key=value` pairs the console's `status` reply gets on this target.
std::size_t linux_status_pairs(void* context, char* out, std::size_t capacity) {
  auto* robot = static_cast<Robot*>(context);
  const TickStats tick = robot->tick->stats();
  const EncoderStats l = robot->encoders->stats(Wheel::left);
  const EncoderStats r = robot->encoders->stats(Wheel::right);
  const bool soft = robot->left_pwm.active == &robot->left_pwm.soft ||
                    robot->right_pwm.active == &robot->right_pwm.soft;
  const int length = std::snprintf(
      out, capacity,
      " tick_rt=%d event_rt=%d tick_late_us_mean=%u tick_late_us_max=%u tick_missed=%u"
      " edges_l=%u edges_r=%u dropped_l=%u dropped_r=%u misread_l=%u misread_r=%u"
      " queue_full_l=%u queue_full_r=%u pwm=%s",
      tick.realtime ? 1 : 0, robot->encoders->realtime() ? 1 : 0, tick.late_us_mean,
      tick.late_us_max, tick.missed, l.events, r.events, l.dropped, r.dropped, l.misread, r.misread,
      l.queue_full, r.queue_full, soft ? "software_low_precision" : "sysfs");
  return length < 0 ? 0u : static_cast<std::size_t>(length);
}

// Opens a serial port raw at 115200 8N1. @return the descriptor or -1 with `error` set.
int open_tty(const std::string& device, std::string& error) {
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    error = device + ": " + std::strerror(errno);
    return -1;
  }
  termios mode{};
  if (tcgetattr(fd, &mode) != 0) {
    error = device + ": not a terminal (" + std::strerror(errno) + ")";
    ::close(fd);
    return -1;
  }
  cfmakeraw(&mode);
  cfsetispeed(&mode, B115200);
  cfsetospeed(&mode, B115200);
  mode.c_cflag |= CLOCAL | CREAD;
  mode.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
  if (tcsetattr(fd, TCSANOW, &mode) != 0) {
    error = device + ": cannot set 115200 8N1 (" + std::strerror(errno) + ")";
    ::close(fd);
    return -1;
  }
  return fd;
}

struct Options {
  std::string config = kDefaultConfig;
  std::string tty;
  std::string store;
  bool pty = false;
  bool check = false;
};

// The command line, by CLI11. @return -1 to go on, else the exit status. Options may repeat
// (the last value counts); anything unknown is refused naming it.
int parse_options(int argc, char** argv, Options& options) {
  CLI::App app{"odocal-linux", "odocal-linux"};
  app.set_help_flag();  // --help prints the reference of the configuration keys too
  app.allow_extras();   // unknown arguments are named below, in this program's words
  bool help = false;
  bool version = false;
  app.add_flag("-h,--help", help);
  app.add_flag("--version", version);
  app.add_flag("--pty", options.pty);
  app.add_flag("--check", options.check);
  for (auto [name, target] :
       {std::pair{"--config", &options.config}, std::pair{"--tty", &options.tty},
        std::pair{"--store", &options.store}}) {
    app.add_option(name, *target)->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // The only parse error left: an option without its value ("--config: 1 required ...").
    const std::string what = e.what();
    std::fprintf(stderr, "odocal-linux: %s needs a value (see --help)\n",
                 what.substr(0, what.find(':')).c_str());
    return kExitUsage;
  }
  if (!app.remaining().empty()) {
    std::fprintf(stderr, "odocal-linux: unknown option \"%s\" (see --help)\n",
                 app.remaining().front().c_str());
    return kExitUsage;
  }
  if (help) {
    print_help();
    return 0;
  }
  if (version) {
    std::printf("odocal-linux %s\n", console::project_version);
    return 0;
  }
  if (options.pty && !options.tty.empty()) {
    std::fprintf(stderr, "odocal-linux: --pty and --tty exclude each other\n");
    return kExitUsage;
  }
  return -1;
}

/// Opens every line and PWM channel of `config` and prints the wiring on stderr. @return false
/// (the reason printed) when any cannot be set up.
bool open_robot(Robot& robot, const LinuxConfig& config) {
  const SetupResult wired = robot.open(config);
  if (!wired.ok()) {
    std::fprintf(stderr, "odocal-linux: %s\n", wired.message.c_str());
    return false;
  }
  std::fprintf(stderr,
               "odocal-linux: encoders %s/%s %s/%s, direction %s %s, PWM left %s, right %s\n",
               describe(config.left_a).c_str(), describe(config.left_b).c_str(),
               describe(config.right_a).c_str(), describe(config.right_b).c_str(),
               describe(config.left_dir).c_str(), describe(config.right_dir).c_str(),
               robot.left_pwm.description.c_str(), robot.right_pwm.description.c_str());
  return true;
}

/// The console's byte stream: stdio, a pty or a serial port (`tty_fd`, closed by the caller).
struct ConsoleStream {
  std::unique_ptr<posix::FdByteStream> fd_stream;
  std::unique_ptr<posix::PtyByteStream> pty_stream;
  hal::ByteStream* raw = nullptr;
  int input_fd = -1;
  int tty_fd = -1;
};

/// Opens the console stream the options ask for. @return false (the reason printed) when the
/// pty or the serial port cannot be opened.
bool open_console_stream(const Options& options, ConsoleStream& stream) {
  std::string error;
  if (options.pty) {
    stream.pty_stream = std::make_unique<posix::PtyByteStream>();
    if (!stream.pty_stream->open(error)) {
      std::fprintf(stderr, "odocal-linux: pty: %s\n", error.c_str());
      return false;
    }
    std::fprintf(stderr, "odocal-linux: console on %s\n", stream.pty_stream->slave_name().c_str());
    stream.raw = stream.pty_stream.get();
    stream.input_fd = stream.pty_stream->input_fd();
    return true;
  }
  if (!options.tty.empty()) {
    stream.tty_fd = open_tty(options.tty, error);
    if (stream.tty_fd < 0) {
      std::fprintf(stderr, "odocal-linux: console %s\n", error.c_str());
      return false;
    }
  }
  const int tty_fd = stream.tty_fd;
  stream.fd_stream = std::make_unique<posix::FdByteStream>(tty_fd >= 0 ? tty_fd : STDIN_FILENO,
                                                           tty_fd >= 0 ? tty_fd : STDOUT_FILENO);
  stream.raw = stream.fd_stream.get();
  stream.input_fd = stream.fd_stream->input_fd();
  return true;
}

/// The console's options on this target: echo and CRLF on a terminal, and this target's
/// `status` pairs.
console::ConsoleOptions console_options_for(const Options& options, const ConsoleStream& stream,
                                            Robot& robot) {
  const bool terminal = options.pty || stream.tty_fd >= 0 || isatty(STDIN_FILENO) == 1;
  console::ConsoleOptions console_options;
  console_options.echo = terminal ? console::EchoMode::automatic : console::EchoMode::off;
  console_options.crlf = terminal;
  console_options.banner = true;
  console_options.status_pairs = &linux_status_pairs;  // tick_rt, lateness, dropped edges, ...
  console_options.status_context = &robot;
  return console_options;
}

/// The control tick's rate the loop's configuration asks for, Hz.
std::uint32_t control_rate_hz(const Robot& robot) {
  return static_cast<std::uint32_t>(robot.loop->config().control_hz + 0.5f);
}

/// Starts the encoder-event thread, the console (which loads the saved parameters), then the
/// control tick at the rate they give, `rate_hz`, and enables the motor driver; warns when the
/// threads are not real-time. @return false (the reason printed) when a thread cannot start.
bool start_robot(Robot& robot, const LinuxConfig& config, console::Console& console,
                 std::uint32_t& rate_hz) {
  SetupResult started = robot.encoders->start(config.event_priority, config.event_holdback_us);
  if (!started.ok()) {
    std::fprintf(stderr, "odocal-linux: %s\n", started.message.c_str());
    return false;
  }
  static_cast<void>(console.start(robot.clock.now_us()));
  rate_hz = control_rate_hz(robot);
  if (robot.tick->start(rate_hz, &Robot::on_tick, &robot) == 0u) {
    std::fprintf(stderr, "odocal-linux: control tick: %s\n", robot.tick->error().c_str());
    return false;
  }
  robot.enable.set(true);
  if (!robot.encoders->realtime() || !robot.tick->stats().realtime || config.tick_priority == 0) {
    std::fprintf(stderr, "odocal-linux: threads not on SCHED_FIFO (%s); see `status`\n",
                 config.tick_priority == 0 ? "priority 0 configured"
                                           : "needs root, CAP_SYS_NICE or an rtprio limit");
  }
  return true;
}

/// Serves the console until SIGINT or SIGTERM, or the end of its input (stdio, a serial port),
/// restarting the tick when `set control_hz` changes the rate it started at, `rate_hz`.
void serve_console(Robot& robot, console::Console& console, const ConsoleStream& stream,
                   std::uint32_t rate_hz) {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::uint32_t last_rate_check_us = robot.clock.now_us();
  while (!stop_requested.load()) {
    pollfd wait{stream.input_fd, POLLIN, 0};
    // Short sleeps: `stream odom` lines and queued output are due without input.
    static_cast<void>(poll(&wait, 1, console.idle() ? 5 : 0));
    const std::uint32_t now_us = robot.clock.now_us();
    console.poll(now_us);
    if (now_us - last_rate_check_us > 100000u) {
      last_rate_check_us = now_us;
      const std::uint32_t wanted = control_rate_hz(robot);
      if (wanted != rate_hz) {  // `set control_hz` took effect in the loop: follow it
        rate_hz = wanted;
        static_cast<void>(robot.tick->start(rate_hz, &Robot::on_tick, &robot));
      }
    }
    const auto& fd_stream = stream.fd_stream;
    if (fd_stream && (fd_stream->end_of_input() || fd_stream->output_broken()) && console.idle()) {
      break;
    }
  }
}

int run(const Options& options, const LinuxConfig& config) {
  Robot robot;
  if (!open_robot(robot, config)) {
    return kExitSetup;
  }
  if (options.check) {
    std::fprintf(stderr, "odocal-linux: --check: every line and channel set up\n");
    robot.shut_down();
    return 0;
  }

  const std::string store_path = options.store.empty() ? config.store : options.store;
  posix::FileBlockStore flash(store_path);
  std::string error;
  if (!flash.open(error)) {
    std::fprintf(stderr, "odocal-linux: store %s: %s\n", store_path.c_str(), error.c_str());
    robot.shut_down();
    return kExitSetup;
  }
  params::ParamStore store(flash);

  ConsoleStream stream;
  if (!open_console_stream(options, stream)) {
    robot.shut_down();
    return kExitSetup;
  }
  const console::ConsoleOptions console_options = console_options_for(options, stream, robot);
  console::Console console(*stream.raw, *robot.loop, store, console_options);

  std::uint32_t rate_hz = 0u;
  if (!start_robot(robot, config, console, rate_hz)) {
    robot.shut_down();
    return kExitSetup;
  }
  serve_console(robot, console, stream, rate_hz);
  robot.shut_down();
  if (stream.tty_fd >= 0) {
    stream.fd_stream.reset();
    ::close(stream.tty_fd);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  const int parsed = parse_options(argc, argv, options);
  if (parsed >= 0) {
    return parsed;
  }
  LinuxConfig config;
  std::string error;
  if (!linux_target::load_config(options.config, config, error)) {
    std::fprintf(stderr, "odocal-linux: %s\n", error.c_str());
    return kExitUsage;
  }
  return run(options, config);
}
