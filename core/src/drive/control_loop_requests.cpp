// The control loop's main-loop side: requests put in the tick's mailbox, and reads of what the
// tick published, each under the critical section (the tick itself: control_loop.cpp).
#include <cmath>

#include "odocal/drive/control_loop.hpp"

namespace odocal::drive {

ConfigCheck ControlLoop::configure(const DriveConfig& config) {
  const ConfigCheck result = check(config);
  if (!result) {
    return result;
  }
  hal::CriticalGuard guard(critical_);
  inbox_.config = config;
  inbox_.config_pending = true;
  // The wiring at once, here (no edge or tick runs inside the section): the tick that takes the
  // rest of the configuration does no more work for it.
  apply_wiring(config.wiring_fix);
  return result;
}

DriveConfig ControlLoop::config() const {
  hal::CriticalGuard guard(critical_);
  return inbox_.config;
}

bool ControlLoop::drive(const Twist& twist, std::uint32_t duration_ms, bool trial) {
  if (!std::isfinite(twist.v_mps) || !std::isfinite(twist.w_radps)) {
    return false;
  }
  hal::CriticalGuard guard(critical_);
  if (published_.status.faults != fault_none) {
    return false;
  }
  inbox_.command = Command::drive;
  inbox_.twist = twist;
  inbox_.duration_ms = trial ? duration_ms : duration_ms | held_bit;
  return true;
}

bool ControlLoop::run(const Path& path) {
  if (path.count == 0u) {
    return false;
  }
  hal::CriticalGuard guard(critical_);
  if (published_.status.faults != fault_none) {
    return false;
  }
  inbox_.command = Command::run;
  // The tick is held off (critical section) and the loop is not in a fault (mode_ is fault exactly
  // when the published faults are set): one copy, straight where it runs. The next tick starts it,
  // or cancels it when a later command replaces this one first.
  motion_.load(path);
  return true;
}

void ControlLoop::stop() {
  hal::CriticalGuard guard(critical_);
  inbox_.command = Command::stop;
}

Pose ControlLoop::pose() const {
  Odometry copy;
  {
    hal::CriticalGuard guard(critical_);
    if (inbox_.reset_pose) {
      return Pose{};  // the next tick resets the odometry: it reads zero from now on
    }
    copy = odometry_;  // the tick's own, read under the critical section (no published copy)
  }
  return copy.pose();
}

void ControlLoop::reset_pose() {
  hal::CriticalGuard guard(critical_);
  inbox_.reset_pose = true;
}

LoopStatus ControlLoop::status() const {
  hal::CriticalGuard guard(critical_);
  LoopStatus status = published_.status;
  // A command the tick has not taken yet reads as taken (as `config()` does): `run` then `status`
  // says mode=path even when no tick came between the two lines.
  switch (inbox_.command) {
    case Command::run:
      status.mode = Mode::path;
      status.path = motion_.path().id;  // run() loaded it already
      status.segment = 0u;
      status.trial_open = true;
      break;
    case Command::drive:
      status.mode = Mode::drive;
      status.path = PathId::none;
      status.segment = 0u;
      status.trial_open = static_cast<std::int32_t>(inbox_.duration_ms) > 0;  // timed, no held_bit
      break;
    case Command::stop:
      status.mode = Mode::idle;
      status.path = PathId::none;
      status.segment = 0u;
      status.faults = fault_none;
      status.trial_open = false;
      break;
    case Command::none:
      break;
  }
  return status;
}

TrialRecord ControlLoop::last_trial() const {
  hal::CriticalGuard guard(critical_);
  return trial_.last();
}

WheelCounts ControlLoop::wheel_counts() const {
  hal::CriticalGuard guard(critical_);
  return published_.counts;
}

void ControlLoop::note_tick_duration_us(float duration_us) {
  hal::CriticalGuard guard(critical_);
  LoopStatus& status = published_.status;
  // Exponential average over about 64 ticks, and the largest seen since start-up.
  status.tick_us_avg += (duration_us - status.tick_us_avg) * (1.0f / 64.0f);
  if (duration_us > status.tick_us_max) {
    status.tick_us_max = duration_us;
  }
}

}  // namespace odocal::drive
