#pragma once
/// @file
/// The simulated robot: two DC motors with quadrature encoders, rigid-body motion on the floor,
/// slip, floor cables that each wheel rolls over, and the "absolute" measurement. It is the `sim`
/// HAL backend: the firmware sees it only through hal::PwmOutput, hal::DigitalOutput,
/// hal::DigitalInput and hal::MonotonicClock.
///
/// Fixed-size, no heap, no exceptions, no I/O: it also runs inside the QEMU firmware image.
/// Single-threaded: the owner advances it with `advance_to_ns()` from one event loop, and edge
/// handlers run from inside that call at the instants the encoder lines change.

#include <cstdint>

#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/digital_input.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/pwm_output.hpp"
#include "odocal/sim/random.hpp"
#include "odocal/sim/robot_model.hpp"

namespace odocal::sim {

/// Simulated time as the firmware sees it: microseconds modulo 2^32, set by the plant.
class SimClock final : public hal::MonotonicClock {
 public:
  /// Sets the time, ns since the start of the simulation.
  void set_ns(std::uint64_t t_ns) { t_ns_ = t_ns; }
  [[nodiscard]] std::uint64_t ns() const { return t_ns_; }

 private:
  std::uint32_t do_now_us() override { return static_cast<std::uint32_t>(t_ns_ / 1000u); }
  std::uint64_t t_ns_ = 0u;
};

/// The simulator's event loop is one thread: edges and ticks never preempt each other, so the
/// critical section has nothing to exclude.
class SimCriticalSection final : public hal::CriticalSection {
 private:
  void do_enter() override {}
  void do_exit() override {}
};

/// One encoder channel: a level the plant drives, and the handler the firmware registered.
class EncoderLine final : public hal::DigitalInput {
 public:
  /// Sets the level; runs the handler when it changed. Plant-internal.
  void drive(bool level) {
    if (level != level_) {
      level_ = level;
      if (handler_ != nullptr) {
        handler_(context_);
      }
    }
  }
  /// Inverts the level and runs the handler (one quadrature edge). Plant-internal.
  void toggle() {
    level_ = !level_;
    if (handler_ != nullptr) {
      handler_(context_);
    }
  }
  /// Sets the level without running the handler (initial state).
  void preset(bool level) { level_ = level; }
  [[nodiscard]] bool level() const { return level_; }

 private:
  bool do_read() override { return level_; }
  void do_on_edge(hal::EdgeHandler handler, void* context) override {
    handler_ = handler;
    context_ = context;
  }
  bool level_ = false;
  hal::EdgeHandler handler_ = nullptr;
  void* context_ = nullptr;
};

/// PWM input of one H-bridge channel: the duty the firmware last set.
class MotorPwm final : public hal::PwmOutput {
 public:
  [[nodiscard]] float duty() const { return duty_; }

 private:
  void do_set_duty(float duty) override { duty_ = duty; }
  float duty_ = 0.0f;
};

/// Direction input of one H-bridge channel (high = forward).
class MotorDirection final : public hal::DigitalOutput {
 public:
  [[nodiscard]] bool forward() const { return level_; }

 private:
  void do_set(bool level) override { level_ = level; }
  bool level_ = true;
};

/// One driven wheel: motor, gearbox, encoder and its ground contact.
class Wheel {
 public:
  hal::PwmOutput& pwm() { return pwm_; }
  hal::DigitalOutput& forward() { return direction_; }
  /// The encoder lines (their concrete type, so that wiring them costs no virtual call).
  EncoderLine& channel_a() { return a_; }
  EncoderLine& channel_b() { return b_; }

