// Console command `selftest`: drives each wheel alone, slowly and briefly, and says what the
// wiring got wrong (docs/wiring.md). Two timed drives the console watches from `poll`; the tick
// does nothing it would not do for a `drive`.

#include <cmath>
#include <numbers>

#include "odocal/console/console.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::console {
namespace {

// Each wheel turns at a tenth of max_wheel_radps (2.5 rad/s by default: about an eighth of a
// turn) for kDrive_ms, then coasts to rest for kCoast_ms with the motors let go.
constexpr std::uint32_t kDrive_ms = 300u;
constexpr std::uint32_t kRelease_ms = 2u * kDrive_ms;
constexpr std::uint32_t kCoast_ms = 700u;
constexpr float kSpeedShare = 0.1f;

// Fault bits, in the order of the names in kNames.
constexpr unsigned kLeftReversed = 0x01u;
constexpr unsigned kLeftStill = 0x04u;
constexpr unsigned kCrossed = 0x10u;
constexpr unsigned kIllegal = 0x20u;  // left; right is the next bit
constexpr unsigned kLeftWeak = 0x80u;
// Names in bit order, each ended by a NUL, the list by an empty name (Console::flag_names).
constexpr char kNames[] =
    "left_reversed\0right_reversed\0left_still\0right_still\0crossed\0left_illegal\0"
    "right_illegal\0left_weak\0right_weak\0";

}  // namespace

void Console::cmd_selftest(const Token* words, std::size_t count) {
  // `selftest left` / `selftest right`: that wheel alone (the host then measures where the robot
  // went, to tell a reversed motor from a reversed encoder).
  unsigned first = 0u;
  selftest_last_ = 1u;
  if (count == 2u) {
    const bool left = words[1].is("left");
    if (!left && !words[1].is("right")) {
      send_error(ErrorCode::bad_argument, "selftest [left|right]");
      return;
    }
    first = left ? 0u : 1u;
    selftest_last_ = static_cast<std::uint8_t>(first);
  }
  selftest_faults_ = 0u;
  start_selftest_wheel(first);
}

void Console::start_selftest_wheel(unsigned wheel) {
  const drive::DriveConfig config = params::to_drive_config(settings_.values());
  const drive::DiffDriveKinematics kinematics(config);
  drive::WheelRates rates;
  (wheel == 0u ? rates.left_radps : rates.right_radps) = kSpeedShare * config.max_wheel_radps;
  // The twist that turns this wheel alone (forward and inverse kinematics are exact inverses).
  // Longer than the test: the console replaces it (`release`), so it never ends in braking.
  if (!loop_.drive(kinematics.forward(rates), kRelease_ms)) {
    selftest_phase_ = 0u;
    send_error(ErrorCode::fault, "drive faulted; stop acknowledges");
    return;
  }
  const drive::WheelCounts counts = loop_.wheel_counts();
  const drive::LoopStatus status = loop_.status();
  selftest_start_[0] = static_cast<std::int32_t>(counts.left);
  selftest_start_[1] = static_cast<std::int32_t>(counts.right);
  selftest_illegal_[0] = status.illegal_left;
  selftest_illegal_[1] = status.illegal_right;
  selftest_duty_ = 0.0f;
  // A quarter of the counts the wheel turns at the commanded speed tells motion from jitter.
  selftest_enough_ = 0.25f * kSpeedShare * config.max_wheel_radps *
                     (static_cast<float>(kDrive_ms) * 1e-3f) * config.counts_per_rev /
                     (2.0f * std::numbers::pi_v<float>);
  selftest_due_us_ = last_now_us_ + kDrive_ms * 1000u;
  selftest_phase_ = static_cast<std::uint8_t>(2u * wheel + 1u);
}

void Console::continue_selftest() {
  const drive::LoopStatus status = loop_.status();
  const unsigned wheel = (selftest_phase_ - 1u) >> 1u;
  const bool driving = (selftest_phase_ & 1u) != 0u;
  const drive::WheelCounts counts = loop_.wheel_counts();
  const std::int32_t moved[2] = {static_cast<std::int32_t>(counts.left) - selftest_start_[0],
                                 static_cast<std::int32_t>(counts.right) - selftest_start_[1]};
  const std::int32_t own = moved[wheel];
  const std::int32_t other = moved[1u - wheel];
  const float enough = selftest_enough_;
  const auto counted = [enough](std::int32_t n) {
    return n != 0 && static_cast<float>(n < 0 ? -n : n) >= enough;
  };
  if (driving) {
    const float duty = std::fabs(wheel == 0u ? status.left_duty : status.right_duty);
    selftest_duty_ = duty > selftest_duty_ ? duty : selftest_duty_;
    // A wheel counting the wrong way, or the other wheel's encoder counting, runs away under
    // the speed loop (and braking would drive it on): release the motors as soon as it shows.
    const bool wrong = counted(other) || (own < 0 && counted(own));
    if (!wrong && static_cast<std::int32_t>(last_now_us_ - selftest_due_us_) < 0) {
      return;
    }
    // Zero set-points after a drive that has not ended: the motors are let go (no braking).
    static_cast<void>(loop_.drive(drive::Twist{}, kCoast_ms));
    selftest_due_us_ = last_now_us_ + (kCoast_ms + 100u) * 1000u;
    ++selftest_phase_;
    return;
  }
  if (static_cast<std::int32_t>(last_now_us_ - selftest_due_us_) < 0) {
    return;
  }
  unsigned found = 0u;
  if (counted(other)) {
    found |= kCrossed;
  } else if (!counted(own)) {
    found |= kLeftStill;
  } else if (own < 0) {
    found |= kLeftReversed;
  } else if (selftest_duty_ > settings_.values().get(params::ParamId::stall_duty)) {
    found |= kLeftWeak;  // it turns, but only at a duty where it should already run
  }
  // The left wheel's bits shifted by one name the right wheel's (crossed stays one bit).
  found = (found & ~kCrossed) << wheel | (found & kCrossed);
  if (status.illegal_left != selftest_illegal_[0]) {
    found |= kIllegal;
  }
  if (status.illegal_right != selftest_illegal_[1]) {
    found |= kIllegal << 1u;
  }
  selftest_faults_ = static_cast<std::uint16_t>(selftest_faults_ | found);
  selftest_counts_[2u * wheel] = moved[0];
  selftest_counts_[2u * wheel + 1u] = moved[1];
  if (wheel != selftest_last_) {
    start_selftest_wheel(1u);
    return;
  }
  selftest_phase_ = 0u;
  if (status.faults != drive::fault_none) {
    loop_.stop();  // acknowledges a stall fault the test caused (the motors are parked)
  }
  ReplyLine reply(out_);
  reply.text("ok faults=");
  flag_names(reply, selftest_faults_, kNames);
  append(reply, " ll=%i lr=%i rl=%i rr=%i", selftest_counts_[0], selftest_counts_[1],
         selftest_counts_[2], selftest_counts_[3]);
  send(reply);
}

}  // namespace odocal::console
