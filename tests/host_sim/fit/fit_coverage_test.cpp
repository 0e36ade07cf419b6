// `odocal fit`: do its 95 % intervals cover the truth 95 % of the time? Many hidden simulated
// robots (varied geometry, slip and measurement noise), each driven through a small tape-measure
// calibration with the real firmware, each fitted with the default interval settings.
//
// ODOCAL_FIT_ROBOTS=N runs N robots instead of the default (docs/results.md reports 300);
// ODOCAL_FIT_FIRST_SEED moves the seeds; ODOCAL_FIT_INTERVAL=student-t|percentile measures the
// other interval methods on the same robots (the default is what `odocal fit` uses);
// ODOCAL_FIT_PATH_TRUTH=1 logs the exact truth along the path (motion capture) instead.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "odocal/calib/random.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

/// A hidden robot drawn from `seed`: diameters within ±0.5 % and the wheelbase within ±2 % of
/// nominal; slip σ 2.5e-4 … 1e-3; measurement σ 1 … 3 mm and 0.2 … 0.6° (smooth floor: bumps
/// add wheel turns the geometry does not explain, so the "true diameter" would not be the
/// effective one).
RobotSpec varied_robot(std::uint64_t seed) {
  calib::Random random(seed);
  const auto between = [&](double lo, double hi) { return lo + (hi - lo) * random.uniform(); };
  RobotSpec spec = default_robot();
  spec.truth.left_diameter_m = 0.060 * between(0.995, 1.005);
  spec.truth.right_diameter_m = 0.060 * between(0.995, 1.005);
  spec.truth.wheelbase_m = 0.150 * between(0.98, 1.02);
  spec.truth.slip_sigma = between(2.5e-4, 1e-3);
  spec.truth.measure_sigma_m = between(0.001, 0.003);
  spec.truth.measure_heading_sigma_rad = between(0.2, 0.6) * 3.14159265358979323846 / 180.0;
  return spec;
}

