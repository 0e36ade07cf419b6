// odocal-sim --protocol ros-arduino-bridge: a simulated robot that runs ROSArduinoBridge instead
// of odocal (docs/simulation.md, "A ROSArduinoBridge robot"). The robot file's true geometry on
// the hal/sim plant; the firmware is ROSArduinoBridge's as its source has it: a PID on encoder
// counts per 30 Hz frame (diff_controller.h: Kp 20, Kd 12, Ki 0, Ko 50, integer arithmetic, the
// output accumulated and clamped to +-255 PWM), the 2000 ms auto-stop, and the serial commands
// e, r, m, u, b (ROSArduinoBridge.ino's runCommand, commands.h). No odometry, no paths, no
// parameters. Beside them the simulator's own tape measure, `measure`.

#include <poll.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>

#include "odocal/posix/fd_byte_stream.hpp"
#include "odocal/sim/plant.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "sim_app.hpp"

namespace odocal::sim_app {
namespace {

constexpr int kFrameHz = 30;                // PID_RATE
constexpr std::int64_t kAutoStopMs = 2000;  // AUTO_STOP_INTERVAL
constexpr long kMaxPwm = 255;               // MAX_PWM
constexpr long kBaud = 57600;               // BAUDRATE

/// One wheel's PID state, as diff_controller.h keeps it (the firmware's integer types).
struct WheelPid {
  long target = 0;  ///< counts per frame
  long encoder = 0;
  long previous_encoder = 0;
  long previous_input = 0;
  long integral = 0;
  long output = 0;
};

/// The robot: the plant, ROSArduinoBridge's loop, and the line protocol.
class BridgeRobot {
 public:
  BridgeRobot(const host::RobotSpec& spec, std::uint64_t seed) : plant_(spec.truth, seed) {
    reset_pid();
  }

  /// Runs the plant to the next frame and does what ROSArduinoBridge's loop does there.
  void frame() {
    ++frame_;
    plant_.advance_to_ns(frame_ns(frame_));
    if (moving_ && now_ms() - last_motor_ms_ > kAutoStopMs) {
      set_motors(0, 0);
      moving_ = false;
    }
    update_pid();
  }

  /// A reset of the board (a brown-out): the motors stop, the PID starts afresh and the counts
  /// start again from 0 (ROSArduinoBridge keeps nothing over a reset); the body stays where it is.
  void restart() {
    set_motors(0, 0);
    moving_ = false;
    reset_pid();
    left_.target = 0;
    right_.target = 0;
    offset_[0] = plant_.left().encoder_count();
    offset_[1] = plant_.right().encoder_count();
  }

  [[nodiscard]] std::uint64_t next_frame_ns() const { return frame_ns(frame_ + 1); }
  [[nodiscard]] double simulated_s() const { return static_cast<double>(plant_.now_ns()) * 1e-9; }

  /// One command line (without its terminator): the reply line (without CR LF).
  std::string answer(const std::string& line) {
    const char command = line.empty() ? '\0' : line[0];
    const std::string args = line.size() > 1 ? line.substr(1) : std::string();
    if (line == "measure") {
      return measure();  // the simulator's tape, before `m` would take it for a motor command
    }
    long a = 0;
    long b = 0;
    switch (command) {
      case 'e':
        return std::to_string(count32(0)) + " " + std::to_string(count32(1));
      case 'r':
        offset_[0] = plant_.left().encoder_count();
        offset_[1] = plant_.right().encoder_count();
        reset_pid();
        frame_pose_ = plant_.pose();  // the tape's frame: where the robot stands now
        ++resets_;
        return "OK";
      case 'm':
        two_args(args, a, b);
        last_motor_ms_ = now_ms();
        if (a == 0 && b == 0) {
          set_motors(0, 0);
          reset_pid();
          moving_ = false;
        } else {
          moving_ = true;
        }
        left_.target = a;
        right_.target = b;
        return "OK";
      case 'u':
        gains(args);
        return "OK";
      case 'b':
        return std::to_string(kBaud);
      default:
        break;
    }
    return "Invalid Command";
  }

 private:
  static std::uint64_t frame_ns(std::uint64_t k) {
    return static_cast<std::uint64_t>(std::llround(static_cast<double>(k) * 1e9 / kFrameHz));
  }
  [[nodiscard]] std::int64_t now_ms() const {
    return static_cast<std::int64_t>(plant_.now_ns() / 1000000u);
  }
  [[nodiscard]] std::int64_t count(int side) const {
    return (side == 0 ? plant_.left().encoder_count() : plant_.right().encoder_count()) -
           offset_[side];
  }
  /// The count as the firmware's 32-bit `long` holds it (it wraps).
  [[nodiscard]] long count32(int side) const {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(count(side)));
  }

