// auto's planning: what the target likely takes before any run, and the runs the fitted geometry
// cannot explain as it explains the others (a heading typed with the wrong sign, a reading 2 m
// off), on tick logs of a robot of known geometry.
#include "auto_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../fit/synthetic_logs.hpp"

namespace odocal::host::session::auto_plan {
namespace {

namespace syn = odocal::host::synthetic;

/// Six turns in place end 37.3 degrees short of six turns (what the tape shows).
constexpr double leftover = 37.3 * syn::pi / 180.0;

/// Twelve runs of the auto kinds (lines of 2 m, six turns in place each way, arcs each way),
/// measured at the end with a tape's scatter (a fixed pattern within 2 mm and 0.4 degree).
std::vector<TickLog> runs(const syn::Truth& t) {
  std::vector<std::vector<syn::Move>> kinds = {
      {syn::line(2000.0)},           {syn::turn(12.0 * syn::pi - leftover, t)},
      {syn::arc(1885.0, 400.0, t)},  {syn::turn(-12.0 * syn::pi + leftover, t)},
      {syn::arc(1885.0, -400.0, t)},
  };
  std::vector<TickLog> logs;
  for (int i = 0; i < 12; ++i) {
    TickLog log = syn::make_log(t, kinds[static_cast<std::size_t>(i) % kinds.size()],
                                syn::Truthing::end_only);
    TickRow& end = log.rows.back();
    end.x_mm += 1.5 * std::sin(1.7 * i);
    end.y_mm += 1.5 * std::cos(2.3 * i);
    end.theta_deg += 0.3 * std::sin(0.9 * i);
    logs.push_back(log);
  }
  return logs;
}

FitGeometry geometry_of(const syn::Truth& t) {
  FitGeometry g;
  g.wheel_diameter_left_mm = t.left_mm;
  g.wheel_diameter_right_mm = t.right_mm;
  g.wheelbase_mm = t.wheelbase_mm;
  return g;
}

TEST(AutoPlan, RunsThatAgreeAreNotSuspect) {
  const syn::Truth t;
  EXPECT_TRUE(suspect_runs(runs(t), FitNominal{}, geometry_of(t)).empty());
}

TEST(AutoPlan, AHeadingTypedWithTheWrongSignIsSuspect) {
  const syn::Truth t;
  std::vector<TickLog> logs = runs(t);
  // Run 2 (index 1) turned six times counter-clockwise and ended at -37.3 degrees; the heading is
  // typed +37.3.
  TickRow& end = logs[1].rows.back();
  ASSERT_NEAR(std::remainder(end.theta_deg, 360.0), -37.3, 0.5);
  end.theta_deg = -std::remainder(end.theta_deg, 360.0);
  const std::vector<SuspectRun> s = suspect_runs(logs, FitNominal{}, geometry_of(t));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].index, 1u);
  EXPECT_NEAR(std::fabs(s[0].heading_deg), 74.6, 1.0);
}

TEST(AutoPlan, AReadingTwoMetresOffIsSuspect) {
  const syn::Truth t;
  std::vector<TickLog> logs = runs(t);
  logs[5].rows.back().x_mm += 2000.0;  // the second line
  const std::vector<SuspectRun> s = suspect_runs(logs, FitNominal{}, geometry_of(t));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].index, 5u);
  EXPECT_NEAR(s[0].position_mm, 2000.0, 5.0);
  // What the others miss by: the tape's pattern, a couple of millimetres.
  EXPECT_LT(s[0].typical_mm, 3.0 * kMeasureSigmaMm);
}

TEST(AutoPlan, TheTargetLikelyTakesMoreRunsTheTighterItIs) {
  Plan plan;
  FitNominal nominal;
  const Expectation loose = expected_before_runs(plan, nominal, 20.0, 6, 200);
  const Expectation tight = expected_before_runs(plan, nominal, 2.0, 6, 200);
  EXPECT_TRUE(loose.reached);
  EXPECT_LE(loose.runs, tight.runs);
  EXPECT_GE(loose.runs, 6u);  // the first round always
  // With room for the first round only, a tight target is not reached and says what it leaves.
  const Expectation capped = expected_before_runs(plan, nominal, 0.5, 6, 6);
  EXPECT_FALSE(capped.reached);
  EXPECT_EQ(capped.runs, 6u);
  EXPECT_GT(capped.sigma_sys_mm, 0.5);
  // The precision falls about as 1/sqrt(runs): twice the runs, about 1/sqrt(2) of it.
  const Expectation more = expected_before_runs(plan, nominal, 0.0, 6, 24);
  const Expectation fewer = expected_before_runs(plan, nominal, 0.0, 6, 12);
  EXPECT_NEAR(more.sigma_sys_mm / fewer.sigma_sys_mm, 1.0 / std::sqrt(2.0), 0.15);
}

// The target's stop bound: a variance estimated from v degrees of freedom is below the true one
// by the chi-square law; the bound is sqrt(v / chi2_0.16(v)). For even v that law's CDF has a
// closed form, 1 - exp(-x/2) sum_{k < v/2} (x/2)^k / k!, solved here by bisection: the
// Wilson-Hilferty approximation the session uses is within 1.5 % of it from 2 degrees of freedom,
// and the bound shrinks towards 1 as the runs add degrees of freedom.
TEST(AutoPlan, TheStopBoundIsTheChiSquareBoundOfTheRunsDegreesOfFreedom) {
  const auto cdf = [](double x, int v) {
    double term = 1.0, sum = 0.0;
    for (int k = 0; k < v / 2; ++k) {
      sum += term;
      term *= 0.5 * x / (k + 1);
    }
    return 1.0 - std::exp(-0.5 * x) * sum;
  };
  const double one_sigma_below = 0.158655254;
  for (const int v : {2, 4, 6, 10, 20, 40}) {
    double lo = 0.0, hi = 10.0 * v;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (cdf(mid, v) < one_sigma_below ? lo : hi) = mid;
    }
    const double exact = std::sqrt(v / lo);
    EXPECT_NEAR(stop_factor_for(v), exact, 0.015 * exact) << v << " degrees of freedom";
    EXPECT_GT(stop_factor_for(v), stop_factor_for(v + 1.0));
  }
  EXPECT_GT(stop_factor_for(1e6), 1.0);
  EXPECT_LT(stop_factor_for(1e6), 1.002);
  // No estimate of the runs' scatter: nothing to widen; too few degrees of freedom: no bound.
  EXPECT_EQ(stop_factor_for(0.0), 1.0);
  EXPECT_FALSE(std::isfinite(stop_factor_for(0.3)));
}

}  // namespace
}  // namespace odocal::host::session::auto_plan
