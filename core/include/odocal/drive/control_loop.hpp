#pragma once
/// @file
/// The fixed-rate control tick: encoders -> speed -> odometry -> motion -> kinematics -> PI -> PWM.

#include <cstdint>

#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/odometry.hpp"
#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/drive/trial.hpp"
#include "odocal/drive/velocity_estimator.hpp"
#include "odocal/drive/wheel_controller.hpp"
#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/pwm_output.hpp"

namespace odocal::drive {

/// Sticky fault bits. Any fault parks the motors (duty 0) until `stop()` acknowledges it.
enum FaultBits : std::uint8_t {
  fault_none = 0x00,
  fault_encoder_left = 0x01,  ///< illegal transitions above `max_illegal`
  fault_encoder_right = 0x02,
  fault_stall_left = 0x04,  ///< duty above `stall_duty` with no net motion for `stall_ms`
  fault_stall_right = 0x08,
  /// Every bit above: a new fault adds its bit here too (the console's fault names are
  /// static_asserted against it, core/src/console/commands_system.cpp).
  fault_all = 0x0F,
};

/// What the loop is doing.
enum class Mode : std::uint8_t { idle, drive, path, fault };

/// Name of a mode as the console prints it.
[[nodiscard]] const char* mode_name(Mode mode);

/// A consistent picture of the loop for the console.
struct LoopStatus {
  Mode mode = Mode::idle;
  PathId path = PathId::none;
  std::uint8_t segment = 0u;
  std::uint8_t faults = fault_none;
  std::uint32_t ticks = 0u;
  std::uint32_t illegal_left = 0u;
  std::uint32_t illegal_right = 0u;
  float left_radps = 0.0f;
  float right_radps = 0.0f;
  float left_duty = 0.0f;
  float right_duty = 0.0f;
  float tick_us_avg = 0.0f;  ///< from `note_tick_duration_us`, exponential average
  float tick_us_max = 0.0f;
  bool trial_open = false;         ///< a trial runs or settles (its record is not out yet)
  bool clipped = false;            ///< the last tick scaled the wheel set-points to max_wheel_radps
  std::uint32_t pose_resets = 0u;  ///< odometry resets taken effect since start-up
};

/// The wheels' cumulative encoder counts since start-up at one tick (wide: never wrap).
struct WheelCounts {
  std::uint64_t t_us = 0u;  ///< time of that tick since the first tick, µs
  std::int64_t left = 0;
  std::int64_t right = 0;
};

/// One H-bridge channel: PWM magnitude and a direction line (high = forward).
struct MotorChannel {
  hal::PwmOutput& pwm;
  hal::DigitalOutput& forward;
};

/// A direction line seen through an inverter: how the loop drives a motor whose leads are
/// reversed (WiringFix), with no per-tick test.
class InvertedOutput final : public hal::DigitalOutput {
 public:
  explicit InvertedOutput(hal::DigitalOutput& line) : line_(line) {}

 private:
  void do_set(bool level) override;  // out of line: its vtable lives in one object file
  hal::DigitalOutput& line_;
};

/// Owns the drive pipeline. The edge contexts feed `left_decoder()` / `right_decoder()`; the
/// tick context calls `tick()`; the main loop calls the command methods, which take the critical
/// section so the tick never sees half a command. Those methods also read tick-owned state (the
/// pose, the last trial) and load a new path into the executor under the section, so a tick must
/// never run while the main loop holds it: true for a tick interrupt on one core; a target whose
/// tick is a thread runs each `tick()` inside the critical section (firmware/linux does).
class ControlLoop {
 public:
  ControlLoop(MotorChannel left, MotorChannel right, hal::CriticalSection& critical,
              const DriveConfig& config = DriveConfig{});

  /// Decoders for the edge ISRs. ISR context.
  QuadratureDecoder& left_decoder() { return left_decoder_; }
  QuadratureDecoder& right_decoder() { return right_decoder_; }

  /// One control period. Tick context. @param now_us monotonic microseconds (wraps).
  void tick(std::uint32_t now_us);

  // --- main-loop API (each call is atomic with respect to the tick) ---