  /// atoi of the first two words, as runCommand parses `m`.
  static void two_args(const std::string& args, long& a, long& b) {
    const char* text = args.c_str();
    char* end = nullptr;
    a = std::strtol(text, &end, 10);
    b = std::strtol(end, nullptr, 10);
  }

  /// `u p:d:i:o`: the gains, in that order (missing ones left as they were).
  void gains(const std::string& args) {
    long* targets[4] = {&kp_, &kd_, &ki_, &ko_};
    std::size_t at = args.find_first_not_of(' ');
    for (long* target : targets) {
      if (at == std::string::npos || at >= args.size()) {
        break;
      }
      *target = std::strtol(args.c_str() + at, nullptr, 10);
      at = args.find(':', at);
      at = at == std::string::npos ? at : at + 1;
    }
    if (ko_ == 0) {
      ko_ = 1;  // the firmware would divide by zero; the simulation keeps going
    }
  }

  void reset_pid() {
    for (int side = 0; side < 2; ++side) {
      WheelPid& p = side == 0 ? left_ : right_;
      p = WheelPid{};
      p.encoder = count32(side);
      p.previous_encoder = p.encoder;
    }
  }

  void pid(WheelPid& p) const {
    const long input = p.encoder - p.previous_encoder;
    const long error = p.target - input;
    long output = (kp_ * error - kd_ * (input - p.previous_input) + p.integral) / ko_;
    p.previous_encoder = p.encoder;
    output += p.output;
    if (output >= kMaxPwm) {
      output = kMaxPwm;
    } else if (output <= -kMaxPwm) {
      output = -kMaxPwm;
    } else {
      p.integral += ki_ * error;
    }
    p.output = output;
    p.previous_input = input;
  }

  void update_pid() {
    left_.encoder = count32(0);
    right_.encoder = count32(1);
    if (!moving_) {
      if (left_.previous_input != 0 || right_.previous_input != 0) {
        reset_pid();
      }
      return;
    }
    pid(right_);
    pid(left_);
    set_motors(left_.output, right_.output);
  }

  void set_motors(long left, long right) {
    sim::Wheel* wheels[2] = {&plant_.left(), &plant_.right()};
    const long pwm[2] = {left, right};
    for (int side = 0; side < 2; ++side) {
      wheels[side]->forward().set(pwm[side] >= 0);
      wheels[side]->pwm().set_duty(static_cast<float>(std::labs(pwm[side])) /
                                   static_cast<float>(kMaxPwm));
    }
  }

  /// The tape: the true pose plus the robot file's noise, in the frame of the last `r`; asked
  /// again where the robot stands still, the same reading (a note taken once).
  std::string measure() {
    const sim::WorldPose truth = plant_.pose();
    if (!last_reading_.empty() && truth.x_m == read_at_.x_m && truth.y_m == read_at_.y_m &&
        truth.theta_rad == read_at_.theta_rad && frames_read_ == resets_) {
      return last_reading_;
    }
    read_at_ = truth;
    frames_read_ = resets_;
    const sim::WorldPose world = plant_.measure();
    const double dx = world.x_m - frame_pose_.x_m;
    const double dy = world.y_m - frame_pose_.y_m;
    const double c = std::cos(frame_pose_.theta_rad);
    const double s = std::sin(frame_pose_.theta_rad);
    const double theta =
        std::remainder(world.theta_rad - frame_pose_.theta_rad, 2.0 * std::numbers::pi);
    char text[128];
    std::snprintf(text, sizeof text, "ok x_mm=%.3f y_mm=%.3f theta_deg=%.3f",
                  1000.0 * (c * dx + s * dy), 1000.0 * (-s * dx + c * dy),
                  theta * 180.0 / std::numbers::pi);
    last_reading_ = text;
    return text;
  }

