// The random part of odometry error (Chong & Kleeman's per-wheel model, host_sim/src/fit/
// fit_noise.cpp): its propagation along a path against closed forms, the 95 % end-point ellipse
// against many simulated runs (several robots and slip levels, tolerance from the binomial
// scatter), the estimate beside `odocal fit` against the simulator's slip, and the ROS 2
// covariances.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

/// χ² with 2 degrees of freedom: P(d² <= 5.991) = 0.95.
constexpr double chi2_2dof_95 = 5.991464547107979;

/// A straight log: both wheels roll `length_mm`, counts every `step` counts.
TickLog straight_log(double length_mm, double diameter_mm, double counts_per_rev) {
  TickLog log;
  const double counts = length_mm / (3.14159265358979323846 * diameter_mm) * counts_per_rev;
  const int steps = 1000;
  for (int i = 0; i <= steps; ++i) {
    TickRow row;
    row.t_s = i * 0.01;
    row.count_l = counts * i / steps;
    row.count_r = counts * i / steps;
    log.rows.push_back(row);
  }
  return log;
}

TEST(OdometryNoise, StraightLineCovarianceHasTheClosedForm) {
  // Along the line each wheel's error moves the end by half of it: var = k·d/4. The heading is a
  // random walk of rate k/b² per mm, and its integral over the line gives the lateral variance
  // k·d³/(3b²).
  const double d = 2000.0, b = 150.0, k = 0.01;
  const TickLog log = straight_log(d, 60.0, 1440.0);
  const FitNominal nominal{60.0, b, 1440.0};
  const FitGeometry geometry{60.0, 60.0, b};
  const EndSensitivity s = end_sensitivity(log, 0, log.rows.size() - 1, nominal, geometry);
  EXPECT_NEAR(s.end[0], d, 1e-6);
  for (const Eigen::Matrix3d* a : {&s.left, &s.right}) {
    const Eigen::Matrix3d cov = k * *a;
    EXPECT_NEAR(cov(0, 0), k * d / 4.0, 1e-9 * d);
    EXPECT_NEAR(cov(1, 1), k * d * d * d / (3.0 * b * b), 2e-3 * k * d * d * d / (3.0 * b * b));
    EXPECT_NEAR(cov(2, 2), k * d / (b * b), 1e-9);
  }
  // Either wheel's error turns the robot and swings it sideways the same way (lateral and heading
  // errors correlate alike), but a longer left wheel turns it right, a longer right one left
  // (along-track and heading errors correlate with opposite signs).
  EXPECT_GT(s.left(1, 2) * s.right(1, 2), 0.0);
  EXPECT_LT(s.left(0, 2) * s.right(0, 2), 0.0);
  const Eigen::Matrix3d both = end_covariance(s, WheelNoise{k, k});
  EXPECT_NEAR(both(1, 1), 2.0 * k * d * d * d / (3.0 * b * b), 4e-3 * k * d * d * d / (b * b));
}

/// A robot whose firmware knows its true geometry, so that what remains is random.
RobotSpec told_the_truth(RobotSpec spec) {
  const double d_l = spec.truth.left_diameter_m * 1e3;
  const double d_r = spec.truth.right_diameter_m * 1e3;
  const double d = 0.5 * (d_l + d_r);
  spec.nominal.wheel_diameter_mm = static_cast<float>(d);
  spec.nominal.c_l = static_cast<float>(d_l / d);
  spec.nominal.c_r = static_cast<float>(d_r / d);
  spec.nominal.wheelbase_mm = static_cast<float>(spec.truth.wheelbase_m * 1e3);
  spec.nominal.counts_per_rev = static_cast<float>(spec.truth.counts_per_rev);
  return spec;
}

RobotSpec robot_of(double diameter_mm, double wheelbase_mm, double slip_sigma) {
  RobotSpec spec = default_robot();
  spec.truth.left_diameter_m = diameter_mm * 0.999e-3;
  spec.truth.right_diameter_m = diameter_mm * 1.001e-3;
  spec.truth.wheelbase_m = wheelbase_mm * 1e-3;
  spec.truth.slip_sigma = slip_sigma;
  return told_the_truth(spec);
}

