// Accuracy figures of Maddahi & Zareinia, Tables 3 and 4: RMS of the radial error per scenario
// and the improvement over no calibration, reproduced to the printed precision (half a unit of
// the last printed digit).
#include "odocal/calib/accuracy.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace odocal::calib {
namespace {

struct Scenario {
  std::vector<EndError> trials;
  std::vector<double> printed_r;  // r_e column
  double printed_rms;
  double printed_improvement;  // k_I, percent (0 for NC)
};

void check_table(const std::vector<Scenario>& table, double rms_tol) {
  double baseline = 0.0;
  ASSERT_EQ(rms_radial_error(table[0].trials.data(), table[0].trials.size(), baseline),
            AccuracyStatus::ok);
  for (const Scenario& s : table) {
    for (std::size_t i = 0; i < s.trials.size(); ++i) {
      // x_e, y_e are printed to ±0.05, so r from them is good to 0.05·(|x| + |y|)/r; the printed
      // r_e adds its own ±0.05.
      const EndError& e = s.trials[i];
      const double r = std::hypot(e.x_mm, e.y_mm);
      const double tol = 0.05 * (std::fabs(e.x_mm) + std::fabs(e.y_mm)) / r + 0.05;
      EXPECT_NEAR(r, s.printed_r[i], tol);
    }
    double rms = 0.0;
    ASSERT_EQ(rms_radial_error(s.trials.data(), s.trials.size(), rms), AccuracyStatus::ok);
    EXPECT_NEAR(rms, s.printed_rms, rms_tol);
    double pct = 0.0;
    ASSERT_EQ(improvement_pct(rms, baseline, pct), AccuracyStatus::ok);
    EXPECT_NEAR(pct, s.printed_improvement, 0.05);
  }
}

TEST(Accuracy, Table3SystematicErrorsReproduce) {
  check_table({{{{33.5, -45.2}, {34.2, -40.1}, {32.2, -42.7}, {36.9, -52.1}, {35.6, -49.0}},
                {56.3, 52.7, 53.5, 63.8, 60.6},
                57.5,
                0.0},
               {{{9.8, -2.5}, {10.6, 4.6}, {-8.3, 8.1}, {9.5, 6.4}, {9.5, -3.7}},
                {10.1, 11.6, 11.6, 11.5, 10.2},
                11.0,
                80.9},
               {{{6.2, 4.3}, {-5.4, 5.9}, {7.1, -1.3}, {-4.7, 5.2}, {3.8, 4.0}},
                {7.5, 8.0, 7.2, 7.0, 5.5},
                7.1,
                87.6}},
              0.05);
}

TEST(Accuracy, Table4NonSystematicErrorsReproduce) {
  check_table(
      {{{{1848.8, 3383.7},
         {2033.4, -3022.4},
         {2040.3, -3384.3},
         {2242.0, -3896.3},
         {2112.9, -3374.6}},
        {3855.8, 3642.7, 3951.8, 4495.3, 3981.5},
        3995.3,
        0.0},
       {{{645.7, -182.3}, {586.8, -374.8}, {518.8, -626.6}, {532.3, -722.3}, {521.0, -292.1}},
        {670.9, 696.2, 813.5, 897.2, 597.4},
        742.8,
        81.4},
       {{{429.5, 318.0}, {304.9, 443.4}, {426.5, 102.2}, {245.1, 403.1}, {230.5, 305.2}},
        {534.4, 538.1, 438.5, 471.8, 382.5},
        476.7,
        88.1}},
      0.05);
}

// By hand: errors (3, 4) and (0, 0): r = 5 and 0, RMS = sqrt(25/2) = 3.5355339; against a
// baseline of 10 the improvement is 64.644661 %; a worse scenario gives a negative value.
TEST(Accuracy, HandComputedValuesAndErrors) {
  const EndError trials[2] = {{3.0, 4.0}, {0.0, 0.0}};
  double rms = 0.0;
  {
    const test::AllocationWatch watch;
    ASSERT_EQ(rms_radial_error(trials, 2, rms), AccuracyStatus::ok);
    EXPECT_EQ(watch.allocations(), 0u);
  }
  EXPECT_NEAR(rms, 3.5355339, 1e-7);
  double pct = 0.0;
  ASSERT_EQ(improvement_pct(rms, 10.0, pct), AccuracyStatus::ok);
  EXPECT_NEAR(pct, 64.644661, 1e-6);
  ASSERT_EQ(improvement_pct(20.0, 10.0, pct), AccuracyStatus::ok);
  EXPECT_DOUBLE_EQ(pct, -100.0);
  EXPECT_EQ(rms_radial_error(trials, 0, rms), AccuracyStatus::no_trials);
  const EndError bad[1] = {{NAN, 0.0}};
  EXPECT_EQ(rms_radial_error(bad, 1, rms), AccuracyStatus::non_finite);
  EXPECT_EQ(improvement_pct(1.0, 0.0, pct), AccuracyStatus::bad_baseline);
  EXPECT_EQ(improvement_pct(NAN, 1.0, pct), AccuracyStatus::non_finite);
  // 1e300 / 1e-10 overflows: refused, not returned as −inf.
  EXPECT_EQ(improvement_pct(1e300, 1e-10, pct), AccuracyStatus::non_finite);
  ASSERT_EQ(improvement_pct(10.0, 10.0, pct), AccuracyStatus::ok);
  EXPECT_FALSE(std::signbit(pct));
}

// r = hypot(x, y): errors of 1e155 mm would overflow x² + y² (1e310) but not r. The RMS of
// equal radial errors r is r itself; all-zero errors give 0.
TEST(Accuracy, HugeErrorsDoNotOverflow) {
  const EndError huge[2] = {{1e155, 1e155}, {-1e155, 1e155}};
  double rms = 0.0;
  ASSERT_EQ(rms_radial_error(huge, 2, rms), AccuracyStatus::ok);
  EXPECT_NEAR(rms / (std::sqrt(2.0) * 1e155), 1.0, 1e-12);
  const EndError tiny[2] = {{3e-200, 4e-200}, {0.0, 0.0}};
  ASSERT_EQ(rms_radial_error(tiny, 2, rms), AccuracyStatus::ok);
  EXPECT_NEAR(rms / 3.5355339e-200, 1.0, 1e-7);
  const EndError zero[1] = {{0.0, 0.0}};
  ASSERT_EQ(rms_radial_error(zero, 1, rms), AccuracyStatus::ok);
  EXPECT_EQ(rms, 0.0);
  const EndError beyond[1] = {{1.5e308, 1.5e308}};  // r itself is not a double
  EXPECT_EQ(rms_radial_error(beyond, 1, rms), AccuracyStatus::non_finite);
}

}  // namespace
}  // namespace odocal::calib
