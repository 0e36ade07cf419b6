#include "odocal/math/bounded_trig.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace odocal::math {
namespace {

// One float rounding near 1 is 2^-24 ~ 6e-8; the polynomial evaluation and the reduction add a
// few such roundings. 2.5e-7 = about four roundings of a unit value.
constexpr double kUnitTolerance = 2.5e-7;

TEST(BoundedTrig, SinCosMatchDoubleOverTheHeadingRange) {
  double worst = 0.0;
  for (int i = -200000; i <= 200000; ++i) {
    const float x = static_cast<float>(i) * 1.6e-5f;  // [-3.2, 3.2] rad, every quadrant
    const SinCos sc = sin_cos(x);
    worst = std::fmax(worst, std::fabs(sc.sin - std::sin(static_cast<double>(x))));
    worst = std::fmax(worst, std::fabs(sc.cos - std::cos(static_cast<double>(x))));
  }
  EXPECT_LT(worst, kUnitTolerance);
}

TEST(BoundedTrig, SmallAnglesKeepTheirRelativeAccuracy) {
  // The tick's half-increments: sin x ~ x must be right to float precision relative to x.
  for (float x = 1e-30f; x < 0.1f; x *= 1.7f) {
    const SinCos sc = sin_cos(x);
    const double exact = std::sin(static_cast<double>(x));
    EXPECT_NEAR(sc.sin, exact, 3.0 * 6e-8 * exact) << x;
    EXPECT_NEAR(-sin_cos(-x).sin, exact, 3.0 * 6e-8 * exact) << x;
    EXPECT_NEAR(sc.cos, std::cos(static_cast<double>(x)), kUnitTolerance) << x;
  }
  EXPECT_EQ(sin_cos(0.0f).sin, 0.0f);
  EXPECT_EQ(sin_cos(0.0f).cos, 1.0f);
}

TEST(BoundedTrig, ModerateAnglesStillAccurate) {
  // Up to 64 rad the split-pi/2 reduction is exact; the error stays a few roundings of 1.
  for (float x = -64.0f; x <= 64.0f; x += 0.0137f) {
    const SinCos sc = sin_cos(x);
    EXPECT_NEAR(sc.sin, std::sin(static_cast<double>(x)), kUnitTolerance) << x;
    EXPECT_NEAR(sc.cos, std::cos(static_cast<double>(x)), kUnitTolerance) << x;
  }
}

TEST(BoundedTrig, WrapPiMatchesRemainder) {
  const double two_pi = 2.0 * M_PI;
  for (float a = -1000.0f; a <= 1000.0f; a += 0.0731f) {
    const float w = wrap_pi(a);
    EXPECT_GE(w, -3.14159265f) << a;
    EXPECT_LE(w, 3.14159265f) << a;
    // The same angle: the difference is a whole number of turns, up to float rounding of |a|.
    const double turns = (static_cast<double>(a) - w) / two_pi;
    EXPECT_NEAR(turns, std::round(turns), 1e-6) << a;
    const double exact = std::remainder(static_cast<double>(a), two_pi);
    if (std::fabs(std::fabs(exact) - M_PI) > 1e-4) {  // away from the +-pi seam
      EXPECT_NEAR(w, exact, 4.0 * 6e-8 * (1.0 + std::fabs(a))) << a;
    }
  }
  EXPECT_EQ(wrap_pi(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(wrap_pi(3.0f), 3.0f);
  EXPECT_FLOAT_EQ(wrap_pi(-3.0f), -3.0f);
}

}  // namespace
}  // namespace odocal::math

namespace odocal::math {
namespace {

TEST(BoundedTrig, DoubleMatchesLibmToAFewRoundings) {
  // Double epsilon is 2.2e-16; reduction plus Horner evaluation: a few roundings of a unit value.
  constexpr double tolerance = 8.0 * 2.2e-16;
  double worst = 0.0;
  for (int i = -400000; i <= 400000; ++i) {
    const double x = i * 2.5e-5;  // [-10, 10] rad: the UMBmark square's turns and their errors
    const SinCosOf<double> sc = sin_cos(x);
    worst = std::fmax(worst, std::fabs(sc.sin - std::sin(x)));
    worst = std::fmax(worst, std::fabs(sc.cos - std::cos(x)));
  }
  EXPECT_LT(worst, tolerance);
  for (double x = 1e-300; x < 0.5; x *= 3.1) {  // relative accuracy of small angles
    EXPECT_NEAR(sin_cos(x).sin, std::sin(x), 4.0 * 1.1e-16 * x) << x;
  }
}

// arctan2's bound: the result is a sum of at most pi and a float atan of magnitude <= pi/2, each
// rounded (half a rounding of pi each, 1.2e-7), plus the series' own roundings on |u| <= 0.4142
// (a few of 0.4, < 1e-7) and its truncation (< 5e-10): 3e-7 rad covers them.
constexpr double kAngleTolerance = 3e-7;

TEST(BoundedTrig, Arctan2MatchesDoubleInEveryQuadrant) {
  double worst = 0.0;
  for (int i = -200000; i <= 200000; ++i) {
    const double angle = i * 1.6e-5;  // [-3.2, 3.2] rad: every octant and the +-pi seam
    for (const double length : {1.0, 1e-20, 3e7}) {
      const auto y = static_cast<float>(length * std::sin(angle));
      const auto x = static_cast<float>(length * std::cos(angle));
      const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x));
      const double got = arctan2(y, x);
      worst = std::fmax(worst, std::fabs(got - exact));
      ASSERT_LE(std::fabs(got), 3.14159275) << y << " " << x;  // float pi at most
    }
  }
  EXPECT_LT(worst, kAngleTolerance);
}

TEST(BoundedTrig, Arctan2AxesAndOrigin) {
  constexpr double pi = 3.14159265358979323846;
  EXPECT_EQ(arctan2(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(arctan2(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(arctan2(0.0f, -1.0f), pi, kAngleTolerance);
  EXPECT_NEAR(arctan2(1.0f, 0.0f), pi / 2, kAngleTolerance);
  EXPECT_NEAR(arctan2(-1.0f, 0.0f), -pi / 2, kAngleTolerance);
  EXPECT_NEAR(arctan2(-1.0f, -1.0f), -3 * pi / 4, kAngleTolerance);
}

TEST(BoundedTrig, ArctanOfSlopesMatchesDouble) {
  // Lateral chord slopes are small (y/x ~ 1e-3..1e-1), yet any finite slope is in the contract.
  double worst = 0.0;
  for (double v = 1e-30; v < 1e30; v *= 1.01) {
    for (const double slope : {v, -v}) {
      const auto f = static_cast<float>(slope);
      worst = std::fmax(worst, std::fabs(arctan(f) - std::atan(static_cast<double>(f))));
    }
  }
  EXPECT_LT(worst, kAngleTolerance);
  // Small slopes keep their relative accuracy (atan v ~ v).
  for (float v = 1e-30f; v < 1e-2f; v *= 1.9f) {
    EXPECT_NEAR(arctan(v), std::atan(static_cast<double>(v)), 4.0 * 6e-8 * v) << v;
  }
}

}  // namespace
}  // namespace odocal::math