  /// Shaft angle since the start, rad (forward positive).
  [[nodiscard]] double angle_rad() const { return angle_rad_; }
  /// Shaft speed, rad/s.
  [[nodiscard]] double speed_radps() const { return speed_radps_; }
  /// Encoder position in counts (x4) since the start: the edges generated so far, signed.
  [[nodiscard]] std::int64_t encoder_count() const { return count_; }
  /// Motor terminal voltage applied during the last step, V.
  [[nodiscard]] double voltage_v() const { return voltage_v_; }
  /// Ground distance the contact point travelled, m (signed, with slip and bumps).
  [[nodiscard]] double ground_m() const { return ground_m_; }
  /// Floor cables (bumps) this wheel has started to roll over since construction.
  [[nodiscard]] std::uint32_t bumps_crossed() const { return bumps_; }

 private:
  friend class Plant;
  MotorPwm pwm_;
  MotorDirection direction_;
  EncoderLine a_;
  EncoderLine b_;
  MotorModel motor_{};
  double decay_ = 0.0;             ///< 1/time constant a, 1/s
  double torque_per_volt_ = 0.0;   ///< k/R, N·m per V
  double speed_per_torque_ = 0.0;  ///< 1/(J·a): steady speed per net torque, rad/s per N·m
  double step_factor_ = 0.0;       ///< exp(−a·h) for the standard step h
  double step_lag_s_ = 0.0;        ///< (1 − exp(−a·h))/a for the standard step, s
  double radius_m_ = 0.03;
  double count_rad_ = 0.0;       ///< angle per count
  double counts_per_rad_ = 0.0;  ///< 1/count_rad_
  double angle_rad_ = 0.0;
  double speed_radps_ = 0.0;
  double voltage_v_ = 0.0;
  double ground_m_ = 0.0;
  std::int64_t count_ = 0;  ///< floor(angle / count_rad)
  double slip_ratio_ = 0.0;
  double slip_left_m_ = 0.0;  ///< wheel travel until the slip ratio is redrawn
  // Floor cables, crossed by this wheel's own contact point (Plant::set_bumps).
  double bump_arc_m_ = 0.0;    ///< wheel travel (rolled) spent over one cable
  double bump_chord_m_ = 0.0;  ///< floor distance covered meanwhile
  double bump_ratio_ = 1.0;    ///< chord / arc: floor progress per rolled travel on a cable
  double bump_next_m_ = 0.0;   ///< floor distance to the next cable
  double bump_left_m_ = 0.0;   ///< rolled travel still on the current cable
  std::uint32_t bumps_ = 0u;
  // Cables laid under this wheel (Plant::lay_cables); laid_count_ 0: the random floor.
  double laid_first_m_ = 0.0;        ///< floor distance from the run's start to the first
  std::uint32_t laid_count_ = 0u;    ///< how many
  std::uint32_t cables_ahead_ = 0u;  ///< not yet reached in this run
};

/// Planar pose in the world frame: x, y in m, θ in rad (counter-clockwise, not wrapped).
struct WorldPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double theta_rad = 0.0;
};

/// The whole robot on its floor.
class Plant {
 public:
  /// @param model a model for which `check(model)` is `ModelError::none` (otherwise the plant
  ///        stays still: `ok()` is false); @param seed of every random term.
  Plant(const RobotModel& model, std::uint64_t seed);

