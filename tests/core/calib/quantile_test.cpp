// The one sample quantile (type 7): order statistics and the interpolation between them; the one
// Student-t quantile against the tables and closed forms.

#include "odocal/calib/quantile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace odocal::calib {
namespace {

TEST(SampleQuantile, EndsAreTheMinimumAndTheMaximum) {
  std::vector<double> v = {4.0, -1.0, 9.5, 3.0, 3.0};
  EXPECT_EQ(sample_quantile(v.data(), v.size(), 0.0), -1.0);
  EXPECT_EQ(sample_quantile(v.data(), v.size(), 1.0), 9.5);
  std::vector<double> one = {7.25};
  EXPECT_EQ(sample_quantile(one.data(), one.size(), 0.0), 7.25);
  EXPECT_EQ(sample_quantile(one.data(), one.size(), 0.5), 7.25);
  EXPECT_EQ(sample_quantile(one.data(), one.size(), 1.0), 7.25);
}

TEST(SampleQuantile, InterpolatesBetweenOrderStatistics) {
  // Sorted: 10 20 30 40 50. h = p·4: p = 0.5 -> the third (30); p = 0.3 -> h = 1.2, 20 + 0.2·10;
  // p = 0.95 -> h = 3.8, 40 + 0.8·10.
  const std::vector<double> data = {50.0, 10.0, 40.0, 20.0, 30.0};
  const auto q = [&data](double p) {
    std::vector<double> v = data;
    return sample_quantile(v.data(), v.size(), p);
  };
  EXPECT_DOUBLE_EQ(q(0.5), 30.0);
  EXPECT_DOUBLE_EQ(q(0.3), 22.0);
  EXPECT_DOUBLE_EQ(q(0.95), 48.0);
  EXPECT_DOUBLE_EQ(q(0.25), 20.0);  // h = 1 exactly: the second, nothing of the third
  // Even count: the median is the mean of the middle two.
  std::vector<double> even = {3.0, 1.0, 4.0, 2.0};
  EXPECT_DOUBLE_EQ(sample_quantile(even.data(), even.size(), 0.5), 2.5);
}

TEST(SampleQuantile, AgreesWithSortingOnTiesAndKeepsTheValues) {
  std::vector<double> v;
  for (int i = 0; i < 101; ++i) {
    v.push_back(static_cast<double>((i * 37) % 11));  // many ties, unsorted
  }
  std::vector<double> sorted = v;
  std::sort(sorted.begin(), sorted.end());
  for (double p : {0.025, 0.1, 0.5, 0.9, 0.975}) {
    std::vector<double> w = v;
    const double h = p * 100.0;
    const auto below = static_cast<std::size_t>(h);
    const double expected =
        sorted[below] + (h - static_cast<double>(below)) *
                            (sorted[std::min<std::size_t>(below + 1, 100)] - sorted[below]);
    EXPECT_DOUBLE_EQ(sample_quantile(w.data(), w.size(), p), expected) << p;
    std::sort(w.begin(), w.end());
    EXPECT_EQ(w, sorted);  // reordered, nothing lost
  }
}

// Student-t quantiles against the published tables (Abramowitz & Stegun table 26.10; any
// statistics table), to the 4-5 digits they print: a rounded table, a crude integration or a
// truncated expansion misses some of them (the Cornish-Fisher series to 1/ν⁴ is 0.05 off at
// ν = 1, a 3-digit table up to 5e-4).
TEST(StudentTQuantile, MatchesTheTables) {
  EXPECT_NEAR(student_t_quantile(0.975, 1.0), 12.7062, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 2.0), 4.3027, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 3.0), 3.1824, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 5.0), 2.5706, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 10.0), 2.2281, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.975, 30.0), 2.0423, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.95, 4.0), 2.1318, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.95, 30.0), 1.6973, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.995, 1.0), 63.6567, 5e-5);
  EXPECT_NEAR(student_t_quantile(0.9995, 3.0), 12.9240, 5e-5);
}

TEST(StudentTQuantile, ClosedFormsForOneAndTwoDegreesOfFreedom) {
  // ν = 1 is the Cauchy distribution, t = tan(π(p − 1/2)); ν = 2 has
  // t = (2p − 1)·sqrt(2 / (4p(1 − p))). Both exact, so the agreement is to rounding.
  const double pi = std::numbers::pi;
  for (const double p : {0.6, 0.75, 0.9, 0.975, 0.999}) {
    const double cauchy = std::tan(pi * (p - 0.5));
    EXPECT_NEAR(student_t_quantile(p, 1.0), cauchy, 1e-9 * cauchy) << p;
    const double two = (2.0 * p - 1.0) * std::sqrt(2.0 / (4.0 * p * (1.0 - p)));
    EXPECT_NEAR(student_t_quantile(p, 2.0), two, 1e-9 * two) << p;
  }
}

TEST(StudentTQuantile, NormalLimitSymmetryAndFractionalDegreesOfFreedom) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(student_t_quantile(0.975, inf), 1.959963985, 1e-9);
  EXPECT_NEAR(normal_quantile(0.975), 1.959963985, 1e-9);
  // Large but finite: t − z ≈ (z³ + z)/(4ν) (A&S 26.7.5), on both sides of the switch to the
  // expansion at 1e5.
  const double z = 1.959963984540054;  // Φ⁻¹(0.975) to double precision
  for (const double dof : {1e4, 99999.0, 1e5, 1e7}) {
    EXPECT_NEAR(student_t_quantile(0.975, dof) - z, (z * z * z + z) / (4.0 * dof),
                3.0 / (dof * dof) + 1e-10)
        << dof;
  }
  EXPECT_DOUBLE_EQ(student_t_quantile(0.025, 3.0), -student_t_quantile(0.975, 3.0));
  EXPECT_EQ(student_t_quantile(0.5, 7.0), 0.0);
  // Welch and Bell-McCaffrey degrees of freedom are not whole: strictly between the neighbours.
  const double t = student_t_quantile(0.975, 3.5);
  EXPECT_LT(t, 3.1824);
  EXPECT_GT(t, 2.7764);
  EXPECT_TRUE(std::isnan(student_t_quantile(0.975, 0.0)));
  EXPECT_TRUE(std::isnan(student_t_quantile(1.0, 3.0)));
}

}  // namespace
}  // namespace odocal::calib
