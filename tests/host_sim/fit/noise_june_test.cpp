// The per-wheel noise model on real runs (OptiOdom, June 2020: one robot, squares and circles,
// each data set repeating one path; tests/data/optiodom-june, MIT licence): geometry and noise
// fitted on the other sets of the same path kind, the 95 % ellipse predicted for each run of the
// set left out, and the share of real end points inside.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"

namespace odocal::host {
namespace {

namespace fs = std::filesystem;

constexpr double chi2_2dof_95 = 5.991464547107979;

fs::path june_dir() {
  const char* source = std::getenv("ODOCAL_SOURCE_DIR");
  return fs::path(source != nullptr ? source : ".") / "tests" / "data" / "optiodom-june";
}

struct DataSet {
  std::string name;
  std::vector<TickLog> runs;
};

std::vector<DataSet> sets_of(const std::string& kind) {
  std::vector<DataSet> sets;
  std::vector<fs::path> dirs;
  for (const auto& entry : fs::directory_iterator(june_dir())) {
    if (entry.is_directory() && entry.path().filename().string().rfind(kind + "-", 0) == 0) {
      dirs.push_back(entry.path());
    }
  }
  std::sort(dirs.begin(), dirs.end());
  for (const fs::path& dir : dirs) {
    DataSet set;
    set.name = dir.filename().string();
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() == ".csv")
        files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files)
      set.runs.push_back(read_tick_log(file.string()));
    sets.push_back(std::move(set));
  }
  return sets;
}

struct Count {
  int inside = 0;
  int runs = 0;
};

/// Leave one set out: fit geometry and noise on the others, predict each held-out run's end.
Count held_out_coverage(const std::vector<DataSet>& sets) {
  const FitNominal nominal{84.0, 200.0, 2796.8};
  Count c;
  for (std::size_t out = 0; out < sets.size(); ++out) {
    std::vector<TickLog> training;
    for (std::size_t i = 0; i < sets.size(); ++i) {
      if (i != out)
        training.insert(training.end(), sets[i].runs.begin(), sets[i].runs.end());
    }
    FitOptions fit_options;
    fit_options.replicates = 0;
    const FitOutcome fit = fit_geometry(training, nominal, fit_options);
    EXPECT_TRUE(fit) << fit.error.message;
    if (!fit)
      continue;
    NoiseOptions options;
    options.replicates = 0;
    options.heading_length_mm = fit.result->heading_length_mm;
    const NoiseEstimate noise =
        estimate_wheel_noise(training, nominal, fit.result->geometry, options);
    EXPECT_TRUE(noise.ok) << noise.error;
    const double v = noise.measure_sigma_mm * noise.measure_sigma_mm;
    for (const TickLog& run : sets[out].runs) {
      std::size_t last = run.rows.size() - 1;
      while (last > 0 && !run.rows[last].has_xy)
        --last;
      const EndSensitivity s = end_sensitivity(run, 0, last, nominal, fit.result->geometry);
      // The measured start and end each add the measurement noise (the start's heading noise
      // swings the whole run about it).
      Eigen::Matrix2d cov = end_covariance(s, noise.noise).topLeftCorner<2, 2>();
      const double h2 = 1.0 / (options.heading_length_mm * options.heading_length_mm);
      const Eigen::Vector2d arm(-(s.end[1] - s.start[1]), s.end[0] - s.start[0]);
      cov += v * (2.0 * Eigen::Matrix2d::Identity() + h2 * arm * arm.transpose());
      const Eigen::Vector2d e(s.end[0] - run.rows[last].x_mm, s.end[1] - run.rows[last].y_mm);
      c.inside += e.dot(cov.ldlt().solve(e)) <= chi2_2dof_95 ? 1 : 0;
      ++c.runs;
    }
  }
  return c;
}

TEST(OdometryNoiseJune, HeldOutEllipsesHoldAboutNinetyFivePercentOfRealEndPoints) {
  if (!fs::exists(june_dir())) {
    FAIL() << june_dir() << " missing";
  }
  int inside = 0, runs = 0;
  for (const char* kind : {"square", "circle"}) {
    const Count c = held_out_coverage(sets_of(kind));
    std::printf("%s: %d of %d held-out end points inside their 95 %% ellipse\n", kind, c.inside,
                c.runs);
    inside += c.inside;
    runs += c.runs;
  }
  ASSERT_GT(runs, 40);
  // 3 standard deviations of Binomial(n, 0.95).
  EXPECT_NEAR(inside, 0.95 * runs, 3.0 * std::sqrt(runs * 0.95 * 0.05));
}

}  // namespace
}  // namespace odocal::host