  Plant(const Plant&) = delete;
  Plant& operator=(const Plant&) = delete;

  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] const RobotModel& model() const { return model_; }

  // --- the HAL endpoints ---
  Wheel& left() { return left_; }
  Wheel& right() { return right_; }
  [[nodiscard]] const Wheel& left() const { return left_; }
  [[nodiscard]] const Wheel& right() const { return right_; }
  SimClock& clock() { return clock_; }
  hal::CriticalSection& critical_section() { return critical_; }

  /// Simulated time since construction, ns.
  [[nodiscard]] std::uint64_t now_ns() const { return clock_.ns(); }

  /// Runs the physics up to `t_ns` in steps of at most `physics_step_ns` (the last one shorter if
  /// needed). Encoder edges are delivered through the lines' handlers during the call, each with
  /// the clock set to the instant the shaft crossed the edge. Does nothing if `t_ns` <= now.
  void advance_to_ns(std::uint64_t t_ns);

  /// The true pose (ground truth), world frame.
  [[nodiscard]] const WorldPose& pose() const { return pose_; }
  /// Path length of the robot centre, m (backwards counts negative).
  [[nodiscard]] double distance_m() const { return distance_m_; }
  /// Cable crossings since construction, both wheels together (each wheel counts its own).
  [[nodiscard]] std::uint32_t bumps_crossed() const { return left_.bumps_ + right_.bumps_; }

  /// Puts the robot down at `pose` (a new run): wheels at rest, a fresh random distance from each
  /// wheel to its first cable. Wheel angles and encoder lines are kept (the firmware's decoders
  /// stay consistent).
  void place(const WorldPose& pose = WorldPose{});

  /// Both wheels slower than `radps`.
  [[nodiscard]] bool at_rest(double radps = 1.0e-3) const;

  /// The "absolute" measurement: the true pose plus independent normal noise of the model's
  /// standard deviations (UMBmark's sonar calibrator).
  [[nodiscard]] WorldPose measure();

  /// Changes the floor: cable height (0 = smooth) and mean spacing, m (height >= 0 and below the
  /// wheel radius; a spacing <= 0 keeps the current one). Each wheel meets a cable every
  /// `spacing` (± the model's jitter) of floor its own contact point sweeps, at its own random
  /// phase; rolling over one it turns through an arc while covering only the chord, so it loses
  /// ground travel, and the heading follows from the two wheels' ground travel.
  void set_bumps(double height_m, double spacing_m);

  /// Lays a fixed row of cables under one wheel only (the extended UMBmark's floor): `count`
  /// cables of `height_m`, the first `first_m` of floor after the start of each run (`place()`),
  /// then every `spacing_m` (no jitter); the other wheel rolls on a smooth floor and, past the
  /// last cable, so does this one. Crossing one is the same physics as set_bumps (arc instead of
  /// chord, and a random skid of the heading). set_bumps() returns to the random floor (the
  /// spacing stays `spacing_m` until it gives another).
  /// @param right_wheel true: the right wheel's path, false: the left one's.
  /// @param height_m >= 0 and below that wheel's radius (0 = a smooth floor).
  void lay_cables(bool right_wheel, double height_m, double first_m, double spacing_m,
                  std::uint32_t count);

 private:
  void step(std::uint32_t dt_ns);
  void integrate_motor(Wheel& wheel, double dt_s, bool standard_step, double& delta_rad);
  struct Sweep;
  static bool leaves_count(const Wheel& wheel);
  static Sweep sweep_of(Wheel& wheel, double from);
  void fire(Sweep& sweep, std::uint64_t t0_ns, double dt_ns, std::int64_t last_ns,
            std::int64_t& previous_ns);
  void deliver_edges(double left_from, double right_from, std::uint64_t t0_ns, std::uint32_t dt_ns);
  void deliver_wheel_edges(Wheel& wheel, double from, std::uint64_t t0_ns, std::uint32_t dt_ns);
  double ground_travel(Wheel& wheel, double rolled_m);
  double over_cables(Wheel& wheel, double rolled_m);
  void start_bump(Wheel& wheel);
  void place_cables();

  RobotModel model_;
  bool ok_ = false;
  Random random_;
  Random floor_random_;  ///< the cables' own stream: a smooth floor draws nothing from it
  Wheel left_;
  Wheel right_;
  SimClock clock_;
  SimCriticalSection critical_;
  WorldPose pose_{};
  double cos_ = 1.0;
  double sin_ = 0.0;
  double inverse_wheelbase_ = 0.0;  ///< 1/true wheelbase, 1/m
  double arc_gap_m_ = 0.0;          ///< true arc wheelbase − wheelbase, m (0: one wheelbase)
  double distance_m_ = 0.0;
};

}  // namespace odocal::sim
