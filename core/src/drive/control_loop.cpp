// The control tick: the pipeline from encoders to motors, its faults and its braking (the main
// loop's requests and reads: control_loop_requests.cpp).
#include "odocal/drive/control_loop.hpp"

#include <cmath>

#include "odocal/name_list.hpp"

namespace odocal::drive {
namespace {

WheelGains gains_of(const DriveConfig& config) {
  WheelGains gains;
  gains.kp = config.kp;
  gains.ki = config.ki;
  gains.kff = config.kff;
  gains.max_duty = 1.0f;
  return gains;
}

// A path's length argument, for the trial record (line length, square side; 0 for the others).
float path_length_m(const Path& path) {
  const bool sized =
      path.id == PathId::line || path.id == PathId::umbmark_cw || path.id == PathId::umbmark_ccw;
  return sized && path.count > 0u ? path.segments[0].distance_m : 0.0f;
}

// How long both wheels must be still after a trial's motion before it closes, ms.
constexpr float kMinStill_ms = 50.0f;

// Braking gives up after this long (a wheel held by something never reads "at rest"), ms.
constexpr std::uint32_t kMaxBrake_us = 1000000u;

// The longest tick period the loop integrates over; a longer gap (debugger halt, first tick)
// is treated as this long so the integrators do not jump.
constexpr std::uint32_t kMaxTickGap_us = 100000u;

}  // namespace

const char* mode_name(Mode mode) {
  // In Mode's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char names[] = "idle\0drive\0path\0fault";
  static_assert(nul_count(names) == static_cast<std::size_t>(Mode::fault) + 1u,
                "one name per Mode, in its order");
  const auto n = static_cast<unsigned>(mode);
  return name_at(names, n <= static_cast<unsigned>(Mode::fault) ? n : 0u);
}

void InvertedOutput::do_set(bool level) {
  line_.set(!level);
}

ControlLoop::ControlLoop(MotorChannel left, MotorChannel right, hal::CriticalSection& critical,
                         const DriveConfig& config)
    // Each member built once from the configuration in force (no defaults written first and
    // overwritten: the robot's flash).
    : left_(left),
      right_(right),
      critical_(critical),
      config_(valid(config) ? config : DriveConfig{}),
      kinematics_(config_),
      inbox_{config_} {
  apply_config(config_);
  apply_wiring(config_.wiring_fix);
  drive_motors(0.0f, 0.0f);
}

void ControlLoop::apply_wiring(std::uint32_t wiring_fix) {
  const bool swap_out = (wiring_fix & swap_motors) != 0u;
  MotorChannel& left_out = swap_out ? right_ : left_;
  MotorChannel& right_out = swap_out ? left_ : right_;
  left_pwm_ = &left_out.pwm;
  right_pwm_ = &right_out.pwm;
  InvertedOutput& left_inverted = swap_out ? right_inverted_ : left_inverted_;
  InvertedOutput& right_inverted = swap_out ? left_inverted_ : right_inverted_;
  left_forward_ = (wiring_fix & invert_left_motor) != 0u
                      ? static_cast<hal::DigitalOutput*>(&left_inverted)
                      : &left_out.forward;
  right_forward_ = (wiring_fix & invert_right_motor) != 0u
                       ? static_cast<hal::DigitalOutput*>(&right_inverted)
                       : &right_out.forward;
  // The decoders stay with their connectors (the edge contexts feed them); their edges advance
  // the counters the tick reads as the left or right wheel.
  const bool swap_in = (wiring_fix & swap_encoders) != 0u;
  QuadratureDecoder& left_in = swap_in ? right_decoder_ : left_decoder_;
  QuadratureDecoder& right_in = swap_in ? left_decoder_ : right_decoder_;
  left_in.route(left_decoder_, (wiring_fix & invert_left_encoder) != 0u);
  right_in.route(right_decoder_, (wiring_fix & invert_right_encoder) != 0u);
}

void ControlLoop::apply_config(const DriveConfig& config) {
  if (&config != &config_) {
    config_ = config;
  }
  kinematics_.configure(config_);
  left_wheel_.speed.set_counts_per_rev(config_.counts_per_rev);
  right_wheel_.speed.set_counts_per_rev(config_.counts_per_rev);
  left_wheel_.controller.set_gains(gains_of(config_));
  right_wheel_.controller.set_gains(gains_of(config_));
}

void ControlLoop::take_command(const Taken& inbox, const EncoderSnapshot& left,
                               const EncoderSnapshot& right) {
  if (inbox.reset_pose) {
    odometry_.reset();
    ++pose_resets_;
  }
  switch (inbox.command) {
    case Command::stop:
      start_braking();
      motion_.cancel();
      mode_ = Mode::idle;
      drive_twist_ = Twist{};
      faults_ = fault_none;  // stop acknowledges faults
      left_wheel_.stall_us = 0u;
      right_wheel_.stall_us = 0u;
      left_wheel_.illegal_base = left.illegal;  // from this tick's snapshot, not a fresh racy read
      right_wheel_.illegal_base = right.illegal;
      trial_.abandon();
      break;
    case Command::drive:
      if (mode_ != Mode::fault) {
        motion_.cancel();
        mode_ = Mode::drive;
        drive_twist_ = inbox.twist;
        drive_ms_ = inbox.duration_ms & ~held_bit;
        drive_age_us_ = 0u;
        if (static_cast<std::int32_t>(inbox.duration_ms) > 0) {  // timed, and no held_bit
          trial_.begin(PathId::drive, 0.0f, left_wheel_.speed.position_counts(),
                       right_wheel_.speed.position_counts());
        } else {
          trial_.abandon();  // an open-ended drive is no trial
        }
      }
      break;
    case Command::run:
      if (mode_ != Mode::fault) {
        motion_.start_loaded(odometry_);  // the tick loaded it from the mailbox
        mode_ = motion_.busy() ? Mode::path : Mode::idle;
        drive_twist_ = Twist{};
        trial_.begin(motion_.path().id, path_length_m(motion_.path()),
                     left_wheel_.speed.position_counts(), right_wheel_.speed.position_counts());
      }
      break;
    case Command::none:
      break;
  }
}

bool ControlLoop::stalled(Wheel& wheel, std::uint32_t dt_us) {
  // A wheel is stalled when it gets a large duty and does not get anywhere for stall_ms: its
  // position stays within one count of where the window began. Net motion, not edges: a dead
  // encoder channel still yields edges from the other one, whose counts only go back and forth.
  const std::int64_t position = wheel.speed.position_counts();
  const std::int64_t moved = position - wheel.stall_start;
  if (std::fabs(wheel.duty) > config_.stall_duty && moved <= 1 && moved >= -1) {
    wheel.stall_us += dt_us;
  } else {
    wheel.stall_us = 0u;
    wheel.stall_start = position;
  }
  return static_cast<float>(wheel.stall_us) * 1e-3f > config_.stall_ms;
}

void ControlLoop::check_faults(const EncoderSnapshot& left, const EncoderSnapshot& right,
                               std::uint32_t dt_us) {
  if (left.illegal - left_wheel_.illegal_base > config_.max_illegal) {
    faults_ |= fault_encoder_left;
  }
  if (right.illegal - right_wheel_.illegal_base > config_.max_illegal) {
    faults_ |= fault_encoder_right;
  }
  if (stalled(left_wheel_, dt_us)) {
    faults_ |= fault_stall_left;
  }
  if (stalled(right_wheel_, dt_us)) {
    faults_ |= fault_stall_right;
  }
}

Twist ControlLoop::twist_for_mode(float dt_s, std::uint32_t dt_us) {
  switch (mode_) {
    case Mode::drive: {
      drive_age_us_ += dt_us;
      const float age_ms = static_cast<float>(drive_age_us_) * 1e-3f;
      const bool expired = drive_ms_ > 0u ? age_ms >= static_cast<float>(drive_ms_)
                                          : age_ms > config_.cmd_timeout_ms;
      if (expired) {
        mode_ = Mode::idle;
        drive_twist_ = Twist{};
        start_braking();
      }
      return drive_twist_;
    }
    case Mode::path: {
      const Twist twist = motion_.update(odometry_, config_, dt_s);
      if (!motion_.busy()) {
        mode_ = Mode::idle;
      }
      return twist;
    }
    case Mode::idle:
    case Mode::fault:
      break;
  }
  return Twist{};
}

void ControlLoop::start_braking() {
  const float left = left_wheel_.speed.speed_radps();
  const float right = right_wheel_.speed.speed_radps();
  left_wheel_.brake_sign = left > 0.0f ? 1 : (left < 0.0f ? -1 : 0);
  right_wheel_.brake_sign = right > 0.0f ? 1 : (right < 0.0f ? -1 : 0);
  brake_us_ = 0u;
}

float ControlLoop::brake_duty(Wheel& wheel) {
  // The speed loop's proportional term alone, towards zero: the duty shrinks with the speed and
  // is 0 at rest, so braking cannot push the wheel backwards (an integral term, wound up by the
  // angle turned while stopping, did: a few counts of reverse creep). The controller stays reset
  // so the next motion starts bumpless.
  wheel.controller.reset();
  const float measured = wheel.speed.speed_radps();
  // At rest (the estimator reads 0 once no edge came for its timeout), or turning back: release.
  if (wheel.brake_sign != 0 &&
      (measured * static_cast<float>(wheel.brake_sign) <= 0.0f || brake_us_ > kMaxBrake_us)) {
    wheel.brake_sign = 0;
  }
  if (wheel.brake_sign == 0) {
    return 0.0f;
  }
  const float duty = -config_.kp * measured;
  return duty > 1.0f ? 1.0f : (duty < -1.0f ? -1.0f : duty);
}

void ControlLoop::drive_motors(float left_duty, float right_duty) {
  left_wheel_.duty = left_duty;
  right_wheel_.duty = right_duty;
  left_forward_->set(left_duty >= 0.0f);
  left_pwm_->set_duty(std::fabs(left_duty));
  right_forward_->set(right_duty >= 0.0f);
  right_pwm_->set_duty(std::fabs(right_duty));
}

void ControlLoop::take_inbox(EncoderSnapshot& left, EncoderSnapshot& right, Taken& inbox) {
  hal::CriticalGuard guard(critical_);
  left = left_decoder_.snapshot();
  right = right_decoder_.snapshot();
  inbox.config_pending = inbox_.config_pending;
  if (inbox_.config_pending) {
    config_ = inbox_.config;  // applied by the tick, outside the critical section
    inbox_.config_pending = false;
  }
  inbox.command = inbox_.command;
  inbox.twist = inbox_.twist;
  inbox.duration_ms = inbox_.duration_ms;
  inbox.reset_pose = inbox_.reset_pose;
  inbox_.command = Command::none;
  inbox_.reset_pose = false;
}

std::uint32_t ControlLoop::advance_clock(std::uint32_t now_us, const EncoderSnapshot& left,
                                         const EncoderSnapshot& right) {
  if (!started_) {
    started_ = true;
    last_tick_us_ = now_us;
    left_wheel_.speed.reset(left, now_us);
    right_wheel_.speed.reset(right, now_us);
    left_wheel_.illegal_base = left.illegal;
    right_wheel_.illegal_base = right.illegal;
  }
  std::uint32_t dt_us = now_us - last_tick_us_;
  last_tick_us_ = now_us;
  clock_us_ += dt_us;
  if (dt_us > kMaxTickGap_us) {
    dt_us = kMaxTickGap_us;
  }
  ++ticks_;
  return dt_us;
}

void ControlLoop::estimate(const EncoderSnapshot& left, const EncoderSnapshot& right,
                           std::uint32_t now_us) {
  left_wheel_.speed.update(left, now_us);
  right_wheel_.speed.update(right, now_us);
  odometry_.update(
      static_cast<float>(left_wheel_.speed.delta_counts()) * kinematics_.left_m_per_count(),
      static_cast<float>(right_wheel_.speed.delta_counts()) * kinematics_.right_m_per_count(),
      // The wheelbase in force: b, or with an arc wheelbase the blend for the wheels' measured
      // rates (M/T speeds: a tick's 0-3 counts would quantise the weight and bias it).
      kinematics_.wheelbase_for_rates_m(left_wheel_.speed.speed_radps(),
                                        right_wheel_.speed.speed_radps()));
}

bool ControlLoop::wheel_duties(float dt_s, std::uint32_t dt_us, float& left_duty,
                               float& right_duty) {
  if (mode_ == Mode::fault) {
    left_wheel_.controller.reset();
    right_wheel_.controller.reset();
    left_wheel_.brake_sign = 0;  // a fault parks the motors: no braking either
    right_wheel_.brake_sign = 0;
    return false;
  }
  const Twist twist = twist_for_mode(dt_s, dt_us);
  WheelRates rates = kinematics_.inverse(twist);
  float scale = 1.0f;
  const bool clipped = limit_wheel_speeds(rates, config_.max_wheel_radps, scale);
  if (rates.left_radps == 0.0f && rates.right_radps == 0.0f) {
    // Nothing to drive. After a drive or a `stop`, brake each wheel to rest under proportional
    // speed control to zero (a robot told to stop stops: about a third of the distance it would
    // roll out on its shorted windings); then, and otherwise (idle, settling between path
    // segments), release the motors, instead of a velocity loop that would wind up and creep
    // backwards.
    brake_us_ += dt_us;
    left_duty = brake_duty(left_wheel_);
    right_duty = brake_duty(right_wheel_);
  } else {
    left_wheel_.brake_sign = 0;
    right_wheel_.brake_sign = 0;
    left_duty =
        left_wheel_.controller.update(rates.left_radps, left_wheel_.speed.speed_radps(), dt_s);
    right_duty =
        right_wheel_.controller.update(rates.right_radps, right_wheel_.speed.speed_radps(), dt_s);
  }
  return clipped;
}

void ControlLoop::publish(const EncoderSnapshot& left, const EncoderSnapshot& right,
                          float left_duty, float right_duty, bool clipped) {
  hal::CriticalGuard guard(critical_);
  LoopStatus& status = published_.status;
  status.mode = mode_;
  status.path = mode_ == Mode::path ? motion_.path_id() : PathId::none;
  status.segment = motion_.segment_index();
  status.faults = faults_;
  status.ticks = ticks_;
  status.illegal_left = left.illegal;
  status.illegal_right = right.illegal;
  status.left_radps = left_wheel_.speed.speed_radps();
  status.right_radps = right_wheel_.speed.speed_radps();
  status.left_duty = left_duty;
  status.right_duty = right_duty;
  status.trial_open = trial_.open();
  status.pose_resets = pose_resets_;
  status.clipped = clipped;
  published_.counts = WheelCounts{clock_us_, left_wheel_.speed.position_counts(),
                                  right_wheel_.speed.position_counts()};
}

void ControlLoop::tick(std::uint32_t now_us) {
  // 1. Snapshot the encoders and take the main loop's requests, in one short critical section.
  EncoderSnapshot left_snap;
  EncoderSnapshot right_snap;
  Taken inbox;
  take_inbox(left_snap, right_snap, inbox);
  const std::uint32_t dt_us = advance_clock(now_us, left_snap, right_snap);
  const float dt_s = static_cast<float>(dt_us) * 1e-6f;
  if (inbox.config_pending) {
    apply_config(config_);
  }
  take_command(inbox, left_snap, right_snap);

  // 2. Estimate wheel speeds. 3. Odometry from the wheel increments.
  estimate(left_snap, right_snap, now_us);

  // Faults are sticky and park the motors.
  check_faults(left_snap, right_snap, dt_us);
  if (faults_ != fault_none) {
    mode_ = Mode::fault;
    motion_.cancel();
    trial_.abandon();
  }

  // 4. Motion -> body twist. 5. Inverse kinematics (Maddahi eq. 7) with speed limiting that
  // keeps the curvature. 6. Wheel PI. 7. Outputs.
  float left_duty = 0.0f;
  float right_duty = 0.0f;
  const bool clipped = wheel_duties(dt_s, dt_us, left_duty, right_duty);
  drive_motors(left_duty, right_duty);

  // 8. Trial bookkeeping: a trial closes once the robot is at rest after its motion.
  // A closed trial's record stays in trial_ (last_trial reads it under the critical section).
  static_cast<void>(trial_.update(mode_ == Mode::path || mode_ == Mode::drive,
                                  left_wheel_.speed.position_counts(),
                                  right_wheel_.speed.position_counts(), odometry_, dt_us,
                                  std::fmax(config_.settle_ms, kMinStill_ms)));

  // 9. Publish for the main loop.
  publish(left_snap, right_snap, left_duty, right_duty, clipped);
}

}  // namespace odocal::drive