/// The simulator's slip as the per-wheel model sees it: the slip ratio, N(0, σ²), holds for
/// `slip_length` of travel, so a wheel's travel error over s is a sum of s/L independent terms of
/// variance σ²L²: k = σ²·L.
double true_k_mm(const RobotSpec& spec) {
  return spec.truth.slip_sigma * spec.truth.slip_sigma * spec.truth.slip_length_m * 1e3;
}

struct Coverage {
  int inside = 0;
  int runs = 0;
};

/// Drives `runs` paths (1 m squares, alternately cw and ccw, and the unseen path) and counts the
/// true end points inside the 95 % ellipse the model predicts around the odometry's end, with
/// wheel noise `noise` (the ellipse of each run from its own logged counts).
Coverage coverage(const RobotSpec& spec, std::uint64_t seed, int runs, const WheelNoise& noise) {
  SimulatedRobot robot(spec, seed);
  EXPECT_TRUE(robot.configure(spec.nominal));
  const FitNominal nominal{static_cast<double>(spec.nominal.wheel_diameter_mm),
                           static_cast<double>(spec.nominal.wheelbase_mm),
                           static_cast<double>(spec.nominal.counts_per_rev)};
  const FitGeometry geometry{spec.truth.left_diameter_m * 1e3, spec.truth.right_diameter_m * 1e3,
                             spec.truth.wheelbase_m * 1e3};
  Coverage c;
  for (int i = 0; i < runs; ++i) {
    const drive::Path path =
        i % 3 == 2 ? drive::make_unseen_path() : drive::make_umbmark_square(i % 3 == 0, 1.0f);
    TickLog log;
    const RunOutcome out = run_path_logged(robot, path, log);
    EXPECT_TRUE(out.completed);
    const EndSensitivity s = end_sensitivity(log, 0, log.rows.size() - 1, nominal, geometry);
    const Eigen::Matrix2d cov = end_covariance(s, noise).topLeftCorner<2, 2>();
    const Eigen::Vector2d e((out.truth.x_m - static_cast<double>(out.odometry.x_m)) * 1e3,
                            (out.truth.y_m - static_cast<double>(out.odometry.y_m)) * 1e3);
    // A zero-size ellipse (no noise) holds no real end point.
    const Eigen::LLT<Eigen::Matrix2d> llt(cov);
    const bool positive = llt.info() == Eigen::Success && cov.determinant() > 0.0;
    c.inside += positive && e.dot(llt.solve(e)) <= chi2_2dof_95 ? 1 : 0;
    ++c.runs;
  }
  return c;
}

/// Binomial scatter of the number inside: 3 standard deviations of Binomial(n, 0.95).
double tolerance_runs(int n) {
  return 3.0 * std::sqrt(n * 0.95 * 0.05);
}

TEST(OdometryNoise, NinetyFivePercentEllipseHoldsNinetyFivePercentOfSimulatedEndPoints) {
  struct Case {
    double diameter_mm, wheelbase_mm, slip;
  };
  const Case cases[] = {{60.0, 151.5, 0.002},
                        {60.0, 151.5, 0.01},
                        {40.0, 100.0, 0.005},
                        {100.0, 300.0, 0.003},
                        {100.0, 300.0, 0.02}};
  int inside = 0;
  int total = 0;
  for (const Case& k : cases) {
    const RobotSpec spec = robot_of(k.diameter_mm, k.wheelbase_mm, k.slip);
    const double kk = true_k_mm(spec);
    const Coverage c = coverage(spec, 17u, 240, WheelNoise{kk, kk});
    std::printf("D %.0f mm, b %.0f mm, slip %.3f (k %.3g mm^2/mm): %d of %d inside\n",
                k.diameter_mm, k.wheelbase_mm, k.slip, kk, c.inside, c.runs);
    EXPECT_NEAR(c.inside, 0.95 * c.runs, tolerance_runs(c.runs))
        << "D " << k.diameter_mm << " b " << k.wheelbase_mm << " slip " << k.slip;
    inside += c.inside;
    total += c.runs;
  }
  EXPECT_NEAR(inside, 0.95 * total, tolerance_runs(total));
}

/// Tape-measure logs (end only, with the robot's measurement noise) of lines and squares.
std::vector<TickLog> training_logs(const RobotSpec& spec, std::uint64_t seed, int count) {
  SimulatedRobot robot(spec, seed);
  EXPECT_TRUE(robot.configure(spec.nominal));
  std::vector<TickLog> logs;
  for (int i = 0; i < count; ++i) {
    const drive::Path path =
        i % 4 == 3 ? drive::make_line(2.0f) : drive::make_umbmark_square(i % 2 == 0, 2.0f);
    TickLog log;
    EXPECT_TRUE(run_path_logged(robot, path, log, LogTruth::end_only, 20u).completed);
    logs.push_back(std::move(log));
  }
  return logs;
}