  /// Replaces the configuration from the next tick on; refused (nothing changed) when `check()`
  /// refuses it, and the result says why.
  ConfigCheck configure(const DriveConfig& config);
  [[nodiscard]] DriveConfig config() const;
  /// Drives at a body twist. With `duration_ms` > 0 it stops after that long; with 0 it stops
  /// when not renewed within `cmd_timeout_ms`. Cancels a running path. Refused in a fault.
  /// A timed drive is a trial unless `trial` is false (a set-point held until renewed or timed
  /// out, as ROSArduinoBridge's `m`).
  [[nodiscard]] bool drive(const Twist& twist, std::uint32_t duration_ms, bool trial = true);
  /// Starts a path from the current pose. Refused (false) in a fault or for an empty path.
  [[nodiscard]] bool run(const Path& path);
  /// Stops at once (set-points to zero), abandons any path, and acknowledges faults.
  void stop();
  /// The odometry pose (zero once `reset_pose` is asked, even before a tick takes it).
  [[nodiscard]] Pose pose() const;
  /// Sets the odometry pose to zero.
  void reset_pose();
  /// The loop's status as of the last tick, with a command not taken yet shown as taken (mode,
  /// path, faults acknowledged by `stop`), so a reply never contradicts the command before it.
  [[nodiscard]] LoopStatus status() const;
  /// The mode and faults the last tick published, read without the critical section: only for
  /// a caller that runs the ticks itself and asks between them (the host simulator's procedures,
  /// which ask after every tick).
  [[nodiscard]] Mode mode_after_tick() const { return published_.status.mode; }
  [[nodiscard]] std::uint8_t faults_after_tick() const { return published_.status.faults; }
  /// The last finished trial (number 0 before the first). A trial begins with a path or a timed
  /// drive and closes once the robot is at rest after it (TrialRecorder). This and
  /// `wheel_counts` are called from several places of the main loop (never the tick): out of
  /// line, one copy each in the robot's flash.
  [[nodiscard, gnu::noinline]] TrialRecord last_trial() const;
  /// Cumulative counts at the last tick, for logging runs.
  [[nodiscard, gnu::noinline]] WheelCounts wheel_counts() const;
  /// Records how long the last tick took, µs (the target measures it).
  void note_tick_duration_us(float duration_us);

 private:
  /// What the main loop asks of the tick; written and read only under the critical section.
  enum class Command : std::uint8_t { none, drive, run, stop };
  /// Set in the mailbox's duration_ms: a drive that is no trial, however long (a drive lasts at
  /// most a few minutes, far below 2^31 ms). A flag bit, not a command of its own: the tick
  /// tests it with the sign of the duration it tests anyway.
  static constexpr std::uint32_t held_bit = 0x80000000u;
  struct Inbox {
    DriveConfig config{};
    bool config_pending = false;
    Command command = Command::none;
    Twist twist{};
    std::uint32_t duration_ms = 0u;
    bool reset_pose = false;
  };
  /// The part of the mailbox the tick takes each time (small: the path and the configuration
  /// are copied only when they come, straight to where they are used).
  struct Taken {
    bool config_pending = false;
    Command command = Command::none;
    Twist twist{};
    std::uint32_t duration_ms = 0u;
    bool reset_pose = false;
  };
  /// What the tick shows the main loop; written and read only under the critical section.
  struct Published {
    LoopStatus status{};
    WheelCounts counts{};
  };

  void apply_config(const DriveConfig& config);
  // The tick's stages, in its order (each called once, from `tick`; inlined there).
  /// Snapshots the encoders and takes the main loop's requests, in one short critical section;
  /// a new configuration goes straight to config_ (the tick applies it outside the section).
  void take_inbox(EncoderSnapshot& left, EncoderSnapshot& right, Taken& inbox);
  /// Advances the loop's clock to `now_us` (the first tick starts the estimators). @return the
  /// period to integrate over, µs, at most kMaxTickGap_us.
  [[nodiscard]] std::uint32_t advance_clock(std::uint32_t now_us, const EncoderSnapshot& left,
                                            const EncoderSnapshot& right);
  /// The wheels' speeds, and the odometry from their increments.
  void estimate(const EncoderSnapshot& left, const EncoderSnapshot& right, std::uint32_t now_us);
  /// The wheels' duties for this tick, by mode: 0 in a fault; braking when nothing is to be
  /// driven; else motion -> twist -> inverse kinematics -> wheel PI. @return true when the set-
  /// points were scaled to max_wheel_radps.
  [[nodiscard]] bool wheel_duties(float dt_s, std::uint32_t dt_us, float& left_duty,
                                  float& right_duty);
  /// Publishes the status and the counts for the main loop, under the critical section.
  void publish(const EncoderSnapshot& left, const EncoderSnapshot& right, float left_duty,
               float right_duty, bool clipped);
  void take_command(const Taken& inbox, const EncoderSnapshot& left, const EncoderSnapshot& right);
  [[nodiscard]] Twist twist_for_mode(float dt_s, std::uint32_t dt_us);
  void check_faults(const EncoderSnapshot& left, const EncoderSnapshot& right, std::uint32_t dt_us);
  void drive_motors(float left_duty, float right_duty);
  /// Points the outputs and the decoders' counters where `wiring_fix` says. Call where neither
  /// an edge nor the tick can interrupt (`configure`, under the critical section; the
  /// constructor, before they are enabled).
  void apply_wiring(std::uint32_t wiring_fix);

