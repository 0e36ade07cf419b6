// ROSArduinoBridge's serial commands, answered beside odocal's own (DESIGN.md "ROS robots",
// docs/ros.md). The protocol as its firmware defines it (hbrobotics/ros_arduino_bridge,
// commands.h and runCommand in ROSArduinoBridge.ino): a line whose first word is one character;
// replies `<left> <right>`, `OK`, the baud rate or `Invalid Command`; wheel speeds in encoder
// counts per PID frame of 1/30 s; the wheels stop when no `m` came for 2000 ms.

#include <numbers>

#include "odocal/console/console.hpp"
#include "odocal/drive/robot_model.hpp"

namespace odocal::console {
namespace {

constexpr float kFramesPerS = 30.0f;          // ROSArduinoBridge's PID_RATE
constexpr std::uint32_t kAutoStopMs = 2000u;  // its AUTO_STOP_INTERVAL
constexpr std::int32_t kMaxCountsPerFrame = 1000000;
static_assert(console_baud == 115200u, "`b` answers kBaudText");
constexpr char kBaudText[] = "115200";

/// The next word at `text` as C's atoi reads it, which is how ROSArduinoBridge's runCommand
/// reads every argument: spaces, a sign, then digits up to the first other character (`1.5` is
/// 1; `x` and no word at all, 0). Held within kMaxCountsPerFrame, where atoi would overflow.
/// Moves `text` past that word; the line ends with a NUL.
std::int32_t next_atoi(const char*& text) {
  while (*text == ' ') {
    ++text;
  }
  const bool negative = *text == '-';
  if (negative || *text == '+') {
    ++text;
  }
  std::int32_t value = 0;
  for (; static_cast<unsigned>(*text - '0') < 10u; ++text) {
    if (value < kMaxCountsPerFrame) {
      value = value * 10 + (*text - '0');  // below 10^7: no overflow
    }
  }
  if (value > kMaxCountsPerFrame) {
    value = kMaxCountsPerFrame;
  }
  while (*text != ' ' && *text != '\0') {
    ++text;
  }
  return negative ? -value : value;
}

/// `e`'s number for a wheel: its counts since `r` (32-bit, wrapping as ROSArduinoBridge's `long`)
/// times `scale`, to the nearest whole number. Monotone: float conversion, a positive factor and
/// rounding never reverse an order, so it never goes back while the wheel rolls forward.
std::int32_t scaled_count(std::uint32_t counts, float scale) {
  float scaled = static_cast<float>(static_cast<std::int32_t>(counts)) * scale + 0.5f;
  // Held within +-2^31 (a factor above 1 and 2^31 counts: past 280 km of a 60 mm wheel).
  if (scaled > 2.1e9f) {
    scaled = 2.1e9f;
  } else if (scaled < -2.1e9f) {
    scaled = -2.1e9f;
  }
  auto whole = static_cast<std::int32_t>(scaled);  // toward zero: one down below 0
  if (static_cast<float>(whole) > scaled) {
    --whole;
  }
  return whole;
}

}  // namespace

void Console::cmd_bridge(const Token* words, std::size_t count) {
  // count 0: an empty line ended by a bare CR (diffdrive_arduino's "\r"), `Invalid Command`.
  const char letter = count != 0u ? words[0].text[0] : '\0';
  banner_due_ = false;  // a ROSArduinoBridge client is on the line: never a line it did not ask
  // A program sends these (diffdrive_arduino), even where a person had typed before (picocom
  // quit, ROS started on the port): the automatic echo goes off, so that at most this line's
  // reply carried an echo.
  if (options_.echo == EchoMode::automatic) {
    echo_ = false;
    editor_.forget_terminal();
  }
  // The model in force (robot_model.hpp), told a unit wheel: its diameters are each wheel's
  // diameter in force over the nominal one; and what one count is to ROS, which knows the
  // nominal robot (wheel_radius = wheel_diameter_mm / 2).
  const params::ParamSet& p = settings_.values();
  using params::ParamId;
  const drive::model::Geometry<float> model =
      drive::model::geometry_in_force(drive::model::Parameters<float>{
          1.0f, p.get(ParamId::wheelbase_mm) * 1e-3f, 0.0f, p.get(ParamId::c_l),
          p.get(ParamId::c_r), p.get(ParamId::f_lat), p.get(ParamId::f_lon)});
  const float nominal_m_per_count = std::numbers::pi_v<float> * p.get(ParamId::wheel_diameter_mm) *
                                    1e-3f / p.get(ParamId::counts_per_rev);
  const drive::WheelCounts counts = loop_.wheel_counts();
  // Counts as ROSArduinoBridge's `long` and diffdrive_arduino's `int` hold them: 32 bits,
  // wrapping (the modular difference; 2^31 counts are a million wheel turns at 1440 counts).
  const auto left = static_cast<std::uint32_t>(counts.left);
  const auto right = static_cast<std::uint32_t>(counts.right);
  switch (letter) {
    case 'e':
      send_line("%i %i", scaled_count(left - bridge_zero_left_, model.left_diameter),
                scaled_count(right - bridge_zero_right_, model.right_diameter));
      return;
    case 'b':
      send_line(kBaudText);
      return;
    case 'a':  // analog read, digital read, sonar ping: no such pin or sensor is wired to the
    case 'd':  // protocol here, so what the firmware reads from one that gives nothing
    case 'p':
      send_line("0");
      return;
    case 'r':
      // The counts to zero, and the wheels stopped: the firmware's resetPID zeroes the targets.
      bridge_zero_left_ = left;
      bridge_zero_right_ = right;
      loop_.stop();
      break;
    case 'o':
      // Raw PWM (joshnewans' firmware): odocal never drives its motors open loop from a host,
      // so it stops them (the one duty both agree on is `o 0 0`).
      loop_.stop();
      break;
    case 'm': {
      // Two numbers as atoi reads them (words after them are ignored): each wheel's speed as
      // ROS computed it for the nominal robot, counts per 1/30 s.
      const char* args = words[0].text + 1;
      const float left_mps =
          static_cast<float>(next_atoi(args)) * nominal_m_per_count * kFramesPerS;
      const float right_mps =
          static_cast<float>(next_atoi(args)) * nominal_m_per_count * kFramesPerS;
      if (left_mps == 0.0f && right_mps == 0.0f) {
        loop_.stop();
        break;
      }
      // The body twist those contact speeds make about the wheelbase in force (the one
      // wheel_separation ROS is told, docs/ros.md); the loop drives it through the calibrated
      // model (Maddahi eq. 7 with c_L, c_R, F_lat, F_lon, the arc wheelbase), as any `drive`.
      drive::Twist twist;
      twist.v_mps = 0.5f * (left_mps + right_mps);
      twist.w_radps = (right_mps - left_mps) / model.wheelbase;
      // Held (no trial) until the next `m`, at most 2000 ms: ROSArduinoBridge's
      // AUTO_STOP_INTERVAL. Refused in a fault, which stays for `m 0 0` or `stop`.
      (void)loop_.drive(twist, kAutoStopMs, false);
      break;
    }
    case 'c':  // pin mode, digital write, analog write: nothing wired to them here
    case 'w':
    case 'x':
    case 'u':  // PID gains: odocal's own wheel loop (kp, ki, kff) keeps its gains
      break;
    default:
      send_line("Invalid Command");
      return;
  }
  send_line("OK");
}

}  // namespace odocal::console
