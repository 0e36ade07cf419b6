// ROSArduinoBridge's serial commands, answered beside odocal's own (DESIGN.md "ROS robots",
// docs/ros.md). The protocol as its firmware defines it (hbrobotics/ros_arduino_bridge,
// commands.h and runCommand in ROSArduinoBridge.ino): a line whose first word is one character;
// replies `<left> <right>`, `OK`, the baud rate or `Invalid Command`; wheel speeds in encoder
// counts per PID frame of 1/30 s; the wheels stop when no `m` came for 2000 ms.

#include <cmath>
#include <numbers>

#include "odocal/console/console.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::console {
namespace {

constexpr float kFramesPerS = 30.0f;              // ROSArduinoBridge's PID_RATE
constexpr std::uint64_t kAutoStopUs = 2000000u;   // its AUTO_STOP_INTERVAL, 2000 ms
constexpr float kMaxCountsPerFrame = 1000000.0f;  // keeps the twist finite; the loop clips it

}  // namespace

void Console::cmd_bridge(const Token* words, std::size_t count) {
  const char letter = words[0].text[0];
  if (letter == 'e') {
    const drive::WheelCounts counts = loop_.wheel_counts();
    const std::int64_t left = counts.left - bridge_zero_left_;
    const std::int64_t right = counts.right - bridge_zero_right_;
    send_line("%I %I", &left, &right);
    return;
  }
  if (letter == 'b') {
    send_line("%u", console_baud);
    return;
  }
  float counts_left = 0.0f;
  float counts_right = 0.0f;
  if (letter == 'r') {
    const drive::WheelCounts counts = loop_.wheel_counts();
    bridge_zero_left_ = counts.left;
    bridge_zero_right_ = counts.right;
  } else if (letter == 'm') {
    if (count != 3u || !parse_number(words[1], counts_left) ||
        !parse_number(words[2], counts_right) || !(std::fabs(counts_left) <= kMaxCountsPerFrame) ||
        !(std::fabs(counts_right) <= kMaxCountsPerFrame)) {
      send_line("Invalid Command");
      return;
    }
    if (counts_left == 0.0f && counts_right == 0.0f) {
      bridge_held_ = false;
      loop_.stop();
    } else {
      // Each wheel's contact point at the speed the nominal robot (wheel_diameter_mm,
      // counts_per_rev) would reach with these counts, as the ROS side computed them; the twist
      // of those two speeds over the wheelbase in force, driven through the calibrated model
      // (Maddahi eq. 7 with c_L, c_R, F_lat, F_lon), turns each wheel so its true contact point
      // moves at that speed.
      const drive::DriveConfig config = params::to_drive_config(settings_.values());
      const drive::DiffDriveKinematics kinematics(config);
      const float m_per_count = std::numbers::pi_v<float> * config.wheel_diameter_mm * 1e-3f /
                                config.counts_per_rev * kFramesPerS;
      const float left_mps = counts_left * m_per_count;
      const float right_mps = counts_right * m_per_count;
      bridge_twist_.v_mps = 0.5f * (left_mps + right_mps);
      bridge_twist_.w_radps =
          (right_mps - left_mps) / kinematics.wheelbase_for_rates_m(left_mps, right_mps);
      bridge_since_us_ = clock_us_;
      bridge_held_ = loop_.drive(bridge_twist_, 0u);
    }
  } else if (letter != 'u') {
    send_line("Invalid Command");
    return;
  }
  send_line("OK");
}

void Console::hold_bridge_motion() {
  if (!bridge_held_) {
    return;
  }
  if (clock_us_ - bridge_since_us_ > kAutoStopUs) {
    bridge_held_ = false;
    loop_.stop();
    return;
  }
  // Renewed at every poll: the loop's own cmd_timeout_ms still stops the wheels if the main loop
  // stops polling. Refused in a fault: the hold ends, and the fault stays for `stop` (or `m 0 0`).
  bridge_held_ = loop_.drive(bridge_twist_, 0u);
}

}  // namespace odocal::console