  MotorChannel left_;   ///< the left motor connector
  MotorChannel right_;  ///< the right motor connector
  hal::CriticalSection& critical_;

  /// One wheel's tick-owned state: its speed, its speed loop, the watch for its faults and its
  /// braking.
  struct Wheel {
    // Built in place in the loop's constructor: out of line, one copy for both wheels cost the
    // robot's flash more than it saved.
    [[gnu::always_inline]] Wheel() {}  // NOLINT(modernize-use-equals-default)
    VelocityEstimator speed;
    WheelController controller;
    std::uint32_t illegal_base = 0u;  ///< its decoder's illegal count that `stop` acknowledged
    std::uint32_t stall_us = 0u;      ///< time with a large duty and no net motion
    std::int64_t stall_start = 0;     ///< position where the current stall window began
    float duty = 0.0f;                ///< the duty the last tick drove
    /// Braking after a drive ends or `stop`: the speed loop holds a zero set-point until the
    /// wheel is at rest (direction of travel at the start: +1, -1; 0 = released).
    int brake_sign = 0;
  };

  /// Watches `wheel` for a stall over one more tick of `dt_us`. @return true when stalled for
  /// longer than stall_ms. One copy called for each wheel: inlined twice it cost the robot's flash
  /// 52 bytes, called it costs the tick about 60 instructions (docs/performance.md).
  [[gnu::noinline]] bool stalled(Wheel& wheel, std::uint32_t dt_us);
  /// Starts braking the wheels that are turning (a drive ended, or `stop`).
  void start_braking();
  /// One wheel's duty while braking: −kp·speed until the wheel is at rest (or turns the other
  /// way), then 0 and its brake_sign cleared. Keeps its controller reset.
  float brake_duty(Wheel& wheel);

  // Tick-owned state (only the tick touches it; `run` loads motion_ under the critical section).
  DriveConfig config_;
  DiffDriveKinematics kinematics_;
  Wheel left_wheel_;
  Wheel right_wheel_;
  Odometry odometry_;  ///< also read by `pose` under the critical section
  MotionExecutor motion_;
  TrialRecorder trial_;  ///< its last() is also read by the main loop, under the critical section
  Mode mode_ = Mode::idle;
  std::uint8_t faults_ = fault_none;
  Twist drive_twist_{};
  std::uint32_t drive_ms_ = 0u;
  std::uint32_t drive_age_us_ = 0u;
  std::uint32_t last_tick_us_ = 0u;
  std::uint64_t clock_us_ = 0u;  ///< since the first tick, unwrapped
  std::uint32_t ticks_ = 0u;
  std::uint32_t pose_resets_ = 0u;
  bool started_ = false;
  std::uint32_t brake_us_ = 0u;  ///< time since braking started

  // Shared with the main loop under the critical section.
  Inbox inbox_{};
  Published published_{};

  // Last, so that adding them moved no field the tick addresses beyond the short offsets of
  // its loads and stores (the tick's instruction count did not change, docs/performance.md).
  // Edge-owned state (the edge contexts write, the tick snapshots under the critical section).
  QuadratureDecoder left_decoder_;
  QuadratureDecoder right_decoder_;
  InvertedOutput left_inverted_{left_.forward};
  InvertedOutput right_inverted_{right_.forward};
  // What the tick drives as the left and right motors (WiringFix: swapped, inverted).
  hal::PwmOutput* left_pwm_ = &left_.pwm;
  hal::DigitalOutput* left_forward_ = &left_.forward;
  hal::PwmOutput* right_pwm_ = &right_.pwm;
  hal::DigitalOutput* right_forward_ = &right_.forward;
};

}  // namespace odocal::drive
