// ROSArduinoBridge's commands on the console (DESIGN.md "ROS robots", docs/ros.md): each line
// gets its one reply in that firmware's format, never echoed; `m` goes through odocal's loop with
// the calibration factors applied and is held for 2 s; odocal's own commands are unchanged.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "console_rig.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::test {
namespace {

using console::ConsoleOptions;
using console::EchoMode;

ConsoleOptions automatic_echo() {
  ConsoleOptions options = Rig::quiet();
  options.echo = EchoMode::automatic;
  options.crlf = true;  // as on the UART and the pty: replies end with CR LF
  return options;
}

// What a client that writes `bytes` in one write and then reads gets back, byte for byte.
std::string exchange(Rig& rig, const std::string& bytes) {
  const std::size_t mark = rig.stream.output_size;
  rig.stream.type(bytes);
  rig.settle();
  return std::string(rig.stream.output.data() + mark, rig.stream.output_size - mark);
}

// `ms` milliseconds of the robot: a control tick and a console poll each millisecond.
void run_ms(Rig& rig, int ms) {
  for (int i = 0; i < ms; ++i) {
    rig.tick(1);
    rig.console.poll(rig.now_us);
  }
}

drive::Mode mode(const Rig& rig) {
  return rig.loop.status().mode;
}

// Turns a wheel by `counts` encoder counts (x4 quadrature edges on its decoder), forward when
// positive, continuing its quadrature cycle from where the last turn left it.
class WheelTurner {
 public:
  WheelTurner(Rig& rig, bool left) : rig_(rig), left_(left) {}
  void turn(int counts) {
    static constexpr std::uint8_t kCycle[4][2] = {{1, 0}, {1, 1}, {0, 1}, {0, 0}};
    drive::QuadratureDecoder& decoder =
        left_ ? rig_.loop.left_decoder() : rig_.loop.right_decoder();
    for (int i = 0; i < std::abs(counts); ++i) {
      phase_ = (phase_ + (counts > 0 ? 1 : 3)) % 4;
      decoder.on_edge(kCycle[phase_][0] != 0, kCycle[phase_][1] != 0,
                      rig_.now_us + static_cast<std::uint32_t>(i));
    }
  }

