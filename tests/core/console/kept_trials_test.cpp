#include "odocal/console/kept_trials.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace odocal::test {
namespace {

drive::TrialRecord record(std::uint32_t number, std::int64_t count_l, std::int64_t count_r) {
  drive::TrialRecord r;
  r.number = number;
  r.path = drive::PathId::line;
  r.length_m = 2.0f;
  r.duration_ms = 1000u + number;
  r.count_l = count_l;
  r.count_r = count_r;
  r.end = drive::Pose{1.0f, -0.5f, 0.25f};
  return r;
}

TEST(KeptTrials, KeepsTheLast32OldestFirst) {
  console::KeptTrials trials;
  EXPECT_EQ(trials.latest(), nullptr);
  for (std::uint32_t n = 1; n <= 40; ++n) {
    trials.push(record(n, n * 10, -static_cast<std::int64_t>(n)));
  }
  ASSERT_EQ(trials.size(), console::KeptTrials::capacity);
  EXPECT_EQ(trials.at(0).number, 9u);  // 1..8 dropped
  EXPECT_EQ(trials.latest()->number, 40u);
  EXPECT_EQ(trials.find(8), nullptr);
  const console::KeptTrial* t = trials.find(20);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->count_l, 200);
  EXPECT_EQ(t->count_r, -20);
  EXPECT_EQ(t->duration_ms, 1020u);
  EXPECT_EQ(t->path, drive::PathId::line);
  EXPECT_FLOAT_EQ(t->length_m, 2.0f);
  EXPECT_FLOAT_EQ(t->end.x_m, 1.0f);
  EXPECT_FLOAT_EQ(t->end.y_m, -0.5f);
  EXPECT_FLOAT_EQ(t->end.theta_rad, 0.25f);
  trials.clear();
  EXPECT_EQ(trials.size(), 0u);
  EXPECT_EQ(trials.latest(), nullptr);
}

TEST(KeptTrials, CountsBeyond32BitsSaturateInsteadOfWrapping) {
  console::KeptTrials trials;
  // 2^32 + 5 would wrap to 5 in 32 bits: it must read as the largest count instead.
  trials.push(record(1, (std::int64_t{1} << 32) + 5, -(std::int64_t{1} << 40)));
  EXPECT_EQ(trials.latest()->count_l, 2147483647);
  EXPECT_EQ(trials.latest()->count_r, -2147483647);
  trials.push(record(2, 2147483647, -2147483647));  // the range's ends are kept exactly
  EXPECT_EQ(trials.latest()->count_l, 2147483647);
  EXPECT_EQ(trials.latest()->count_r, -2147483647);
}

}  // namespace
}  // namespace odocal::test
