// A reading is checked before it is taken: the reach of the geometry box (worked out by hand from
// the exact-arc model), and each slip a person makes at the tape shown back with what it would
// have been.
#include "reading_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace odocal::host::session {
namespace {

constexpr double deg = 180.0 / std::numbers::pi;

/// 60 mm wheels, 150 mm wheelbase, one wheelbase: the default robot's model in force.
drive::model::Geometry<double> robot() {
  return drive::model::Geometry<double>{60.0, 60.0, 150.0, 0.0};
}

std::optional<drive::Path> path_of_command(const std::string& command) {
  const std::optional<Motion> motion = Motion::of_command(command);
  return motion ? motion->path() : std::nullopt;
}

TEST(Motion, CommandsNameTheirPaths) {
  ASSERT_TRUE(path_of_command("run line 3.000"));
  EXPECT_EQ(path_of_command("run line 3.000")->count, 1);
  EXPECT_EQ(path_of_command("run umbmark-cw 2")->count, drive::make_umbmark_square(true, 2).count);
  EXPECT_TRUE(path_of_command("run unseen"));
  const std::optional<drive::Path> spin = path_of_command("drive 0 1.5708 24000");
  ASSERT_TRUE(spin);
  EXPECT_NEAR(spin->segments[0].angle_rad, 1.5708 * 24.0, 1e-3);
  EXPECT_EQ(spin->segments[0].distance_m, 0.0f);
  EXPECT_FALSE(path_of_command("selftest left"));
  EXPECT_TRUE(Motion::of_command("selftest left"));
  EXPECT_FALSE(path_of_command("run line x"));
  EXPECT_FALSE(path_of_command("drive 0.1 0"));  // runs until stopped: not a run's motion
}

TEST(Motion, ALineIsReadAsTheRobotReadsItAndRefusedWhereItRefuses) {
  // The robot's ranges (console/commands.hpp): a run from 0.01 to 20 m, |v| <= 5 m/s,
  // |w| <= 50 rad/s, 0 .. 600000 whole milliseconds.
  EXPECT_TRUE(Motion::of_command("run line 0.01"));
  EXPECT_FALSE(Motion::of_command("run line 0.009"));
  EXPECT_TRUE(Motion::of_command("run line 20"));
  EXPECT_FALSE(Motion::of_command("run line 20.0001"));
  EXPECT_FALSE(Motion::of_command("drive 5.1 0 1000"));
  EXPECT_FALSE(Motion::of_command("drive 0.1 -50.5 1000"));
  EXPECT_FALSE(Motion::of_command("drive 0.1 0 1000.5"));
  EXPECT_FALSE(Motion::of_command("drive 0.1 0 600001"));
  EXPECT_FALSE(Motion::of_command("selftest both"));
  EXPECT_FALSE(Motion::of_command("run"));
  EXPECT_FALSE(Motion::of_command("get c_l"));
  // Extra spaces are the robot's separators too; the words are the same motion.
  EXPECT_EQ(Motion::of_command("  run   line  1.5 "), Motion::line(1.5));
}

TEST(Motion, AMotionIsTheValueItsLineCarriesAndComparesAsOne) {
  // Built from any double, a motion holds what its line carries: the same motion read back.
  for (const Motion& m :
       {Motion::line(1.23456), Motion::square(true, 2.0004), Motion::square(false, 0.7),
        Motion::timed(0.123456, -0.98765, 2499.6), Motion::timed(0.0, 1.5708, 24000.0),
        Motion::unseen(), Motion::selftest(Motion::Wheels::left),
        Motion::selftest(Motion::Wheels::both)}) {
    const std::optional<Motion> read = Motion::of_command(m.command());
    ASSERT_TRUE(read) << m.command();
    EXPECT_EQ(*read, m) << m.command();
    EXPECT_EQ(read->command(), m.command());
  }
  EXPECT_EQ(Motion::line(1.23456).command(), "run line 1.235");
  EXPECT_EQ(Motion::timed(0.123456, -0.98765, 2499.6).command(), "drive 0.1235 -0.9877 2500");
  EXPECT_EQ(Motion::square(false, 0.7).command(), "run umbmark-ccw 0.700");
  // Compared as values, not as text: "1.5" and "1.500" are the same line.
  EXPECT_EQ(*Motion::of_command("run line 1.5"), *Motion::of_command("run line 1.500"));
  EXPECT_NE(Motion::line(1.5), Motion::square(true, 1.5));
  EXPECT_NE(Motion::timed(0.1, 0.2, 1000), Motion::timed(0.1, 0.2, 1001));
  // A line with more digits than the usual is the motion the robot reads, and the line written for
  // it starts that same motion (session.json rewritten on --resume keeps it).
  const Motion precise = *Motion::of_command("run line 0.50660");
  EXPECT_EQ(*Motion::of_command(precise.command()), precise) << precise.command();
  EXPECT_NE(precise, Motion::line(0.507));
  const Motion fine_arc = *Motion::of_command("drive 0.123456 -0.5 2000");
  EXPECT_EQ(*Motion::of_command(fine_arc.command()), fine_arc) << fine_arc.command();
  // A motion the robot would refuse stays what was asked for: sent, the robot refuses it (and the
  // session says so); never another motion.
  const Motion too_long = Motion::line(25.0);
  EXPECT_EQ(too_long.kind, Motion::Kind::line);
  EXPECT_EQ(too_long.command(), "run line 25.000");
  EXPECT_FALSE(Motion::of_command(too_long.command()));
}

TEST(ReadingCheck, ALinesReachIsTheWheelRatioOverTheShortestWheelbase) {
  // Straight 3 m: the heading turns L·d/(b(1+e)) with the ratio d = 2 % and the wheelbase 8 %
  // short; the noise adds 2 deg and 0.1 deg per wheelbase of line (20 of them), and to the
  // position that heading noise carried over 1.5 m.
  const ReadingAllowance a = allowance_of(drive::make_line(3.0f), robot());
  const double heading = 3000.0 * reading_box::ratio / (150.0 * (1.0 - reading_box::wheelbase));
  const double heading_noise = reading_noise::heading_deg + 0.1 * 3000.0 / 150.0;
  EXPECT_NEAR(a.heading_deg, heading * deg + heading_noise, 1e-3);
  // The stop moves sideways by about L·θ/2 (the heading grows along the line) and along it by
  // the scale: between those and their sum.
  const double sideways = 0.5 * 3000.0 * heading;
  EXPECT_GT(a.position_mm, sideways);
  const double noise = 10.0 + 0.01 * 3000.0 + heading_noise / deg * 1500.0;
  EXPECT_LT(a.position_mm, sideways + reading_box::scale * 3000.0 + noise + 1.0);
}

TEST(ReadingCheck, ATurnInPlacesReachIsTheScaleOverTheWheelbase) {
  // Six turns in place: the heading is θ·(1 + s)/(1 + e); its largest change is at s = +5 %,
  // e = −8 %.
  drive::Path spin;
  ASSERT_TRUE(spin.push(drive::Segment{0.0f, static_cast<float>(12.0 * std::numbers::pi)}));
  const ReadingAllowance a = allowance_of(spin, robot());
  const double reach = 2160.0 * ((1.0 + reading_box::scale) / (1.0 - reading_box::wheelbase) - 1.0);
  EXPECT_NEAR(a.heading_deg, reach + reading_noise::heading_deg + 0.005 * 2160.0, 0.01);
  // Unequal wheels turning in place move the centre round a circle of radius b·d/4 (d the
  // ratio's share): at most its diameter away, on top of the 10 mm of tape.
  EXPECT_LT(a.position_mm, reading_noise::position_mm + 1.1 * 150.0 * reading_box::ratio / 2.0);
}

/// The facts of a 3 m line whose odometry stopped at 3000.1, 0.0, heading 0.1.
ReadingFacts line_facts() {
  ReadingFacts f;
  f.odom = SessionPose{3000.1, 0.0, 0.1};
  f.allowance = allowance_of(drive::make_line(3.0f), robot());
  f.extent = extent_of(drive::make_line(3.0f));
  return f;
}

void expect_slip(const ReadingFacts& f, const SessionPose& typed_pose, const std::string& typed,
                 const std::string& slip, const SessionPose& meant) {
  const ReadingVerdict v = judge_reading(f, typed_pose, typed);
  EXPECT_FALSE(v.plausible) << typed;
  EXPECT_NE(v.likely.find(slip), std::string::npos) << typed << ": " << v.likely;
  ASSERT_TRUE(v.suggestion) << typed;
  EXPECT_NEAR(v.suggestion->x_mm, meant.x_mm, 1e-9) << typed;
  EXPECT_NEAR(v.suggestion->y_mm, meant.y_mm, 1e-9) << typed;
  if (meant.theta_deg) {
    ASSERT_TRUE(v.suggestion->theta_deg);
    EXPECT_NEAR(*v.suggestion->theta_deg, *meant.theta_deg, 1e-9) << typed;
  }
  EXPECT_NE(v.explained().find("did you mean"), std::string::npos);
}

TEST(ReadingCheck, ATrueReadingIsTaken) {
  const ReadingFacts f = line_facts();
  EXPECT_TRUE(judge_reading(f, SessionPose{3012.5, 3.0, 0.4}, "3012.5 3 0.4").plausible);
  // 1 % of wheel difference over 3 m puts the stop 300 mm to the side: still a robot.
  EXPECT_TRUE(judge_reading(f, SessionPose{2995.0, -300.0, -11.0}, "").plausible);
  EXPECT_TRUE(judge_reading(f, SessionPose{2995.0, 300.0, std::nullopt}, "").plausible);
}

TEST(ReadingCheck, EachSlipIsShownBackWithWhatItWouldHaveBeen) {
  const ReadingFacts f = line_facts();
  const SessionPose meant{3012.5, 3.0, 0.4};
  expect_slip(f, {3.0, 3012.5, 0.4}, "3 3012.5 0.4", "x and y swapped", meant);
  expect_slip(f, {3.0125, 0.003, 0.4}, "3.0125 0.003 0.4", "metres for millimetres", meant);
  expect_slip(f, {301.25, 0.3, 0.4}, "301.25 0.3 0.4", "centimetres", meant);
  expect_slip(f, {-3012.5, 3.0, 0.4}, "-3012.5 3 0.4", "the sign of x", meant);
  expect_slip(f, {3012.5, 3.0, 360.4}, "3012.5 3 360.4", "a whole turn", meant);
  // The difference from the odometry typed as the stop point.
  expect_slip(f, {12.4, 3.0, 0.3}, "12.4 3 0.3", "difference from the odometry", meant);
}

TEST(ReadingCheck, AnArcsSideTellsASwappedPairsSign) {
  // A right arc (0.15 m/s, -0.2 rad/s, 3 s) whose odometry stopped at 427.2, -133.9: the pair
  // typed swapped and the lateral sign lost.
  const std::optional<drive::Path> arc = path_of_command("drive 0.150 -0.200 3000");
  ASSERT_TRUE(arc);
  ReadingFacts f;
  f.odom = SessionPose{427.2, -133.9, -34.4};
  f.allowance = allowance_of(*arc, robot());
  f.extent = extent_of(*arc);
  EXPECT_TRUE(judge_reading(f, SessionPose{428.8, -130.6, -34.0}, "").plausible);
  expect_slip(f, {130.6, 428.8, -34.0}, "130.6 428.8 -34", "swapped, and the sign of y",
              {428.8, -130.6, -34.0});
  expect_slip(f, {428.8, 130.6, -34.0}, "428.8 130.6 -34", "the sign of y", {428.8, -130.6, -34.0});
  expect_slip(f, {428.8, -130.6, 34.0}, "428.8 -130.6 34", "the heading's sign",
              {428.8, -130.6, -34.0});
}

TEST(ReadingCheck, ADecimalCommaIsNamed) {
  ReadingFacts f = line_facts();
  f.odom = SessionPose{12.0, 0.0, 0.0};  // a 3 m line whose odometry stopped at 12.0 mm
  // "12,5 3" is read as x 12, y 5, heading 3: plausible here? 5 mm to the side, yes: not asked.
  EXPECT_TRUE(judge_reading(f, SessionPose{12.0, 5.0, 3.0}, "12,5 3").plausible);
  // After 3 m, "12,5 3" (read as 12, 5, 3) cannot be: asked, the comma named.
  const ReadingFacts line = line_facts();
  const ReadingVerdict v = judge_reading(line, SessionPose{12.0, 5.0, 3.0}, "12,5 3");
  EXPECT_FALSE(v.plausible);
  EXPECT_NE(v.explained().find("comma"), std::string::npos) << v.explained();
  // "1,5" (read as 1 and 5) after 3 m: asked.
  const ReadingVerdict alone = judge_reading(line, SessionPose{1.0, 5.0, std::nullopt}, "1,5");
  EXPECT_FALSE(alone.plausible);
}

TEST(ReadingCheck, AReadingNoSlipExplainsIsStillAsked) {
  const ReadingFacts f = line_facts();
  const ReadingVerdict two_metres = judge_reading(f, SessionPose{5000.0, 0.0, 0.0}, "5000 0 0");
  EXPECT_FALSE(two_metres.plausible);
  EXPECT_NE(two_metres.problem.find("2000 mm"), std::string::npos) << two_metres.problem;
  EXPECT_FALSE(two_metres.suggestion);
  EXPECT_NE(two_metres.explained().find("measure again"), std::string::npos);
  const ReadingVerdict turned = judge_reading(f, SessionPose{3000.0, 0.0, -170.9}, "");
  EXPECT_FALSE(turned.plausible);  // 191 deg from the odometry's heading
}

TEST(ReadingCheck, ATurnInPlaceNeedsItsHeadingAndAgreesWithItsRepeat) {
  drive::Path spin;
  ASSERT_TRUE(spin.push(drive::Segment{0.0f, static_cast<float>(12.0 * std::numbers::pi)}));
  ReadingFacts f;
  f.odom = SessionPose{0.2, -0.1, 0.1};
  f.allowance = allowance_of(spin, robot());
  f.extent = extent_of(spin);
  f.heading_needed = true;
  const ReadingVerdict none = judge_reading(f, SessionPose{1.0, 2.0, std::nullopt}, "1 2");
  EXPECT_FALSE(none.plausible);
  EXPECT_NE(none.problem.find("heading"), std::string::npos);
  // Alone, six turns leave a heading anywhere within about ±318 deg of the odometry's: -37.3 and
  // +37.3 can both be.
  EXPECT_TRUE(judge_reading(f, SessionPose{1.0, 2.0, 37.3}, "").plausible);
  // The same run measured at -37.3 once before, the same factors in force: one earlier reading
  // alone cannot tell which of the two is off, so neither is questioned here (the jury shows
  // both); twice before, alike, and +37.3 is the sign.
  f.earlier.push_back(
      EarlierReading{SessionPose{0.1, 0.0, 0.2}, SessionPose{1.5, 1.0, -37.3}, true});
  EXPECT_TRUE(judge_reading(f, SessionPose{1.0, 2.0, 37.3}, "").plausible);
  f.earlier.push_back(
      EarlierReading{SessionPose{0.1, 0.0, 0.2}, SessionPose{1.2, 0.8, -36.8}, true});
  expect_slip(f, {1.0, 2.0, 37.3}, "1 2 37.3", "the heading's sign", {1.0, 2.0, -37.3});
  EXPECT_TRUE(judge_reading(f, SessionPose{1.0, 2.0, -36.1}, "").plausible);
  // A calibration applied between them: a repeat can be anywhere from the earlier error to none
  // (and the noise), not past it on the other side.
  f.earlier[0].same_factors = false;
  f.earlier[1].same_factors = false;
  EXPECT_TRUE(judge_reading(f, SessionPose{1.0, 2.0, -1.0}, "").plausible);
  EXPECT_FALSE(judge_reading(f, SessionPose{1.0, 2.0, 60.0}, "").plausible);
}

}  // namespace
}  // namespace odocal::host::session
