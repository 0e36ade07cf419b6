// The wiring self-test's state machine: two timed drives, each wheel alone, then a coast to rest
// with the motors let go; what each showed, judged from its encoders.

#include "odocal/console/self_test.hpp"

#include <cmath>
#include <numbers>

#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::console {
namespace {

// Each wheel turns at a tenth of max_wheel_radps (2.5 rad/s by default: about an eighth of a
// turn) for kDrive_ms, then coasts to rest for kCoast_ms with the motors let go.
constexpr std::uint32_t kDrive_ms = 300u;
constexpr std::uint32_t kRelease_ms = 2u * kDrive_ms;
constexpr std::uint32_t kCoast_ms = 700u;
constexpr float kSpeedShare = 0.1f;

constexpr unsigned bit(SelfTest::Fault fault) {
  return 1u << static_cast<unsigned>(fault);
}
// The pairs' right-wheel bit is the left one's shifted by one (judge, advance).
static_assert(bit(SelfTest::Fault::right_reversed) == bit(SelfTest::Fault::left_reversed) << 1u &&
              bit(SelfTest::Fault::right_still) == bit(SelfTest::Fault::left_still) << 1u &&
              bit(SelfTest::Fault::right_illegal) == bit(SelfTest::Fault::left_illegal) << 1u &&
              bit(SelfTest::Fault::right_weak) == bit(SelfTest::Fault::left_weak) << 1u);

}  // namespace

SelfTest::Step SelfTest::start(Wheels wheels, std::uint32_t now_us) {
  last_ = wheels == Wheels::left ? 0u : 1u;
  faults_ = 0u;
  return start_wheel(wheels == Wheels::right ? 1u : 0u, now_us);
}

SelfTest::Step SelfTest::start_wheel(unsigned wheel, std::uint32_t now_us) {
  const drive::DriveConfig config = params::to_drive_config(settings_.values());
  const drive::DiffDriveKinematics kinematics(config);
  drive::WheelRates rates;
  (wheel == 0u ? rates.left_radps : rates.right_radps) = kSpeedShare * config.max_wheel_radps;
  // The twist that turns this wheel alone (forward and inverse kinematics are exact inverses).
  // Longer than the test: `advance` replaces it, so it never ends in braking.
  if (!loop_.drive(kinematics.forward(rates), kRelease_ms)) {
    phase_ = Phase::off;
    return Step::refused;
  }
  const drive::WheelCounts counts = loop_.wheel_counts();
  const drive::LoopStatus status = loop_.status();
  start_[0] = static_cast<std::int32_t>(counts.left);
  start_[1] = static_cast<std::int32_t>(counts.right);
  illegal_[0] = status.illegal_left;
  illegal_[1] = status.illegal_right;
  duty_ = 0.0f;
  // A quarter of the counts the wheel turns at the commanded speed tells motion from jitter.
  enough_ = 0.25f * kSpeedShare * config.max_wheel_radps * (static_cast<float>(kDrive_ms) * 1e-3f) *
            config.counts_per_rev / (2.0f * std::numbers::pi_v<float>);
  due_us_ = now_us + kDrive_ms * 1000u;
  phase_ = static_cast<Phase>(2u * wheel + 1u);
  return Step::running;
}

bool SelfTest::counted(std::int32_t counts) const {
  return counts != 0 && static_cast<float>(counts < 0 ? -counts : counts) >= enough_;
}

SelfTest::Step SelfTest::advance(std::uint32_t now_us) {
  const auto phase = static_cast<unsigned>(phase_);
  const drive::LoopStatus status = loop_.status();
  const unsigned wheel = (phase - 1u) >> 1u;
  const drive::WheelCounts counts = loop_.wheel_counts();
  const std::int32_t moved[2] = {static_cast<std::int32_t>(counts.left) - start_[0],
                                 static_cast<std::int32_t>(counts.right) - start_[1]};
  const std::int32_t own = moved[wheel];
  const std::int32_t other = moved[1u - wheel];
  if ((phase & 1u) != 0u) {  // driven
    const float duty = std::fabs(wheel == 0u ? status.left_duty : status.right_duty);
    duty_ = duty > duty_ ? duty : duty_;
    // A wheel counting the wrong way, or the other wheel's encoder counting, runs away under
    // the speed loop (and braking would drive it on): release the motors as soon as it shows.
    const bool wrong = counted(other) || (own < 0 && counted(own));
    if (!wrong && static_cast<std::int32_t>(now_us - due_us_) < 0) {
      return Step::running;
    }
    // Zero set-points after a drive that has not ended: the motors are let go (no braking).
    static_cast<void>(loop_.drive(drive::Twist{}, kCoast_ms));
    due_us_ = now_us + (kCoast_ms + 100u) * 1000u;
    phase_ = static_cast<Phase>(phase + 1u);
    return Step::running;
  }
  if (static_cast<std::int32_t>(now_us - due_us_) < 0) {
    return Step::running;
  }
  unsigned found = 0u;
  if (counted(other)) {
    found = bit(Fault::crossed);
  } else if (!counted(own)) {
    found = bit(Fault::left_still);
  } else if (own < 0) {
    found = bit(Fault::left_reversed);
  } else if (duty_ > settings_.get(params::ParamId::stall_duty)) {
    found = bit(Fault::left_weak);  // it turns, but only at a duty where it should already run
  }
  // The left wheel's bits shifted by one name the right wheel's (crossed stays one bit).
  found = (found & ~bit(Fault::crossed)) << wheel | (found & bit(Fault::crossed));
  if (status.illegal_left != illegal_[0]) {
    found |= bit(Fault::left_illegal);
  }
  if (status.illegal_right != illegal_[1]) {
    found |= bit(Fault::right_illegal);
  }
  faults_ = static_cast<std::uint16_t>(faults_ | found);
  counts_[2u * wheel] = moved[0];
  counts_[2u * wheel + 1u] = moved[1];
  if (wheel != last_) {
    return start_wheel(1u, now_us);
  }
  phase_ = Phase::off;
  if (status.faults != drive::fault_none) {
    loop_.stop();  // acknowledges a stall fault the test caused (the motors are parked)
  }
  return Step::done;
}

}  // namespace odocal::console