  sim::Plant plant_;
  WheelPid left_;
  WheelPid right_;
  long kp_ = 20;
  long kd_ = 12;
  long ki_ = 0;
  long ko_ = 50;
  bool moving_ = false;
  std::int64_t last_motor_ms_ = 0;
  std::uint64_t frame_ = 0;
  std::int64_t offset_[2] = {0, 0};
  sim::WorldPose frame_pose_{};
  std::uint32_t resets_ = 0;  ///< `r`s so far (each a new tape frame)
  std::string last_reading_;  ///< the last `measure`, while the robot stands where it was
  sim::WorldPose read_at_{};
  std::uint32_t frames_read_ = 0;
};

/// Splits bytes into lines (CR, LF or CR LF end one) and answers each.
class LineSplitter {
 public:
  /// Feeds `byte`; true when it ended a line, which is then in `line`.
  bool feed(std::uint8_t byte, std::string& line) {
    const bool after_cr = after_cr_;
    after_cr_ = byte == '\r';
    if (byte == '\n' && after_cr) {
      return false;  // the LF of a CR LF
    }
    if (byte == '\r' || byte == '\n') {
      line.swap(pending_);
      pending_.clear();
      return true;
    }
    if (pending_.size() < 256u) {
      pending_.push_back(static_cast<char>(byte));
    }
    return false;
  }

 private:
  std::string pending_;
  bool after_cr_ = false;
};

void reply(hal::ByteStream& stream, const std::string& text) {
  const std::string line = text + "\r\n";
  std::size_t sent = 0;
  while (sent < line.size() && !stop_requested()) {
    const std::size_t n =
        stream.write(reinterpret_cast<const std::uint8_t*>(line.data()) + sent, line.size() - sent);
    sent += n;
    if (n == 0u) {
      ::usleep(1000);
    }
  }
}

}  // namespace

int run_bridge(const host::RobotSpec& spec, std::uint64_t seed, bool use_pty, double speed,
               double reset_after_s) {
  BridgeRobot robot(spec, seed);
  std::unique_ptr<posix::PtyByteStream> pty;
  std::unique_ptr<posix::FdByteStream> stdio;
  hal::ByteStream* stream = nullptr;
  int input_fd = -1;
  bool terminal = false;
  if (use_pty) {
    pty = std::make_unique<posix::PtyByteStream>();
    std::string error;
    if (!pty->open(error)) {
      std::fprintf(stderr, "odocal-sim: pty: %s\n", error.c_str());
      return 2;
    }
    std::printf("%s\n", pty->slave_name().c_str());
    std::fflush(stdout);
    stream = pty.get();
    input_fd = pty->input_fd();
    terminal = true;
  } else {
    stdio = std::make_unique<posix::FdByteStream>(STDIN_FILENO, STDOUT_FILENO);
    stream = stdio.get();
    input_fd = stdio->input_fd();
    terminal = ::isatty(STDIN_FILENO) == 1;
  }
  // In lockstep (as fast as possible, or scripted input) the robot's time moves one PID frame
  // with each `e`, before it is answered: the host reads the encoders once per frame, and the
  // same lines give the same robot on any machine. Otherwise it runs in real time (x speed).
  const bool lockstep = speed == 0.0 || !terminal;
  Pacer pacer(lockstep ? 0.0 : speed);
  install_stop_handlers();
  LineSplitter splitter;
  std::string line;
  std::uint8_t chunk[256];
  bool reset_done = false;
  while (!stop_requested()) {
    // A reset (SIGUSR1, or --reset-after once): the board restarts on the same line.
    if (take_reset_request() ||
        (reset_after_s > 0.0 && !reset_done && robot.simulated_s() >= reset_after_s)) {
      robot.restart();
      reset_done = true;
    }
    const std::size_t n = stream->read(chunk, sizeof chunk);
    for (std::size_t i = 0; i < n; ++i) {
      if (!splitter.feed(chunk[i], line)) {
        continue;
      }
      if (lockstep && line == "e") {
        robot.frame();
      }
      reply(*stream, robot.answer(line));
    }
    if (stdio && (stdio->end_of_input() || stdio->output_broken())) {
      break;
    }
    if (n > 0u) {
      continue;
    }
    if (lockstep) {
      pollfd wait{input_fd, POLLIN, 0};
      static_cast<void>(::poll(&wait, 1, 50));
      continue;
    }
    // Real time: the frames that are due, then a short wait for input.
    while (!stop_requested() &&
           static_cast<double>(robot.next_frame_ns()) * 1e-9 <= pacer.now_s()) {
      robot.frame();
    }
    pollfd wait{input_fd, POLLIN, 0};
    static_cast<void>(::poll(&wait, 1, 2));
  }
  return 0;
}

}  // namespace odocal::sim_app