 private:
  Rig& rig_;
  bool left_;
  int phase_ = 3;  // {0, 0}: both channels low, where the decoder starts
};

void turn_left_wheel(Rig& rig, int counts) {
  WheelTurner(rig, true).turn(counts);
}

TEST(ConsoleBridge, DiffdriveArduinosByteSequencesGetOneUnechoedReplyEach) {
  // ArduinoComms (joshnewans/diffdrive_arduino) writes each command ended by a bare CR and reads
  // one line up to its LF: "\r" (send_empty_msg), "u p:d:i:o\r", "e\r", "m a b\r".
  auto rig = make_rig(automatic_echo());
  EXPECT_EQ(exchange(*rig, "\r"), "Invalid Command\r\n");
  EXPECT_EQ(exchange(*rig, "u 30:20:0:100\r"), "OK\r\n");
  EXPECT_EQ(exchange(*rig, "e\r"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "m 10 -10\r"), "OK\r\n");
  EXPECT_EQ(exchange(*rig, "e\r"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "m 0 0\r"), "OK\r\n");
  EXPECT_EQ(exchange(*rig, "b\r"), "115200\r\n");
  EXPECT_FALSE(rig->console.echo_enabled());
}

TEST(ConsoleBridge, CrLfAndCrLfEndALineAndEachGetsExactlyOneReply) {
  auto rig = make_rig(automatic_echo());
  EXPECT_EQ(exchange(*rig, "e\n"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "e\r\n"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "e\r"), "0 0\r\n");
  // Several lines in one write, each ending its own way: one reply each, in order, no echo.
  EXPECT_EQ(exchange(*rig, "b\re\nu 1:2:3:4\r\nr\r"), "115200\r\n0 0\r\nOK\r\nOK\r\n");
  // An empty line ended by LF or CR LF is no command (odocal's rule): no reply.
  EXPECT_EQ(exchange(*rig, "\n\r\n"), "");
  EXPECT_FALSE(rig->console.echo_enabled());
}

TEST(ConsoleBridge, EncodersCountAndResetToZero) {
  auto rig = make_rig();
  rig->tick(2);
  turn_left_wheel(*rig, 1440);
  rig->tick(2);
  EXPECT_EQ(rig->reply("e"), "1440 0");
  EXPECT_EQ(rig->reply("r"), "OK");
  EXPECT_EQ(rig->reply("e"), "0 0");
  turn_left_wheel(*rig, 4);  // the next quadrature cycle: 4 counts forward
  rig->tick(2);
  EXPECT_EQ(rig->reply("e"), "4 0");
  // odocal's own view is untouched by `r`: odometry and tick logs keep their counts.
  EXPECT_EQ(rig->loop.wheel_counts().left, 1444);
}

// The two numbers of an `e` reply.
std::pair<long, long> e_counts(const std::string& reply) {
  long left = 0;
  long right = 0;
  char rest = 0;
  EXPECT_EQ(std::sscanf(reply.c_str(), "%ld %ld%c", &left, &right, &rest), 2) << reply;
  return {left, right};
}

TEST(ConsoleBridge, ECountsAreTheWheelsInForceOnTheNominalWheel) {
  // ROS turns counts into distance with the nominal wheel_radius (wheel_diameter_mm / 2): `e`
  // reports each wheel's counts times its diameter in force over the nominal one (robot_model:
  // D_L = D c_L / (F_lat F_lon), D_R = D c_R / F_lon), to the nearest whole count.
  auto rig = make_rig();
  for (const char* set : {"set c_l 0.98", "set c_r 1.03", "set f_lat 1.01", "set f_lon 0.99"}) {
    ASSERT_EQ(rig->reply(set).rfind("ok ", 0), 0u) << set;
  }
  rig->tick(2);  // the loop counts from its first tick on
  const double left_scale = 0.98 / (1.01 * 0.99);
  const double right_scale = 1.03 / 0.99;
  WheelTurner left(*rig, true);
  WheelTurner right(*rig, false);
  std::pair<long, long> last{0, 0};
  int left_total = 0;
  int right_total = 0;
  // Small steps, an `e` after each: whole numbers that never go back, within half a count of
  // the scaled total (float rounding of a scaled step: far below a count).
  for (int step = 0; step < 400; ++step) {
    const int left_step = 1 + step % 7;
    const int right_step = 1 + step % 5;
    left.turn(left_step);
    right.turn(right_step);
    left_total += left_step;
    right_total += right_step;
    rig->tick(1);
    const auto now = e_counts(rig->reply("e"));
    EXPECT_GE(now.first, last.first);
    EXPECT_GE(now.second, last.second);
    EXPECT_NEAR(static_cast<double>(now.first), left_total * left_scale, 0.5 + 1e-3);
    EXPECT_NEAR(static_cast<double>(now.second), right_total * right_scale, 0.5 + 1e-3);
    last = now;
  }
  // Backwards the same way: the counts go down, still whole and within half a count.
  left.turn(-left_total);
  right.turn(-right_total);
  rig->tick(1);
  const auto back = e_counts(rig->reply("e"));
  EXPECT_NEAR(static_cast<double>(back.first), 0.0, 0.5 + 1e-3);
  EXPECT_NEAR(static_cast<double>(back.second), 0.0, 0.5 + 1e-3);
  // `r` starts again from zero, fraction and all.
  EXPECT_EQ(rig->reply("r"), "OK");
  EXPECT_EQ(rig->reply("e"), "0 0");
}

TEST(ConsoleBridge, TheOtherLettersAnswerAsROSArduinoBridgeBuiltWithUseBase) {
  // runCommand (ROSArduinoBridge.ino, commands.h): analog read, digital read and ping print a
  // number; pin mode, digital write, analog write and the PID gains print OK; raw PWM (`o`,
  // joshnewans' firmware that diffdrive_arduino's author points to) prints OK; a letter it
  // does not define (the servo commands are left out of a USE_BASE build) `Invalid Command`.
  auto rig = make_rig();
  for (const char* line : {"a 3", "d 4", "p 7", "a"}) {
    EXPECT_EQ(rig->reply(line), "0") << line;
  }
  for (const char* line : {"c 13 1", "w 13 1", "x 5 128", "u 5:1:0:50", "o 0 0", "u"}) {
    EXPECT_EQ(rig->reply(line), "OK") << line;
  }
  for (const char* line : {"z 1 2", "s 1 90", "t 1", "?", "E", "1"}) {
    EXPECT_EQ(rig->reply(line), "Invalid Command") << line;
  }
  // `u` changes nothing of odocal's own wheel loop.
  const float kp = rig->console.params().get(params::ParamId::kp);
  EXPECT_EQ(rig->reply("u 5:1:0:50"), "OK");
  EXPECT_EQ(rig->console.params().get(params::ParamId::kp), kp);
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
}

TEST(ConsoleBridge, OdocalsOwnCommandsAndTheirEchoAreUnchanged) {
  auto rig = make_rig(automatic_echo());
  EXPECT_EQ(exchange(*rig, "e\r"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "get c_l\r\n"), "ok c_l=1.000000\r\n");
  EXPECT_EQ(exchange(*rig, "ee\r\n"), "err unknown_command unknown command (try help)\r\n");
  EXPECT_FALSE(rig->console.echo_enabled());
  // A person at picocom: an odocal command ended by a bare CR turns the echo on, as before.
  EXPECT_EQ(exchange(*rig, "get c_r\r"), "get c_r\r\nok c_r=1.000000\r\n");
  EXPECT_TRUE(rig->console.echo_enabled());
  // With the echo on, an empty Enter gets a new line and no reply.
  EXPECT_EQ(exchange(*rig, "\r"), "\r\n");
  // picocom quit, ROS started on the port: its first line comes back echoed, then the automatic
  // echo is off and every reply is clean.
  EXPECT_EQ(exchange(*rig, "b\r"), "b\r\n115200\r\n");
  EXPECT_FALSE(rig->console.echo_enabled());
  EXPECT_EQ(exchange(*rig, "e\r"), "0 0\r\n");
  EXPECT_EQ(exchange(*rig, "\r"), "Invalid Command\r\n");
  EXPECT_EQ(exchange(*rig, "u 1:2:3:4\r"), "OK\r\n");
  // The person again: a backspace, or an odocal command ended by a bare CR, turns it back on.
  EXPECT_EQ(exchange(*rig, "get c_l\r"), "get c_l\r\nok c_l=1.000000\r\n");
  EXPECT_TRUE(rig->console.echo_enabled());
}

TEST(ConsoleBridge, AnEchoTheTargetOrEchoOnSetStaysOn) {
  ConsoleOptions options = automatic_echo();
  options.echo = EchoMode::on;  // a known interactive terminal: its echo is not automatic
  auto rig = make_rig(options);
  EXPECT_EQ(exchange(*rig, "e\r"), "e\r\n0 0\r\n");
  EXPECT_TRUE(rig->console.echo_enabled());
  EXPECT_EQ(exchange(*rig, "e\r"), "e\r\n0 0\r\n");
}

// Feed-forward only: on the rig's motors without a plant, the integral would grow until the stall
// watch trips.
std::unique_ptr<Rig> make_feed_forward_rig() {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("set kp 0"), "ok kp=0.000000");
  EXPECT_EQ(rig->reply("set ki 0"), "ok ki=0.000000");
  return rig;
}