TEST(OdometryNoise, EstimateBesideTheFitBracketsTheSimulatorsSlipAndItsEllipseHolds) {
  for (const double slip : {0.005, 0.015}) {
    RobotSpec spec = default_robot();
    spec.truth.slip_sigma = slip;
    // The geometry as `odocal fit` finds it, then the noise from the same runs' residuals.
    const std::vector<TickLog> logs = training_logs(spec, 23u, 40);
    const FitNominal nominal{static_cast<double>(spec.nominal.wheel_diameter_mm),
                             static_cast<double>(spec.nominal.wheelbase_mm),
                             static_cast<double>(spec.nominal.counts_per_rev)};
    FitOptions fit_options;
    fit_options.replicates = 0;
    // With this much slip the runs fix the scale to a few per cent only; the point estimate is
    // what the noise is measured about.
    fit_options.max_relative_sd = 0.1;
    const FitOutcome fit = fit_geometry(logs, nominal, fit_options);
    ASSERT_TRUE(fit) << fit.error.message;
    NoiseOptions options;
    options.level = 0.99;
    const NoiseEstimate e = estimate_wheel_noise(logs, nominal, fit.result->geometry, options);
    ASSERT_TRUE(e.ok) << e.error;
    ASSERT_TRUE(e.has_ci);
    const double k = true_k_mm(spec);
    // Each wheel's interval holds the truth; the sum, better determined, within its intervals'.
    EXPECT_LE(e.ci_k_l.lo, k) << slip;
    EXPECT_GE(e.ci_k_l.hi, k) << slip;
    EXPECT_LE(e.ci_k_r.lo, k) << slip;
    EXPECT_GE(e.ci_k_r.hi, k) << slip;
    // The measurement noise the simulator adds (2 mm) within its interval.
    EXPECT_LE(e.ci_measure_sigma_mm.lo, 2.0) << slip;
    EXPECT_GE(e.ci_measure_sigma_mm.hi, 2.0) << slip;

    // The ellipse from the interval's ends brackets the 95 % of fresh runs (robot told the truth:
    // the coverage tests the random part alone), within the binomial scatter.
    const RobotSpec truth = told_the_truth(spec);
    const double k_lo = 0.5 * (e.ci_k_l.lo + e.ci_k_r.lo);
    const double k_hi = 0.5 * (e.ci_k_l.hi + e.ci_k_r.hi);
    const Coverage low = coverage(truth, 29u, 150, WheelNoise{k_lo, k_lo});
    const Coverage high = coverage(truth, 29u, 150, WheelNoise{k_hi, k_hi});
    std::printf(
        "slip %.3f: true k %.3g; k_l %.3g [%.3g, %.3g], k_r %.3g [%.3g, %.3g], sigma_m %.2f "
        "mm; ellipse at the interval's ends holds %d and %d of %d\n",
        slip, k, e.noise.k_l, e.ci_k_l.lo, e.ci_k_l.hi, e.noise.k_r, e.ci_k_r.lo, e.ci_k_r.hi,
        e.measure_sigma_mm, low.inside, high.inside, high.runs);
    EXPECT_LE(low.inside, 0.95 * low.runs + tolerance_runs(low.runs)) << slip;
    EXPECT_GE(high.inside, 0.95 * high.runs - tolerance_runs(high.runs)) << slip;
  }
}

TEST(OdometryNoise, RosPoseCovariancesFollowTheModel) {
  const WheelNoise noise{0.004, 0.006};  // mm²/mm = 1e-3 m²/m
  const Ros2Covariance c = ros2_covariance(noise, 200.0, 0.5, RosVelocityEstimate{}, 2.0);
  const double k = 0.010e-3, b = 0.2;
  EXPECT_NEAR(c.pose[0], k * 2.0 / 4.0, 1e-15);
  EXPECT_NEAR(c.pose[1], k / (b * b) * 8.0 / 3.0, 1e-15);
  EXPECT_NEAR(c.pose[5], k / (b * b) * 2.0, 1e-15);
  for (int i : {2, 3, 4}) {
    EXPECT_EQ(c.pose[i], 1.0e6);
    EXPECT_EQ(c.twist[i], 1.0e6);
  }
}