std::uint64_t env_number(const char* name, std::uint64_t fallback) {
  const char* text = std::getenv(name);
  return text != nullptr ? std::strtoull(text, nullptr, 10) : fallback;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

TEST(FitCoverage, NinetyFivePercentIntervalsCoverTheTruthOfSimulatedRobots) {
  // Each robot: 4 lines of 1.5 m and 2 + 2 squares of 1 m (UMBmark-style, both ways), measured
  // where they stopped: 8 runs, the fewest that determine all three parameters comfortably, where
  // a bootstrap over runs is most likely to be too narrow.
  const std::uint64_t robots = env_number("ODOCAL_FIT_ROBOTS", 300);
  const std::uint64_t first = env_number("ODOCAL_FIT_FIRST_SEED", 1);
  const char* const names[3] = {"wheel_diameter_left_mm", "wheel_diameter_right_mm",
                                "wheelbase_mm"};
  FitIntervalMethod interval = FitOptions{}.interval;
  if (const char* method = std::getenv("ODOCAL_FIT_INTERVAL"); method != nullptr) {
    for (const FitIntervalMethod m :
         {FitIntervalMethod::wild_t, FitIntervalMethod::student_t, FitIntervalMethod::percentile}) {
      interval = std::string(method) == interval_name(m) ? m : interval;
    }
    std::printf("fit coverage: %s intervals\n", interval_name(interval));
  }
  const LogTruth logged =
      env_number("ODOCAL_FIT_PATH_TRUTH", 0) != 0 ? LogTruth::path : LogTruth::end_only;
  // ODOCAL_FIT_DESIGN_CF=1: the recommended procedure (docs/calibration.md section 4) instead,
  // 20 lines, 2 + 2 squares and 4 + 4 turns in place.
  const bool cf = env_number("ODOCAL_FIT_DESIGN_CF", 0) != 0;
  const int lines = cf ? 20 : 4;
  const int spins = cf ? 8 : 0;
  std::uint64_t covered[3] = {0, 0, 0};
  std::vector<double> half_widths[3];
  double width_sum[3] = {0, 0, 0}, error_square_sum[3] = {0, 0, 0}, dof_sum[3] = {0, 0, 0};
  for (std::uint64_t k = first; k < first + robots; ++k) {
    const RobotSpec spec = varied_robot(k);
    SimulatedRobot robot(spec, 1000003u * k);
    std::vector<TickLog> logs;
    for (int i = 0; i < lines + 4 + spins; ++i) {
      drive::Path path;
      if (i < lines) {
        path = drive::make_line(1.5f);
      } else if (i < lines + 4) {
        path = drive::make_umbmark_square(i % 2 == 0, 1.0f);
      } else {  // 5 turns in place, alternately cw and ccw
        const float turns = (i % 2 == 0 ? -5.0f : 5.0f) * 6.2831853f;
        static_cast<void>(path.push(drive::Segment{0.0f, turns}));
      }
      TickLog log;
      log.source = "robot " + std::to_string(k) + " run " + std::to_string(i + 1);
      ASSERT_TRUE(run_path_logged(robot, path, log, logged, 50u).completed);
      logs.push_back(std::move(log));
    }
    FitOptions options;  // the defaults: B = 500, level 0.95
    options.seed = k;
    options.interval = interval;
    const FitOutcome out =
        fit_geometry(logs,
                     FitNominal{spec.nominal.wheel_diameter_mm, spec.nominal.wheelbase_mm,
                                static_cast<double>(spec.nominal.counts_per_rev)},
                     options);
    ASSERT_TRUE(out) << out.error.message;
    const FitResult& r = *out.result;
    const double truth[3] = {spec.truth.left_diameter_m * 1e3, spec.truth.right_diameter_m * 1e3,
                             spec.truth.wheelbase_m * 1e3};
    const double fitted[3] = {r.geometry.wheel_diameter_left_mm, r.geometry.wheel_diameter_right_mm,
                              r.geometry.wheelbase_mm};
    const FitInterval ci[3] = {*r.ci_left_mm, *r.ci_right_mm, *r.ci_wheelbase_mm};
    for (int i = 0; i < 3; ++i) {
      covered[i] += ci[i].lo <= truth[i] && truth[i] <= ci[i].hi ? 1 : 0;
      width_sum[i] += (ci[i].hi - ci[i].lo) / truth[i];
      dof_sum[i] += r.dof[i];
      half_widths[i].push_back(0.5 * (ci[i].hi - ci[i].lo) / truth[i]);
      error_square_sum[i] += std::pow((fitted[i] - truth[i]) / truth[i], 2);
    }
  }
  // Binomial standard error of a coverage estimate from n independent intervals at the nominal
  // 0.95. The three intervals of one robot share its data, so the pooled estimate is judged as
  // if it had only `robots` independent intervals (conservative), each parameter on its own too.
  const double n = static_cast<double>(robots);
  const double se = std::sqrt(0.95 * 0.05 / n);
  std::uint64_t all = 0;
  for (int i = 0; i < 3; ++i) {
    all += covered[i];
    const double coverage = static_cast<double>(covered[i]) / n;
    const double rms = std::sqrt(error_square_sum[i] / n);
    const double mean_half_width = 0.5 * width_sum[i] / n;
    std::printf(
        "fit coverage: %-24s %3llu/%llu = %.3f; mean half-width %.2e, RMS error %.2e, "
        "mean dof %.1f; median half-width %.2e\n",
        names[i], static_cast<unsigned long long>(covered[i]),
        static_cast<unsigned long long>(robots), coverage, mean_half_width, rms, dof_sum[i] / n,
        median(half_widths[i]));
    EXPECT_GE(coverage, 0.95 - 3.0 * se) << names[i];
    // Informative, not covering by being huge: a Student-t interval from few runs is wider than
    // ±1.96 × the true spread by t_dof/1.96 (1.6 for 3 degrees of freedom), not twice.
    EXPECT_LT(mean_half_width, 2.0 * 1.96 * rms) << names[i];
  }
  const double pooled = static_cast<double>(all) / (3.0 * n);
  std::printf("fit coverage: pooled %llu/%llu = %.4f (binomial SE %.4f as %llu intervals)\n",
              static_cast<unsigned long long>(all), static_cast<unsigned long long>(3 * robots),
              pooled, std::sqrt(0.95 * 0.05 / (3.0 * n)),
              static_cast<unsigned long long>(3 * robots));
  EXPECT_GE(pooled, 0.95 - 3.0 * se);
  EXPECT_LE(pooled, 0.95 + 3.0 * se);
}

}  // namespace
}  // namespace odocal::host
