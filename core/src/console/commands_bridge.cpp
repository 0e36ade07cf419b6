// ROSArduinoBridge's serial commands, answered beside odocal's own (DESIGN.md "ROS robots",
// docs/ros.md). The protocol as its firmware defines it (hbrobotics/ros_arduino_bridge,
// commands.h and runCommand in ROSArduinoBridge.ino): a line whose first word is one character;
// replies `<left> <right>`, `OK`, the baud rate or `Invalid Command`; wheel speeds in encoder
// counts per PID frame of 1/30 s; the wheels stop when no `m` came for 2000 ms.

#include <numbers>

#include "odocal/console/console.hpp"

namespace odocal::console {
namespace {

constexpr float kFramesPerS = 30.0f;          // ROSArduinoBridge's PID_RATE
constexpr std::uint32_t kAutoStopMs = 2000u;  // its AUTO_STOP_INTERVAL
constexpr float kMaxCountsPerFrame = 1000000.0f;
static_assert(console_baud == 115200u, "`b` answers kBaudText");
constexpr char kBaudText[] = "115200";

}  // namespace

void Console::cmd_bridge(const Token* words, std::size_t count) {
  // count 0: an empty line ended by a bare CR (diffdrive_arduino's "\r"), `Invalid Command`.
  const char letter = count != 0u ? words[0].text[0] : '\0';
  // A program sends these (diffdrive_arduino), even where a person had typed before (picocom
  // quit, ROS started on the port): the automatic echo goes off, so that at most this line's
  // reply carried an echo.
  if (options_.echo == EchoMode::automatic) {
    echo_ = false;
    editor_.forget_terminal();
  }
  const drive::WheelCounts counts = loop_.wheel_counts();
  // Counts as ROSArduinoBridge's `long` and diffdrive_arduino's `int` hold them: 32 bits,
  // wrapping (the modular difference; 2^31 counts are a million wheel turns at 1440 counts).
  const auto left = static_cast<std::uint32_t>(counts.left);
  const auto right = static_cast<std::uint32_t>(counts.right);
  if (letter == 'e') {
    send_line("%i %i", static_cast<std::int32_t>(left - bridge_zero_left_),
              static_cast<std::int32_t>(right - bridge_zero_right_));
    return;
  }
  if (letter == 'b') {
    send_line(kBaudText);
    return;
  }
  float counts_left = 0.0f;
  float counts_right = 0.0f;
  if (letter == 'r') {
    bridge_zero_left_ = left;
    bridge_zero_right_ = right;
  } else if (letter == 'm') {
    // Two numbers as odocal reads them (a missing or bad one is refused with its `err` line:
    // diffdrive_arduino writes two whole numbers; words after them are ignored, as
    // ROSArduinoBridge ignores them), within what keeps the twist finite; the loop clips the
    // wheel speeds anyway. split() leaves absent words empty.
    if (!number_arg(words[1], -kMaxCountsPerFrame, kMaxCountsPerFrame, counts_left) ||
        !number_arg(words[2], -kMaxCountsPerFrame, kMaxCountsPerFrame, counts_right)) {
      return;
    }
    if (counts_left == 0.0f && counts_right == 0.0f) {
      loop_.stop();
    } else {
      // The body twist the ROS side meant with the robot's nominal geometry (wheel_radius =
      // wheel_diameter_mm / 2, wheel_separation = wheelbase_mm, counts_per_rev): v the mean of
      // the two wheels' contact speeds, w their difference over the wheelbase. The loop drives
      // it through the calibrated model (Maddahi eq. 7 with c_L, c_R, F_lat, F_lon, the arc
      // wheelbase), as any `drive`.
      const float mps_per_count = std::numbers::pi_v<float> *
                                  settings_.get(params::ParamId::wheel_diameter_mm) * 1e-3f /
                                  settings_.get(params::ParamId::counts_per_rev) * kFramesPerS;
      drive::Twist twist;
      twist.v_mps = 0.5f * (counts_left + counts_right) * mps_per_count;
      twist.w_radps = (counts_right - counts_left) * mps_per_count /
                      (settings_.get(params::ParamId::wheelbase_mm) * 1e-3f);
      // Held (no trial) until the next `m`, at most 2000 ms: ROSArduinoBridge's
      // AUTO_STOP_INTERVAL. Refused in a fault, which stays for `m 0 0` or `stop`.
      (void)loop_.drive(twist, kAutoStopMs, false);
    }
  } else if (letter != 'u') {
    send_line("Invalid Command");
    return;
  }
  send_line("OK");
}

}  // namespace odocal::console