TEST(ConsoleBridge, AnMIsHeldTwoSecondsThenTheWheelsStop) {
  auto rig = make_feed_forward_rig();
  // cmd_timeout_ms (500 ms by default) would stop an odocal `drive` long before: `m` is held.
  EXPECT_EQ(rig->reply("m 10 10"), "OK");
  EXPECT_EQ(mode(*rig), drive::Mode::drive);
  run_ms(*rig, 1990);
  EXPECT_EQ(mode(*rig), drive::Mode::drive);
  // A new `m` starts the 2 s again.
  EXPECT_EQ(rig->reply("m 12 12"), "OK");
  run_ms(*rig, 1990);
  EXPECT_EQ(mode(*rig), drive::Mode::drive);
  run_ms(*rig, 20);  // 2000 ms have passed (and a little more): ROSArduinoBridge's auto-stop
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
  run_ms(*rig, 3000);
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
}

TEST(ConsoleBridge, AFaultEndsTheHoldAndOnlyMZeroOrStopAcknowledgeIt) {
  auto rig = make_rig();  // full gains, no plant: the wheels never move and the stall watch trips
  EXPECT_EQ(rig->reply("m 10 10"), "OK");
  run_ms(*rig, 1500);
  EXPECT_EQ(mode(*rig), drive::Mode::fault);
  run_ms(*rig, 3000);  // the auto-stop does not acknowledge it
  EXPECT_EQ(mode(*rig), drive::Mode::fault);
  EXPECT_EQ(rig->reply("m 10 10"), "OK");  // answered as ROSArduinoBridge would; nothing moves
  EXPECT_EQ(mode(*rig), drive::Mode::fault);
  EXPECT_EQ(rig->reply("m 0 0"), "OK");
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
}

