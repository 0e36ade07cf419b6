// `odocal fit`'s model choice on robots of our own whose truth we know (issue 22): a robot that
// turns in place with one wheelbase and on arcs with another, and a robot with one wheelbase,
// each driven on squares (turns in place) and circles (arcs) in separate data sets. The logs are
// made here from the kinematics (the simulator's robot has one wheelbase): each row's true motion
// turns with b + w·(b_arc − b), w from that row's wheel travel, each wheel slips a little, and the
// capture adds its scatter.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "odocal/calib/random.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host {
namespace {

constexpr double pi = 3.14159265358979323846;

struct TrueRobot {
  double left_mm = 59.9;
  double right_mm = 60.05;
  double turn_wheelbase_mm = 151.5;  ///< turning in place
  double arc_wheelbase_mm = 151.5;   ///< at arc weight 1
};

FitNominal nominal() {
  FitNominal n;
  n.wheel_diameter_mm = 60.0;
  n.wheelbase_mm = 150.0;
  n.counts_per_rev = 1440.0;
  return n;
}

double normal(calib::Random& random) {
  double sum = 0.0;  // Irwin-Hall: mean 0 after the shift, variance 1
  for (int i = 0; i < 12; ++i) {
    sum += random.uniform();
  }
  return sum - 6.0;
}

/// Drives `travel` (per row of 50 ms: left and right wheel ground travel asked for, mm) with the
/// robot `r` and logs it as a capture system would.
TickLog drive(const TrueRobot& r, const std::vector<std::pair<double, double>>& travel,
              calib::Random& random, const std::string& source) {
  TickLog log;
  log.source = source;
  double x = 0.0, y = 0.0, theta = 0.0, turns_l = 0.0, turns_r = 0.0;
  constexpr double slip_sigma = 0.003;  // per row, each wheel
  constexpr double jitter_mm = 0.3;     // capture scatter
  constexpr double jitter_deg = 0.1;
  const auto record = [&](double t) {
    TickRow row;
    row.t_s = t;
    row.count_l = std::round(turns_l * nominal().counts_per_rev);
    row.count_r = std::round(turns_r * nominal().counts_per_rev);
    row.has_xy = row.has_theta = true;
    row.x_mm = x + jitter_mm * normal(random);
    row.y_mm = y + jitter_mm * normal(random);
    row.theta_deg = theta * 180.0 / pi + jitter_deg * normal(random);
    log.rows.push_back(row);
  };
  record(0.0);
  for (std::size_t i = 0; i < travel.size(); ++i) {
    const double left = travel[i].first, right = travel[i].second;
    turns_l += left / (pi * r.left_mm);
    turns_r += right / (pi * r.right_mm);
    const double ground_l = left * (1.0 + slip_sigma * normal(random));
    const double ground_r = right * (1.0 + slip_sigma * normal(random));
    const double forward = std::fabs(left + right), differential = std::fabs(right - left);
    const double w = forward + differential > 0.0 ? forward / (forward + differential) : 0.0;
    const double b = r.turn_wheelbase_mm + w * (r.arc_wheelbase_mm - r.turn_wheelbase_mm);
    const double turn = (ground_r - ground_l) / b;
    const double half = 0.5 * turn;
    const double chord =
        0.5 * (ground_l + ground_r) * (std::fabs(half) > 1e-9 ? std::sin(half) / half : 1.0);
    x += chord * std::cos(theta + half);
    y += chord * std::sin(theta + half);
    theta += turn;
    record(0.05 * static_cast<double>(i + 1));
  }
  return log;
}

/// A 1 m square at 200 mm/s with turns in place at 1 rad/s, counter-clockwise or clockwise.
std::vector<std::pair<double, double>> square(bool ccw) {
  std::vector<std::pair<double, double>> rows;
  const double half_b = 0.5 * nominal().wheelbase_mm;
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i < 100; ++i) {
      rows.emplace_back(10.0, 10.0);
    }
    const double step = half_b * 0.05;  // 1 rad/s
    const int n = static_cast<int>(std::round(0.5 * pi / 0.05));
    for (int i = 0; i < n; ++i) {
      rows.emplace_back(ccw ? -step : step, ccw ? step : -step);
    }
  }
  return rows;
}

