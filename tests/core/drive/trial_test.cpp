#include "odocal/drive/trial.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "odocal/drive/control_loop.hpp"
#include "test_plant.hpp"

namespace odocal::drive {
namespace {

using test::TestRig;

TEST(TrialRecorder, ClosesOnlyOnceTheWheelsHaveBeenStill) {
  TrialRecorder recorder;
  recorder.begin(PathId::line, 1.0f, 100, -50);
  // Moving for 10 ticks of 1 ms, the counts climbing.
  for (int i = 1; i <= 10; ++i) {
    EXPECT_FALSE(recorder.update(true, 100 + 10 * i, -50 + 10 * i, Pose{}, 1000u, 50.0f));
  }
  // Motion over, but a wheel still creeps for 30 ms: not closed.
  for (int i = 1; i <= 30; ++i) {
    EXPECT_FALSE(recorder.update(false, 200 + i, 50, Pose{}, 1000u, 50.0f));
  }
  // Still for 49 ms: not yet; the 50th closes it.
  for (int i = 1; i < 50; ++i) {
    EXPECT_FALSE(recorder.update(false, 230, 50, Pose{}, 1000u, 50.0f));
  }
  EXPECT_TRUE(recorder.open());
  EXPECT_TRUE(recorder.update(false, 230, 50, Pose{0.5f, 0.1f, 0.2f}, 1000u, 50.0f));
  EXPECT_FALSE(recorder.open());
  const TrialRecord& t = recorder.last();
  EXPECT_EQ(t.number, 1u);
  EXPECT_EQ(t.path, PathId::line);
  EXPECT_EQ(t.count_l, 130);  // 230 - 100
  EXPECT_EQ(t.count_r, 100);  // 50 - (-50)
  EXPECT_EQ(t.duration_ms, 10u + 30u + 50u);
  EXPECT_FLOAT_EQ(t.end.x_m, 0.5f);
}

TEST(TrialRecorder, AnAbandonedTrialLeavesNoRecordAndNumbersGoOn) {
  TrialRecorder recorder;
  recorder.begin(PathId::drive, 0.0f, 0, 0);
  EXPECT_FALSE(recorder.update(true, 5, 5, Pose{}, 1000u, 50.0f));
  recorder.abandon();
  EXPECT_FALSE(recorder.update(false, 5, 5, Pose{}, 1000u, 0.0f));
  EXPECT_EQ(recorder.last().number, 0u);
  recorder.begin(PathId::drive, 0.0f, 5, 5);
  EXPECT_TRUE(recorder.update(false, 5, 5, Pose{}, 1000u, 0.0f));
  EXPECT_EQ(recorder.last().number, 1u);
}

TEST(TrialRecorder, AWheelThatNeverSettlesClosesAfterTheLongestSettle) {
  TrialRecorder recorder;
  recorder.begin(PathId::line, 1.0f, 0, 0);
  std::uint32_t ms = 0;
  bool closed = false;
  for (std::int64_t c = 1; !closed && ms < 10000u; ++c, ++ms) {
    closed = recorder.update(false, c, 0, Pose{}, 1000u, 50.0f);  // a count every tick
  }
  EXPECT_TRUE(closed);
  EXPECT_EQ(ms, TrialRecorder::max_settle_ms + 1u);
}

TEST(TrialLog, KeepsTheLast32OldestFirst) {
  TrialLog log;
  EXPECT_EQ(log.latest(), nullptr);
  for (std::uint32_t n = 1; n <= 40; ++n) {
    TrialRecord r;
    r.number = n;
    log.push(r);
  }
  EXPECT_EQ(log.size(), TrialLog::capacity);
  EXPECT_EQ(log.at(0).number, 9u);
  EXPECT_EQ(log.latest()->number, 40u);
  EXPECT_EQ(log.find(8), nullptr);
  ASSERT_NE(log.find(9), nullptr);
  EXPECT_EQ(log.find(9)->number, 9u);
  log.clear();
  EXPECT_EQ(log.size(), 0u);
  EXPECT_EQ(log.find(40), nullptr);
}

TEST(ControlLoopTrials, ALineTrialsCountsAreTheWheelTurnsTheRobotMade) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_line(0.5f)));
  rig.run_until_idle(10.0);
  rig.run_for(3.5);  // settling (TrialRecorder closes within 3 s of the motion)
  const TrialRecord t = rig.loop.last_trial();
  ASSERT_EQ(t.number, 1u);
  EXPECT_EQ(t.path, PathId::line);
  EXPECT_FLOAT_EQ(t.length_m, 0.5f);
  // The test robot's wheels are the nominal ones: 0.5 m is 0.5/(π·0.06)·1440 counts per wheel,
  // plus what the creep and the coast carry past the end (a few mm at most).
  const double counts = 0.5 / (M_PI * 0.06) * 1440.0;
  EXPECT_NEAR(static_cast<double>(t.count_l), counts, counts * 0.01);
  EXPECT_NEAR(static_cast<double>(t.count_r), counts, counts * 0.01);
  // Odometry at the end agrees with the counts: mean travel = the pose's distance.
  const double travel_m = 0.5 * static_cast<double>(t.count_l + t.count_r) * M_PI * 0.06 / 1440.0;
  EXPECT_NEAR(travel_m, std::hypot(t.end.x_m, t.end.y_m), 2e-4);
  EXPECT_FALSE(rig.loop.status().trial_open);
}

TEST(ControlLoopTrials, CumulativeCountsAreWrapSafeAndSurviveTheDecoderWrap) {
  TestRig rig;
  // The raw decoder count starts at 0: driving backwards wraps it to just below 2^32 at once;
  // the cumulative counts must go smoothly negative instead of jumping by 2^32.
  ASSERT_TRUE(rig.loop.drive(Twist{-0.2f, 0.0f}, 500u));  // backwards: counts go negative
  rig.run_for(1.0);
  const WheelCounts counts = rig.loop.wheel_counts();
  EXPECT_LT(counts.left, 0);
  EXPECT_LT(counts.right, 0);
  // ~0.1 m backwards (plus the start lag and the coast).
  const double expected = -0.1 / (M_PI * 0.06) * 1440.0;
  EXPECT_NEAR(static_cast<double>(counts.left), expected, 0.2 * -expected);
  EXPECT_GT(counts.t_us, 900000u);
}

TEST(ControlLoopTrials, StopAbandonsTheTrial) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_line(0.5f)));
  rig.run_for(0.5);
  EXPECT_TRUE(rig.loop.status().trial_open);
  rig.loop.stop();
  rig.run_for(4.0);
  EXPECT_FALSE(rig.loop.status().trial_open);
  EXPECT_EQ(rig.loop.last_trial().number, 0u);
}

}  // namespace
}  // namespace odocal::drive
