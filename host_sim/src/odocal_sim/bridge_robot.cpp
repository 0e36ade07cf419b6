// odocal-sim --protocol ros-arduino-bridge: a simulated robot that runs ROSArduinoBridge instead
// of odocal (docs/simulation.md, "A ROSArduinoBridge robot"). The robot file's true geometry on
// the hal/sim plant; the firmware is ROSArduinoBridge's as its source has it: a PID on encoder
// counts per 30 Hz frame (diff_controller.h: Kp 20, Kd 12, Ki 0, Ko 50, integer arithmetic, the
// output accumulated and clamped to +-255 PWM), the 2000 ms auto-stop, and the serial commands
// as runCommand (ROSArduinoBridge.ino, commands.h) reads and answers them in a USE_BASE build:
// e, r, m, u, b, the pin commands a, c, d, w, x, the sonar's p, and the raw PWM o of joshnewans'
// firmware (the one diffdrive_arduino's author points to). A command ends at a CR only; its
// arguments are read with atoi. No odometry, no paths, no parameters. Beside them the
// simulator's own tape measure, `measure`.

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
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
    // The auto-stop stops raw PWM (`o`) too: it does not look at `moving`.
    if (now_ms() - last_motor_ms_ > kAutoStopMs) {
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

  /// One command as the firmware's loop() collected it before the CR: its letter and its two
  /// argument words. The reply line (without CR LF).
  std::string answer(char command, const std::string& argv1, const std::string& argv2) {
    const long a = atoi_of(argv1);
    const long b = atoi_of(argv2);
    switch (command) {
      case 'e':
        return std::to_string(count32(0)) + " " + std::to_string(count32(1));
      case 'r':
        offset_[0] = plant_.left().encoder_count();
        offset_[1] = plant_.right().encoder_count();
        reset_pid();                  // the targets to 0 with the rest: the PID brakes the wheels
        frame_pose_ = plant_.pose();  // the tape's frame: where the robot stands now
        ++resets_;
        return "OK";
      case 'm':
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
      case 'o':  // raw PWM: the PID off, the duties as given (setMotorSpeeds clamps them)
        last_motor_ms_ = now_ms();
        reset_pid();
        moving_ = false;
        set_motors(std::clamp(a, -kMaxPwm, kMaxPwm), std::clamp(b, -kMaxPwm, kMaxPwm));
        return "OK";
      case 'u':
        gains(argv1);
        return "OK";
      case 'b':
        return std::to_string(kBaud);
      case 'a':  // analogRead, digitalRead: no pin is wired in the simulation
      case 'd':
      case 'p':  // Ping: no sonar answers, pulseIn times out, 0 cm
        return "0";
      case 'c':  // pinMode, digitalWrite, analogWrite
      case 'w':
      case 'x':
        return "OK";
      default:
        break;
    }
    return "Invalid Command";
  }

  /// The simulator's tape (not the firmware's): the true pose in the frame of the last `r`.
  std::string measure() { return tape(); }

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

  /// C's atoi of an argument word, as runCommand reads it: spaces, a sign, digits up to the
  /// first other character; none: 0. Held within 32 bits (where atoi would overflow).
  static long atoi_of(const std::string& word) {
    const long value = std::strtol(word.c_str(), nullptr, 10);
    return std::clamp<long>(value, INT32_MIN, INT32_MAX);
  }

  /// `u p:d:i:o`: the gains, in that order, each read with atoi between the colons (strtok: empty
  /// fields are skipped; missing ones left as they were).
  void gains(const std::string& args) {
    long* targets[4] = {&kp_, &kd_, &ki_, &ko_};
    std::size_t field = 0;
    std::size_t at = 0;
    while (field < 4u && at < args.size()) {
      const std::size_t end = std::min(args.find(':', at), args.size());
      if (end > at) {
        *targets[field++] = atoi_of(args.substr(at, end - at));
      }
      at = end + 1u;
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
  std::string tape() {
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
  std::int64_t last_motor_ms_ = -kAutoStopMs;  // lastMotorCommand starts so: no stop pending
  std::uint64_t frame_ = 0;
  std::int64_t offset_[2] = {0, 0};
  sim::WorldPose frame_pose_{};
  std::uint32_t resets_ = 0;  ///< `r`s so far (each a new tape frame)
  std::string last_reading_;  ///< the last `measure`, while the robot stands where it was
  sim::WorldPose read_at_{};
  std::uint32_t frames_read_ = 0;
};

/// ROSArduinoBridge's loop() reading the serial port: a CR runs the command collected so far;
/// a space steps to the next argument (a third word runs on into the second argument, as there);
/// any other byte, LF included, is the command letter while no space came (the last such byte
/// is the letter), else a character of the argument. So a line ended by LF alone gets no reply,
/// and its bytes are part of the next command.
class FirmwareReader {
 public:
  /// Feeds `byte`; true when it was a CR (the command is then in letter(), argv1(), argv2()).
  bool feed(std::uint8_t byte) {
    if (byte == '\r') {
      letter_ = command_;
      argv1_.swap(pending1_);
      argv2_.swap(pending2_);
      line_.swap(pending_line_);
      command_ = '\0';
      arg_ = 0;
      pending1_.clear();
      pending2_.clear();
      pending_line_.clear();
      return true;
    }
    if (pending_line_.size() < 256u && byte != '\n') {
      pending_line_.push_back(static_cast<char>(byte));
    }
    if (byte == ' ') {
      arg_ = arg_ == 0 ? 1 : 2;
      return false;
    }
    // The firmware's argv1 and argv2 hold 31 characters (and overflow beyond): kept to that.
    if (arg_ == 0) {
      command_ = static_cast<char>(byte);
    } else if (std::string& argv = arg_ == 1 ? pending1_ : pending2_; argv.size() < 31u) {
      argv.push_back(static_cast<char>(byte));
    }
    return false;
  }
  [[nodiscard]] char letter() const { return letter_; }
  [[nodiscard]] const std::string& argv1() const { return argv1_; }
  [[nodiscard]] const std::string& argv2() const { return argv2_; }
  /// The bytes since the previous CR, LFs left out (the simulator's `measure`).
  [[nodiscard]] const std::string& line() const { return line_; }

 private:
  char command_ = '\0';
  int arg_ = 0;
  std::string pending1_;
  std::string pending2_;
  std::string pending_line_;
  char letter_ = '\0';
  std::string argv1_;
  std::string argv2_;
  std::string line_;
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
  FirmwareReader reader;
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
      if (!reader.feed(chunk[i])) {
        continue;
      }
      if (reader.line() == "measure") {
        reply(*stream, robot.measure());  // the simulator's tape, before the firmware's `e`
        continue;
      }
      if (lockstep && reader.letter() == 'e') {
        robot.frame();
      }
      reply(*stream, robot.answer(reader.letter(), reader.argv1(), reader.argv2()));
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
