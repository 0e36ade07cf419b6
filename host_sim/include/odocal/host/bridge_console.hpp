#pragma once
/// @file
/// An odocal console for a robot that runs ROSArduinoBridge (DESIGN "ROS robots"; docs/ros.md,
/// "Calibrating a ROSArduinoBridge robot"). The session talks to it as to any odocal robot; it
/// keeps the parameters on the host and drives the robot through the bridge's own commands: the
/// core's path executor and odometry (the one model, with the factors in force here) run on the
/// host once per 30 Hz frame, on the counts `e` reads, and send each wheel's speed as `m` in
/// counts per frame. Nothing is ever written to the robot's memory: `save` is refused, and the
/// session writes diff_drive_controller.yaml instead.
///
/// Console lines it answers as the firmware does (docs/console.md): echo, version, status,
/// params, get, set, load, provenance, fit apply, odom, odom reset, run line|unseen|umbmark-cw|
/// umbmark-ccw, drive v w ms, stop, trial, stream ticks|off, selftest [left|right], and `measure`
/// (passed to the robot: odocal-sim's tape). Anything else: `err unknown_command`.

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/odometry.hpp"
#include "odocal/host/robot_link.hpp"

namespace odocal::host {

/// What the robot's owner tells odocal about a ROSArduinoBridge robot (its nominal geometry).
struct BridgeNominal {
  double wheel_diameter_mm = 0.0;
  double wheelbase_mm = 0.0;
  double counts_per_rev = 0.0;
};

class BridgeConsole final : public LineChannel {
 public:
  /// ROSArduinoBridge's PID frame (PID_RATE), Hz: `m` speeds are counts per 1/30 s.
  static constexpr int frame_hz = 30;

  /// @param link the robot's serial line (its lines are ended with a bare CR from now on);
  /// @param lockstep the robot is odocal-sim in lockstep (one PID frame per `e`): frames follow
  /// each other at once instead of every 1/30 s of the wall clock.
  BridgeConsole(FdChannel& link, const BridgeNominal& nominal, bool lockstep);

  /// An odocal console line; its reply (and any `#` lines) are read with read_line().
  void write_line(const std::string& line) override;
  /// The next reply or `#` line; while the robot moves or a stream runs, the frames that are due
  /// (at most `timeout_ms` of them in lockstep, of robot time).
  bool read_line(std::string& line, int timeout_ms) override;
  [[nodiscard]] std::string name() const override;

  /// The parameters in force on the host (what the robot is driven and measured with).
  [[nodiscard]] const drive::DriveConfig& config() const { return config_; }
  [[nodiscard]] const BridgeNominal& nominal() const { return nominal_; }
  /// The baud rate the robot reported (`b`), 0 before the first line.
  [[nodiscard]] long baud() const { return baud_; }

 private:
  enum class Motion { idle, path, timed, settling };
  struct Trial {
    std::int64_t number = 0;
    std::string path;
    double duration_ms = 0.0;
    std::int64_t count_l = 0;
    std::int64_t count_r = 0;
    drive::Pose pose{};
  };

  void connect();
  /// Sends `command` (CR-ended) and returns its reply: the first line `expected` accepts (any line
  /// without it); throws LinkError naming `what` was expected.
  std::string ask(const std::string& command, int timeout_ms = 2000,
                  const std::function<bool(const std::string&)>& expected = {},
                  const char* what = "a reply");
  void ask_ok(const std::string& command);
  void answer(const std::string& line);
  /// The parameter commands (get, set, params, provenance, load, save, fit apply): false when
  /// `w` is none of them.
  bool answer_parameters(const std::vector<std::string>& w, const std::string& line);
  void frame();
  void send_wheels(const drive::Twist& twist);
  void stop_wheels();
  void begin_motion(Motion motion, const std::string& path_name);
  void begin_settling();
  [[nodiscard]] double now_ms() const;
  [[nodiscard]] bool active() const { return motion_ != Motion::idle || streaming_; }
  void configure();
  [[nodiscard]] std::string parameter_reply(const drive::ConfigField& field) const;
  void command_set(const std::string& name, const std::string& value);
  void command_fit_apply(const std::string& line);
  void command_run(const std::string& line);
  void command_drive(const std::string& line);
  void command_selftest(const std::string& which);
  void command_params();
  void command_measure(const std::string& line);
  long wheel_counts(int side, double counts_per_frame_wanted);
  /// `e`: the robot's two counts.
  void read_counts(std::int32_t raw[2]);
  /// Whether `raw` lies farther from the last counts than the wheels turn in a frame.
  [[nodiscard]] bool jumped(const std::int32_t raw[2]) const;
  void reply(const std::string& text) { queue_.push_back(text); }

  FdChannel& link_;
  BridgeNominal nominal_;
  bool lockstep_;
  bool connected_ = false;
  long baud_ = 0;
  drive::DriveConfig config_{};
  drive::DriveConfig started_{};  ///< `load`: what the session started with
  drive::DiffDriveKinematics kinematics_{};
  drive::Odometry odometry_{};
  drive::MotionExecutor executor_{};
  std::deque<std::string> queue_;
  bool streaming_ = false;
  bool streaming_crc_ = false;  ///< `# ticks` lines end with " crc=" (stream ticks <hz> crc)
  bool unsaved_ = false;
  std::map<std::string, std::string> provenance_;

  // Counts: the robot's 32-bit ones unwrapped into cumulative 64-bit ones.
  bool have_raw_ = false;
  std::int32_t raw_[2] = {0, 0};
  std::int64_t cumulative_[2] = {0, 0};
  std::int64_t frame_delta_[2] = {0, 0};

  // Time: frames counted in lockstep, the wall clock otherwise.
  std::uint64_t frames_ = 0;
  std::chrono::steady_clock::time_point start_{};
  std::chrono::steady_clock::time_point next_frame_{};
  double last_frame_ms_ = 0.0;

  // The motion under way and its trial.
  Motion motion_ = Motion::idle;
  std::string motion_path_;
  double motion_start_ms_ = 0.0;
  std::int64_t motion_start_counts_[2] = {0, 0};
  drive::Twist timed_twist_{};
  double timed_ms_ = 0.0;
  double settle_start_ms_ = 0.0;
  double still_ms_ = 0.0;
  double carry_[2] = {0.0, 0.0};  ///< fractions of a count per frame not yet sent (dithering)
  bool wheels_stopped_ = true;
  std::int64_t trials_ = 0;
  bool have_trial_ = false;
  Trial trial_{};
};

}  // namespace odocal::host
