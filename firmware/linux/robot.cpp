#include "robot.hpp"

#include <cstdio>

namespace odocal::linux_target {

using namespace odocal::hal::linux_gpiod;

SetupResult MotorPwm::open(ChipSet& chips, const PwmSpec& spec, const LinuxConfig& config,
                           const char* role) {
  SetupResult result = SetupResult::failure(SetupCode::not_found, "");
  if (spec.sysfs) {
    result = sysfs.open(spec.chip, spec.channel, config.pwm_hz, role);
    if (result.ok()) {
      active = &sysfs;
      description = sysfs.name() + " " + std::to_string(config.pwm_hz) + " Hz";
      return result;
    }
    if (!spec.has_gpio) {
      return result;
    }
    std::fprintf(stderr, "odocal-linux: %s; falling back to software PWM\n",
                 result.message.c_str());
  }
  result = soft.open(chips, spec.gpio, config.soft_pwm_hz, config.pwm_priority, kConsumer);
  if (result.ok()) {
    active = &soft;
    description = "software on " + describe(spec.gpio) + " " + std::to_string(config.soft_pwm_hz) +
                  " Hz (LOW PRECISION)";
    std::fprintf(stderr, "odocal-linux: %s: software PWM on %s, low precision\n", role,
                 describe(spec.gpio).c_str());
  }
  return result;
}

void Robot::on_tick(void* context) {
  auto* robot = static_cast<Robot*>(context);
  const std::uint32_t start = robot->clock.now_us();
  {
    // A thread, not an interrupt: the whole tick inside the critical section, so the console's
    // reads of tick-owned state (pose, last trial) and a path load never interleave with it
    // (ControlLoop's contract). Edges wait in the kernel's queue with their timestamps meanwhile.
    hal::CriticalGuard guard(robot->critical);
    robot->loop->tick(start);
  }
  robot->loop->note_tick_duration_us(static_cast<float>(robot->clock.now_us() - start));
}

SetupResult Robot::open(const LinuxConfig& config) {
  SetupResult r = left_dir.open(chips, config.left_dir, true, kConsumer);
  if (r.ok()) {
    r = right_dir.open(chips, config.right_dir, true, kConsumer);
  }
  if (r.ok() && config.has_enable) {
    r = enable.open(chips, config.enable, false, kConsumer);
  }
  if (r.ok()) {
    r = left_pwm.open(chips, config.left_pwm, config, "left_pwm");
  }
  if (r.ok()) {
    r = right_pwm.open(chips, config.right_pwm, config, "right_pwm");
  }
  if (!r.ok()) {
    return r;
  }
  loop = std::make_unique<drive::ControlLoop>(drive::MotorChannel{*left_pwm.active, left_dir},
                                              drive::MotorChannel{*right_pwm.active, right_dir},
                                              critical);
  encoders = std::make_unique<EncoderEvents>(drive::edge_sink(loop->left_decoder()),
                                             drive::edge_sink(loop->right_decoder()), critical);
  tick = std::make_unique<TimerfdTick>(config.tick_priority);
  return encoders->open(chips, EncoderPins{config.left_a, config.left_b},
                        EncoderPins{config.right_a, config.right_b}, kConsumer);
}

SetupResult Robot::start(const LinuxConfig& config, std::uint32_t rate_hz) {
  SetupResult r = encoders->start(config.event_priority, config.event_holdback_us);
  if (r.ok() && tick->start(rate_hz, &Robot::on_tick, this) == 0u) {
    r = SetupResult::failure(SetupCode::system_error, "control tick: " + tick->error());
  }
  return r;
}

void Robot::shut_down() {
  if (tick) {
    tick->stop();
  }
  if (loop) {
    loop->stop();
  }
  enable.set(false);
  left_pwm.sysfs.close();
  left_pwm.soft.close();
  right_pwm.sysfs.close();
  right_pwm.soft.close();
  if (encoders) {
    encoders->close();
  }
}

}  // namespace odocal::linux_target