TEST(ConsoleBridge, BothZeroStopsAtOnceAndOdocalsStopEndsTheHold) {
  auto rig = make_feed_forward_rig();
  EXPECT_EQ(rig->reply("m 10 10"), "OK");
  run_ms(*rig, 100);
  EXPECT_EQ(rig->reply("m 0 0"), "OK");
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
  run_ms(*rig, 100);
  EXPECT_EQ(mode(*rig), drive::Mode::idle);
  EXPECT_EQ(rig->reply("m 10 10"), "OK");
  run_ms(*rig, 100);
  EXPECT_EQ(rig->reply("stop"), "ok mode=idle");
  run_ms(*rig, 100);
  EXPECT_EQ(mode(*rig), drive::Mode::idle);  // the hold did not drive again
}

TEST(ConsoleBridge, RAndOStopTheWheelsAsTheFirmwaresResetPidDoes) {
  for (const char* line : {"r", "o 0 0", "o 100 100"}) {
    auto rig = make_feed_forward_rig();
    EXPECT_EQ(rig->reply("m 10 10"), "OK");
    run_ms(*rig, 100);
    ASSERT_EQ(mode(*rig), drive::Mode::drive);
    EXPECT_EQ(rig->reply(line), "OK") << line;
    EXPECT_EQ(mode(*rig), drive::Mode::idle) << line;
    run_ms(*rig, 100);
    EXPECT_EQ(mode(*rig), drive::Mode::idle) << line;
  }
}

// Both wheels' duties after `line` has driven 500 ms (past the ramp) on a feed-forward rig.
std::pair<float, float> duties_after(const std::string& line) {
  auto rig = make_feed_forward_rig();
  EXPECT_EQ(rig->reply(line), "OK") << line;
  run_ms(*rig, 500);
  return {rig->pwm_left.duty, rig->pwm_right.duty};
}

TEST(ConsoleBridge, ArgumentsAreReadAsCsAtoiReadsThem) {
  // runCommand reads its arguments with atoi: a sign, digits, the first other character ends
  // the number, no digits is 0. The same wheel speeds, so the same duties.
  EXPECT_EQ(duties_after("m 1.5 2"), duties_after("m 1 2"));
  EXPECT_EQ(duties_after("m +3x -4y"), duties_after("m 3 -4"));
  EXPECT_EQ(duties_after("m 10"), duties_after("m 10 0"));
  EXPECT_EQ(duties_after("m 7 8 9"), duties_after("m 7 8"));
  // Beyond a million counts per frame (atoi itself would overflow): a million, then clipped.
  EXPECT_EQ(duties_after("m 99999999 0"), duties_after("m 1000000 0"));
  // No digits: 0 0, which stops.
  for (const char* line : {"m", "m x y", "m - +", "m .5 -.5"}) {
    auto rig = make_feed_forward_rig();
    EXPECT_EQ(rig->reply("m 10 10"), "OK");
    run_ms(*rig, 50);
    EXPECT_EQ(rig->reply(line), "OK") << line;
    EXPECT_EQ(mode(*rig), drive::Mode::idle) << line;
  }
}

TEST(ConsoleBridge, WheelSpeedsGoThroughTheLoopWithTheWheelFactors) {
  auto rig = make_feed_forward_rig();  // each wheel's duty is kff times its set-point (rad/s)
  for (const char* set : {"set c_l 0.98", "set c_r 1.02", "set wheelbase_mm 160"}) {
    EXPECT_EQ(rig->reply(set).rfind("ok ", 0), 0u) << set;
  }
  EXPECT_EQ(rig->reply("m 10 12"), "OK");
  run_ms(*rig, 500);  // past the acceleration ramp
  // ROS asked each wheel for n counts per 1/30 s of the nominal robot (60 mm, 1440 counts): a
  // contact speed of n * 30 * pi * D / N. The twist of those speeds over the wheelbase, driven
  // through the model (UMBmark: wheel diameters D * c_L and D * c_R, Maddahi eq. 7), turns each
  // wheel at its contact speed over its true radius: n * 30 * 2 pi / N / c.
  const double nominal_radps = 30.0 * 2.0 * std::numbers::pi / 1440.0;
  const double left_radps = 10.0 * nominal_radps / 0.98;
  const double right_radps = 12.0 * nominal_radps / 1.02;
  // Float arithmetic through the kinematics: a relative 1e-5 covers it.
  EXPECT_NEAR(rig->pwm_left.duty, 0.033 * left_radps, 0.033 * left_radps * 1e-5);
  EXPECT_NEAR(rig->pwm_right.duty, 0.033 * right_radps, 0.033 * right_radps * 1e-5);
}