/// Two laps of a circle of radius `radius_mm` at 150 mm/s.
std::vector<std::pair<double, double>> circle(double radius_mm, bool ccw) {
  std::vector<std::pair<double, double>> rows;
  const double half_b = 0.5 * nominal().wheelbase_mm;
  const double v = 150.0 * 0.05;
  const double omega = v / radius_mm;
  const int n = static_cast<int>(std::round(4.0 * pi / omega));
  for (int i = 0; i < n; ++i) {
    const double outer = v + omega * half_b, inner = v - omega * half_b;
    rows.emplace_back(ccw ? inner : outer, ccw ? outer : inner);
  }
  return rows;
}

struct Set {
  bool square = false;
  std::vector<TickLog> runs;
};

/// Three square sets and three circle sets (radii 250, 375 and 500 mm) of four runs each.
std::vector<Set> data_sets(const TrueRobot& r, std::uint64_t seed) {
  calib::Random random(seed);
  std::vector<Set> sets;
  const double radii[3] = {250.0, 375.0, 500.0};
  for (int s = 0; s < 6; ++s) {
    Set set;
    set.square = s < 3;
    const std::string folder = (set.square ? "square-" : "circle-") + std::to_string(s);
    for (int k = 0; k < 4; ++k) {
      const bool ccw = k % 2 == 1;
      set.runs.push_back(drive(r, set.square ? square(ccw) : circle(radii[s - 3], ccw), random,
                               folder + "/run-" + std::to_string(k) + ".csv"));
    }
    sets.push_back(std::move(set));
  }
  return sets;
}

FitOptions point_only(std::optional<FitModelKind> model) {
  FitOptions o;
  o.replicates = 0;
  o.estimate_lag = false;
  o.model = model;
  return o;
}

double heldout(const std::vector<TickLog>& train, std::optional<FitModelKind> model,
               const std::vector<TickLog>& held) {
  const FitOutcome out = fit_geometry(train, nominal(), point_only(model), held);
  EXPECT_TRUE(out) << out.error.message;
  return out ? out.result->holdout->path_rms_after_mm : 0.0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Leave one set out: held-out path RMS of the mixed fit over that of the own-kind fit.
void leave_one_set_out(const std::vector<Set>& sets, std::optional<FitModelKind> mixed_model,
                       std::vector<double>& ratios) {
  for (std::size_t s = 0; s < sets.size(); ++s) {
    std::vector<TickLog> own, mixed;
    for (std::size_t i = 0; i < sets.size(); ++i) {
      if (i == s) {
        continue;
      }
      mixed.insert(mixed.end(), sets[i].runs.begin(), sets[i].runs.end());
      if (sets[i].square == sets[s].square) {
        own.insert(own.end(), sets[i].runs.begin(), sets[i].runs.end());
      }
    }
    ratios.push_back(heldout(mixed, mixed_model, sets[s].runs) /
                     heldout(own, std::nullopt, sets[s].runs));
  }
}

TEST(FitTwoWheelbases, ARobotThatTurnsWiderOnArcsIsDescribedWhateverItDrove) {
  TrueRobot r;
  r.arc_wheelbase_mm = r.turn_wheelbase_mm * 1.008;  // the June robot's 0.8 % (1.5 of 200 mm)
  const std::vector<Set> sets = data_sets(r, 22);
  std::vector<TickLog> all;
  for (const Set& s : sets) {
    all.insert(all.end(), s.runs.begin(), s.runs.end());
  }
  const FitOutcome out = fit_geometry(all, nominal(), point_only(std::nullopt));
  ASSERT_TRUE(out) << out.error.message;
  EXPECT_EQ(out.result->model.kind, FitModelKind::arc_wheelbase) << out.result->model.reason;
  // Slip of 0.3 % per row averages over thousands of rows: the wheelbases come out within 0.1 %.
  EXPECT_NEAR(out.result->geometry.wheelbase_mm / r.turn_wheelbase_mm, 1.0, 1e-3);
  EXPECT_NEAR(out.result->geometry.second_wheelbase_mm / r.arc_wheelbase_mm, 1.0, 1e-3);

  std::vector<double> one, chosen;
  leave_one_set_out(sets, FitModelKind::one_wheelbase, one);
  leave_one_set_out(sets, std::nullopt, chosen);
  std::printf("two wheelbases: median one/own %.3f worst %.3f; chosen/own %.3f worst %.3f\n",
              median(one), *std::max_element(one.begin(), one.end()), median(chosen),
              *std::max_element(chosen.begin(), chosen.end()));
  EXPECT_LE(median(chosen), 1.03);
  EXPECT_LE(*std::max_element(chosen.begin(), chosen.end()), 1.15);
  EXPECT_GT(median(one), median(chosen));
}

TEST(FitTwoWheelbases, ARobotWithOneWheelbaseKeepsOne) {
  const TrueRobot r;
  const std::vector<Set> sets = data_sets(r, 23);
  std::vector<TickLog> all;
  for (const Set& s : sets) {
    all.insert(all.end(), s.runs.begin(), s.runs.end());
  }
  const FitOutcome out = fit_geometry(all, nominal(), point_only(std::nullopt));
  ASSERT_TRUE(out) << out.error.message;
  EXPECT_EQ(out.result->model.kind, FitModelKind::one_wheelbase) << out.result->model.reason;
  EXPECT_NEAR(out.result->geometry.wheelbase_mm / r.turn_wheelbase_mm, 1.0, 1e-3);
  // The rule then changes nothing: leaving one set out, the mixed fit is the one-wheelbase fit.
  // (Its ratio to the own-kind fit is noise here: 0.95-1.07 over seeds 23-30 with 6 sets.)
  std::vector<double> one, chosen;
  leave_one_set_out(sets, FitModelKind::one_wheelbase, one);
  leave_one_set_out(sets, std::nullopt, chosen);
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_NEAR(chosen[i], one[i], 1e-9 * one[i]) << "set " << i;
  }
  std::printf("one wheelbase: median chosen/own %.3f worst %.3f\n", median(chosen),
              *std::max_element(chosen.begin(), chosen.end()));
}

