#pragma once
// Internal to odocal-sim: the pieces its main loop wires together (console streams, scripted
// input, pacing, the simulator's own `measure` command, the robot file's firmware defaults).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

#include "odocal/console/console.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/host/sim_robot.hpp"
#include "odocal/params/param_table.hpp"
#include "odocal/posix/fd_byte_stream.hpp"

namespace odocal::sim_app {

/// Set by SIGINT and SIGTERM: the main loop ends, scripted input stops being read.
[[nodiscard]] bool stop_requested();
/// Installs the SIGINT and SIGTERM handlers that set it, and SIGUSR1's, which asks for a reset.
void install_stop_handlers();
/// Whether SIGUSR1 asked for a reset of the robot since the last call (fault injection).
[[nodiscard]] bool take_reset_request();

/// The console's view of a stream whose input the program feeds itself (scripted stdin): it
/// writes through, and gives the console the script's bytes as they are fed.
class ScriptedStream final : public hal::ByteStream {
 public:
  explicit ScriptedStream(hal::ByteStream& inner) : inner_(inner) {}
  /// Queues script bytes for the console to read.
  void feed(const std::string& bytes) { pending_ += bytes; }
  /// Bytes fed and not yet read by the console.
  [[nodiscard]] std::size_t pending() const { return pending_.size() - taken_; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return inner_.write(data, size);
  }
  hal::ByteStream& inner_;
  std::string pending_;
  std::size_t taken_ = 0u;
};

/// The console's view of the pty in lockstep: passes bytes through and counts the input lines
/// the console has read (a CR, or a LF not right after a CR), so that the simulation can give
/// each line the same quantum of robot time whatever the host's timing.
class LineCountingStream final : public hal::ByteStream {
 public:
  explicit LineCountingStream(hal::ByteStream& inner) : inner_(inner) {}
  [[nodiscard]] std::uint64_t lines() const { return lines_; }
  /// While false, nothing is read: input waits in the pty until the robot time a line is given
  /// has passed, whenever the host sent it.
  void accept_input(bool accept) { accepting_ = accept; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override {
    return inner_.write(data, size);
  }
  hal::ByteStream& inner_;
  std::uint64_t lines_ = 0u;
  bool after_cr_ = false;
  bool accepting_ = true;
};

/// Reads scripted input from a non-blocking stream (waiting with poll) in pieces: each piece is
/// the rest of a line up to and including its end (CR, LF or CRLF), or, while no line end has
/// come, the bytes read so far. Pieces go to the console as they come, and its line editor takes
/// them exactly as from a terminal: a line longer than it keeps is refused whole, however long.
/// Every byte is looked at once and the memory is one fixed buffer, so a long line or endless
/// input without a line end (/dev/zero) costs linear time and constant memory.
class LineReader {
 public:
  explicit LineReader(posix::FdByteStream& stream) : stream_(stream) {}
  /// Next piece; `line_end` says whether it ends a line. False at end of input (a last
  /// unterminated line is ended with a LF).
  bool next(std::string& piece, bool& line_end);

 private:
  posix::FdByteStream& stream_;
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
  void wait_for(double simulated_s) const;
  /// The simulated time the wall clock has reached (speed > 0).
  [[nodiscard]] double now_s() const {
    return base_s_ +
           speed_ *
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  double speed_;
  std::chrono::steady_clock::time_point start_;
  double base_s_ = 0.0;
};

/// The firmware's parameter defaults on this simulated robot: the built-in ones, with the robot
/// file's nominal keys (wheel_diameter_mm, wheelbase_mm, counts_per_rev) as if the firmware had
/// been built for that robot. They are in force when the store holds no usable saved set, and
/// `defaults` restores them. @return false, with `error`, when the firmware would refuse them.
bool robot_defaults(const host::RobotSpec& spec, params::ParamSet& set, std::string& error);

/// The simulator's own console command, in the console's one target slot (`measure`): the tape
/// measure, and the floor the extended UMBmark needs (docs/simulation.md, "odocal-sim"). Real
/// targets have neither: they answer `err unknown_command`.
class SimCommand {
 public:
  /// @param default_cable_height_m the height `measure cables` lays when it is not given.
  SimCommand(host::SimulatedRobot& robot, double default_cable_height_m)
      : robot_(robot), default_cable_height_m_(default_cable_height_m) {}

  static void handle(void* context, const console::Token* words, std::size_t count,
                     console::Reply& reply);

  /// Call after each tick: at every odometry reset (a new run from the start mark) laid cables
  /// lie ahead of the robot again, as they do on a real floor for a robot put back on its mark.
  void follow_resets();

  /// Bare `measure` lines answered: questions, as the console counts its own (ConsoleCounters).
  [[nodiscard]] std::uint32_t questions() const { return questions_; }

  static constexpr const char* usage =
      "measure [cables off | cables FIRST_MM SPACING_MM COUNT left|right [HEIGHT_MM]] (sim only)";

 private:
  void measure(console::Reply& reply);
  void cables(const console::Token* words, std::size_t count, console::Reply& reply);
  void lay() { robot_.plant().lay_cables(right_, height_m_, first_m_, spacing_m_, count_); }

  host::SimulatedRobot& robot_;
  double default_cable_height_m_;
  bool laid_ = false;
  bool right_ = true;
  double height_m_ = 0.0;
  double first_m_ = 0.0;
  double spacing_m_ = 0.0;
  std::uint32_t count_ = 0u;
  std::uint32_t resets_seen_ = 0u;
  std::uint32_t questions_ = 0u;
  bool measured_ = false;  ///< the last reading, kept while the robot stands where it was read
  sim::WorldPose measured_truth_{};
  sim::WorldPose measured_pose_{};
  std::uint32_t measured_resets_ = 0u;
};

/// Line noise on what the robot sends (fault injection, --corrupt): each byte is lost with
/// probability rate/2 and has one of its 8 bits flipped with probability rate/2, from its own
/// seeded random stream (the same seed, the same damage to the same bytes).
class CorruptingStream final : public hal::ByteStream {
 public:
  CorruptingStream(hal::ByteStream& inner, double rate, std::uint64_t seed)
      : inner_(inner), rate_(rate), state_(seed * 0x9E3779B97F4A7C15ull + 1u) {}

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override {
    return inner_.read(out, capacity);
  }
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override;
  double uniform();

  hal::ByteStream& inner_;
  double rate_;
  std::uint64_t state_;
  bool decided_ = false;  ///< the next byte's fate is drawn (kept while the line is full)
  int fate_ = 0;          ///< -1 lost, 0 as sent, 1..8 that bit flipped
};

/// odocal-sim --protocol ros-arduino-bridge (bridge_robot.cpp): a simulated robot running
/// ROSArduinoBridge, on a pty or stdio, in lockstep (speed 0 or scripted input: one PID frame per
/// `e`) or in real time times `speed`; reset (its counts from 0 again) on SIGUSR1 or once after
/// `reset_after_s` of robot time (0: never). @return the exit status.
int run_bridge(const host::RobotSpec& spec, std::uint64_t seed, bool use_pty, double speed,
               double reset_after_s);

/// Whether the robot is busy: a motion, its trial not yet closed, or the self-test. Scripted
/// input waits for it (so `# done` comes first).
[[nodiscard]] bool busy(const drive::LoopStatus& status, const console::Console& console);

}  // namespace odocal::sim_app