/// diff_drive_controller's velocity estimate, written from its description (odometry.cpp): at
/// each update every wheel's travel since the last one over the update's period, the body's
/// linear and angular speeds from them, each averaged over the last `window` updates.
class ControllerVelocityEstimate {
 public:
  ControllerVelocityEstimate(double period_s, std::size_t window, double separation_m)
      : period_s_(period_s), window_(window), separation_m_(separation_m) {}
  /// One update with the wheels' positions (m along the floor) now.
  void update(double left_m, double right_m) {
    const double left_mps = (left_m - left_old_) / period_s_;
    const double right_mps = (right_m - right_old_) / period_s_;
    left_old_ = left_m;
    right_old_ = right_m;
    push(linear_, 0.5 * (left_mps + right_mps));
    push(angular_, (right_mps - left_mps) / separation_m_);
  }
  [[nodiscard]] double linear() const { return mean(linear_); }
  [[nodiscard]] double angular() const { return mean(angular_); }

 private:
  void push(std::vector<double>& samples, double value) const {
    samples.push_back(value);
    if (samples.size() > window_) {
      samples.erase(samples.begin());
    }
  }
  static double mean(const std::vector<double>& samples) {
    double sum = 0.0;
    for (const double v : samples) {
      sum += v;
    }
    return sum / static_cast<double>(samples.size());
  }
  double period_s_;
  std::size_t window_;
  double separation_m_;
  double left_old_ = 0.0;
  double right_old_ = 0.0;
  std::vector<double> linear_;
  std::vector<double> angular_;
};

TEST(OdometryNoise, RosTwistCovariancesAreThoseOfTheControllersOwnVelocityEstimate) {
  // The per-wheel random walk (each wheel's travel over |s| errs with variance k·|s|) through
  // the controller's estimator, straight at 0.3 m/s, at two update rates and windows; the
  // estimate read once every window (disjoint windows: independent readings). The variance of
  // n readings' sample variance is 2σ⁴/(n−1): 5 standard errors of it.
  const WheelNoise noise{0.004, 0.009};  // mm²/mm
  const double k_l = noise.k_l * 1e-3, k_r = noise.k_r * 1e-3;
  const double wheelbase_mm = 180.0, speed = 0.3;
  for (const RosVelocityEstimate estimate :
       {RosVelocityEstimate{}, RosVelocityEstimate{30.0, 4u}}) {
    const double period = 1.0 / estimate.update_rate_hz;
    ControllerVelocityEstimate controller(period, estimate.window, wheelbase_mm * 1e-3);
    std::mt19937_64 random(11u);
    std::normal_distribution<double> unit(0.0, 1.0);
    const double step = speed * period;  // each wheel's travel per update
    double left = 0.0, right = 0.0;
    const std::size_t n = 20000;
    std::vector<double> linear, angular;
    for (std::size_t update = 1; update <= n * estimate.window + estimate.window; ++update) {
      left += step + std::sqrt(k_l * step) * unit(random);
      right += step + std::sqrt(k_r * step) * unit(random);
      controller.update(left, right);
      if (update > estimate.window && update % estimate.window == 0u) {
        linear.push_back(controller.linear());
        angular.push_back(controller.angular());
      }
    }
    const auto variance = [](const std::vector<double>& x) {
      double mean = 0.0;
      for (const double v : x)
        mean += v;
      mean /= static_cast<double>(x.size());
      double sum = 0.0;
      for (const double v : x)
        sum += (v - mean) * (v - mean);
      return sum / static_cast<double>(x.size() - 1u);
    };
    const Ros2Covariance c = ros2_covariance(noise, wheelbase_mm, speed, estimate, 1.0);
    const double relative = 5.0 * std::sqrt(2.0 / static_cast<double>(linear.size() - 1u));
    EXPECT_NEAR(variance(linear), c.twist[0], relative * c.twist[0]) << estimate.update_rate_hz;
    EXPECT_NEAR(variance(angular), c.twist[5], relative * c.twist[5]) << estimate.update_rate_hz;
    EXPECT_EQ(c.twist[1], c.twist[0]);
  }
}

}  // namespace
}  // namespace odocal::host