TEST(FitTwoWheelbases, ALagBetweenCountsAndTruthIsEstimated) {
  const TrueRobot r;
  const std::vector<Set> sets = data_sets(r, 31);
  std::vector<TickLog> aligned, late;
  for (const Set& s : sets) {
    for (const TickLog& log : s.runs) {
      aligned.push_back(log);
      // The counts stamped one 50 ms row late: the row at t holds what was counted at t − 50 ms.
      TickLog shifted = log;
      for (std::size_t i = shifted.rows.size() - 1; i > 0; --i) {
        shifted.rows[i].count_l = log.rows[i - 1].count_l;
        shifted.rows[i].count_r = log.rows[i - 1].count_r;
      }
      late.push_back(shifted);
    }
  }
  FitOptions o = point_only(FitModelKind::one_wheelbase);
  o.estimate_lag = true;
  const FitOutcome a = fit_geometry(aligned, nominal(), o);
  const FitOutcome b = fit_geometry(late, nominal(), o);
  ASSERT_TRUE(a && b);
  ASSERT_TRUE(a.result->lag && b.result->lag);
  std::printf(
      "lag: aligned %+.4f s, late %+.4f s; D_L %.4f -> %.4f (at estimate %.4f), %+.4f mm "
      "per 50 ms\n",
      a.result->lag->estimate_s, b.result->lag->estimate_s,
      a.result->geometry.wheel_diameter_left_mm, b.result->geometry.wheel_diameter_left_mm,
      b.result->lag->geometry_at_estimate[0], b.result->lag->per_50ms[0]);
  // A row is 50 ms; the parabola through the costs at ±50 ms finds the lag to a fifth of that.
  EXPECT_NEAR(a.result->lag->estimate_s, 0.0, 0.01);
  EXPECT_NEAR(b.result->lag->estimate_s, 0.05, 0.01);
  // Refitted at the estimate, the late logs give what the aligned ones give (within 0.02 %, a
  // fifth of the 0.1 % per 50 ms the issue measured).
  for (int i = 0; i < 3; ++i) {
    const double aligned_value = i == 0   ? a.result->geometry.wheel_diameter_left_mm
                                 : i == 1 ? a.result->geometry.wheel_diameter_right_mm
                                          : a.result->geometry.wheelbase_mm;
    EXPECT_NEAR(b.result->lag->geometry_at_estimate[i] / aligned_value, 1.0, 2e-4) << i;
  }
}

}  // namespace
}  // namespace odocal::host