TEST(ConsoleBridge, TheTwistGoesThroughTheWholeModelInForce) {
  auto rig = make_feed_forward_rig();
  for (const char* set :
       {"set c_l 0.99", "set f_lat 1.01", "set f_lon 0.98", "set wheelbase_arc_mm 165"}) {
    EXPECT_EQ(rig->reply(set).rfind("ok ", 0), 0u) << set;
  }
  EXPECT_EQ(rig->reply("m 6 14"), "OK");
  run_ms(*rig, 500);
  // The body twist ROS meant with the nominal wheel (60 mm, 1440 counts) and the wheelbase in
  // force (the wheel_separation odocal writes for it: 150 mm scaled as F_lat, F_lon scale it,
  // robot_model.hpp):
  const double mps_per_count = std::numbers::pi * 0.060 / 1440.0 * 30.0;
  const double left_factor = 0.99 / (1.01 * 0.98);
  const double right_factor = 1.0 / 0.98;
  const double wheelbase_m = 0.150 * (left_factor + right_factor) / (0.99 + 1.0);
  drive::Twist twist;
  twist.v_mps = static_cast<float>(0.5 * (6.0 + 14.0) * mps_per_count);
  twist.w_radps = static_cast<float>((14.0 - 6.0) * mps_per_count / wheelbase_m);
  // ... driven through the one model in force (core's kinematics: factors and arc wheelbase).
  const drive::DiffDriveKinematics model(params::to_drive_config(rig->console.params()));
  const drive::WheelRates rates = model.inverse(twist);
  EXPECT_NEAR(rig->pwm_left.duty, 0.033 * rates.left_radps, 0.033 * rates.left_radps * 1e-5);
  EXPECT_NEAR(rig->pwm_right.duty, 0.033 * rates.right_radps, 0.033 * rates.right_radps * 1e-5);
}

/// diffdrive_arduino's main-branch ArduinoComms: writes a command and reads exactly one line
/// back, up to its LF, never flushing what else came.
class NoFlushClient {
 public:
  explicit NoFlushClient(Rig& rig) : rig_(rig) {}
  std::string send_msg(const std::string& bytes) {
    rig_.stream.type(bytes);
    rig_.settle();
    const std::size_t end =
        std::string_view(rig_.stream.output.data(), rig_.stream.output_size).find('\n', read_);
    if (end == std::string_view::npos) {
      return "";
    }
    std::string line(rig_.stream.output.data() + read_, end + 1u - read_);
    read_ = end + 1u;
    return line;
  }
  /// Bytes the robot sent that the client never read.
  [[nodiscard]] std::size_t unread() const { return rig_.stream.output_size - read_; }

 private:
  Rig& rig_;
  std::size_t read_ = 0u;
};

TEST(ConsoleBridge, AClientThatNeverFlushesReadsItsOwnReplyForAThousandCycles) {
  // The robot as it starts on a UART: banner on, automatic echo, CR LF. The client opens the
  // port and sends "\r", the PID gains, then per cycle `e` and `m` (hardware/src/
  // arduino_comms.cpp, main branch); the wheels turn between cycles.
  ConsoleOptions options = automatic_echo();
  options.banner = true;
  auto rig = std::make_unique<Rig>(options);
  // The ring holds 128 KiB of output: 2002 replies of at most 14 bytes fit.
  (void)rig->console.start(rig->now_us);
  rig->tick(2);  // the loop counts from its first tick on
  NoFlushClient client(*rig);
  EXPECT_EQ(client.send_msg("\r"), "Invalid Command\r\n");
  EXPECT_EQ(client.send_msg("u 30:20:0:100\r"), "OK\r\n");
  WheelTurner left(*rig, true);
  WheelTurner right(*rig, false);
  long left_total = 0;
  long right_total = 0;
  for (int cycle = 0; cycle < 1000; ++cycle) {
    const std::string counts = client.send_msg("e\r");
    ASSERT_EQ(counts, std::to_string(left_total) + " " + std::to_string(right_total) + "\r\n")
        << "cycle " << cycle;
    ASSERT_EQ(client.send_msg("m 20 18\r"), "OK\r\n") << "cycle " << cycle;
    // The wheels turn about as asked: 20 and 18 counts per 1/30 s, a 30 Hz cycle.
    left.turn(20);
    right.turn(18);
    left_total += 20;
    right_total += 18;
    rig->tick(33);
  }
  EXPECT_EQ(client.unread(), 0u);
}

}  // namespace
}  // namespace odocal::test
