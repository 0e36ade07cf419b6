// The one sample quantile (type 7): order statistics and the interpolation between them.

#include "odocal/calib/quantile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace
}  // namespace odocal::calib
