// `odocal fit` refuses only what the runs' design cannot determine (issue 32): large scatter at
// the ends gives an estimate with wide intervals and a warning, each refusal names the cause the
// design holds, and the position and heading noise are estimated apart where enough runs tell.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "odocal/calib/random.hpp"
#include "odocal/host/fit.hpp"
#include "synthetic_logs.hpp"

namespace odocal::host {
namespace {

using synthetic::arc;
using synthetic::line;
using synthetic::make_log;
using synthetic::Move;
using synthetic::pi;
using synthetic::square;
using synthetic::Truth;
using synthetic::Truthing;
using synthetic::turn;

/// Standard normal deviates (Box-Muller) from the project's generator.
class Normal {
 public:
  explicit Normal(std::uint64_t seed) : random_(seed) {}
  double operator()() {
    const double u1 = 1.0 - random_.uniform();  // (0, 1]
    const double u2 = random_.uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * pi * u2);
  }

 private:
  calib::Random random_;
};

/// Moves the last row's ground truth by independent normal errors: a measurement of the end.
void disturb_end(TickLog& log, Normal& normal, double sd_mm, double sd_deg) {
  TickRow& end = log.rows.back();
  end.x_mm += sd_mm * normal();
  end.y_mm += sd_mm * normal();
  end.theta_deg += sd_deg * normal();
}

bool says(const std::string& text, const char* word) {
  return text.find(word) != std::string::npos;
}

// ------------------------------------------------------------- large scatter: a warning

/// A mid-size robot as in the issue: 100,000 counts per wheel turn, 150 mm wheels, 450 mm apart
/// nominally (the truth a little off, as built).
Truth mid_size_robot() {
  Truth t;
  t.left_mm = 151.2;
  t.right_mm = 151.6;
  t.wheelbase_mm = 480.0;
  t.counts_per_rev = 100000.0;
  return t;
}

constexpr FitNominal kMidNominal{150.0, 450.0, 100000.0};

/// Four open 6 m arcs of different radii, each measured at its start and its end.
std::vector<TickLog> open_arcs(const Truth& t) {
  std::vector<TickLog> logs;
  const double radii_mm[4] = {2500.0, -3000.0, 2000.0, -4000.0};
  for (int i = 0; i < 4; ++i) {
    logs.push_back(make_log(t, {arc(6000.0, radii_mm[i], t)}, Truthing::start_and_end, 1000.0 * i,
                            -500.0 * i, 30.0 * i));
    logs.back().source = "arc " + std::to_string(i + 1);
  }
  return logs;
}

/// The loosest relative standard deviation the scatter leaves (the old refusal's figure), from
/// the result's covariance of the log-parameters.
double loosest_relative_sd(const FitResult& r) {
  Eigen::Matrix3d cov;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      cov(i, j) = r.relative_cov[i][j];
    }
  }
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues().maxCoeff());
}

/// A result given despite the scatter: intervals, and the warning exactly when the scatter
/// leaves a direction looser than the 1 % a refusal would have needed.
void expect_given_with_intervals(const FitOutcome& out, const char* what, std::size_t& warned) {
  ASSERT_TRUE(out) << what << ": " << out.error.message;
  const FitResult& r = *out.result;
  ASSERT_TRUE(r.ci_left_mm && r.ci_right_mm && r.ci_wheelbase_mm) << what;
  EXPECT_LT(r.ci_wheelbase_mm->lo, r.ci_wheelbase_mm->hi) << what;
  const bool loose = loosest_relative_sd(r) > FitOptions{}.max_relative_sd;
  ASSERT_EQ(r.warnings.size(), loose ? 1u : 0u) << what;
  if (loose) {
    ++warned;
    EXPECT_TRUE(says(r.warnings[0], "large scatter")) << r.warnings[0];
    EXPECT_FALSE(says(r.warnings[0], "closed loop")) << r.warnings[0];
    EXPECT_TRUE(says(fit_result_text(r), "Warning: large scatter"));
    EXPECT_EQ(fit_result_json(r).at("warnings").size(), 1u);
  }
}

TEST(FitDesign, OpenArcsWithLargeEndScatterGiveAnEstimateWithIntervalsAndAWarning) {
  const Truth t = mid_size_robot();
  const std::vector<TickLog> clean = open_arcs(t);
  std::vector<TickLog> noisy = clean;
  // 100 mm per axis (141 mm radially) and 1° of heading at each end: the real robot's end
  // residuals were over 100 mm, fifty times the noise floor.
  constexpr double sd_mm = 100.0, sd_deg = 1.0;
  Normal normal(32u);
  for (TickLog& log : noisy) {
    disturb_end(log, normal, sd_mm, sd_deg);
  }
  FitOptions options;
  options.replicates = 200;
  std::size_t warned = 0;
  const FitOutcome out = fit_geometry(noisy, kMidNominal, options);
  expect_given_with_intervals(out, "all four runs", warned);
  const FitResult& r = *out.result;
  // Four runs measured at their ends: too few to estimate the noise apart, the fixed weight.
  EXPECT_FALSE(r.weighting.estimated);
  // A least-squares fit of 12 end coordinates with 3 parameters predicts those ends with an
  // error of about σ·sqrt(3/12) per axis: radially sqrt(2)·σ/2 (RMS over runs). Three times that
  // bounds the fitted geometry's error on the noise-free ends; the nominal geometry is far worse.
  const FitFigures truth_ends = score_runs(clean, kMidNominal, r.geometry, r.heading_length_mm);
  const double expected_mm = std::sqrt(2.0) * sd_mm * std::sqrt(3.0 / 12.0);
  EXPECT_GT(truth_ends.end_rms_before_mm, 3.0 * expected_mm);
  EXPECT_LT(truth_ends.end_rms_after_mm, 3.0 * expected_mm);
  // Leave one run out, as on the real robot: each fold gives a result that predicts the
  // noise-free end of the run it did not see better than the nominal geometry.
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    std::vector<TickLog> train;
    for (std::size_t j = 0; j < noisy.size(); ++j) {
      if (j != i) {
        train.push_back(noisy[j]);
      }
    }
    const FitOutcome fold = fit_geometry(train, kMidNominal, options, {clean[i]});
    expect_given_with_intervals(fold, ("fold " + std::to_string(i)).c_str(), warned);
    if (fold) {
      EXPECT_LT(fold.result->holdout->end_rms_after_mm, fold.result->holdout->end_rms_before_mm)
          << "fold " << i;
    }
  }
  // With this draw the scatter leaves the scale looser than 1 % in two of the four folds, as on
  // the real robot (the old check refused those): the case the warning is for.
  EXPECT_GE(warned, 2u);
}

TEST(FitDesign, TheSameArcsMeasuredAtTheNoiseFloorGiveNoWarning) {
  const Truth t = mid_size_robot();
  std::vector<TickLog> logs = open_arcs(t);
  Normal normal(7u);
  for (TickLog& log : logs) {
    disturb_end(log, normal, 1.0, 0.1);
  }
  FitOptions options;
  options.replicates = 0;
  const FitOutcome out = fit_geometry(logs, kMidNominal, options);
  ASSERT_TRUE(out) << out.error.message;
  EXPECT_TRUE(out.result->warnings.empty()) << out.result->warnings.front();
  EXPECT_TRUE(fit_result_json(*out.result).at("warnings").empty());
}

// ------------------------------------------------------------- refusals name their cause

FitNominal small_nominal() {
  return FitNominal{60.0, 150.0, 1440.0};
}

FitOutcome fit_quietly(const std::vector<TickLog>& logs, std::optional<FitModelKind> model = {}) {
  FitOptions options;
  options.replicates = 0;
  options.model = model;
  return fit_geometry(logs, small_nominal(), options);
}

TEST(FitDesign, ClosedSquaresMeasuredOnlyAtTheEndLeaveTheScaleForClosedLoops) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 6; ++i) {
    logs.push_back(make_log(t, square(t, 2000.0, i % 2 == 0), Truthing::end_only));
  }
  const FitOutcome out = fit_quietly(logs);
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "scale");
  EXPECT_TRUE(says(out.error.message, "closed loops")) << out.error.message;
}

TEST(FitDesign, TurnsInPlaceAloneLeaveTheScaleButAreNotCalledClosedLoops) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 6; ++i) {
    logs.push_back(
        make_log(t, {turn((i % 2 == 0 ? 1.0 : -1.0) * (2.0 + i) * pi, t)}, Truthing::end_only));
  }
  const FitOutcome out = fit_quietly(logs);
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "scale");
  EXPECT_TRUE(says(out.error.message, "turn in place")) << out.error.message;
  EXPECT_FALSE(says(out.error.message, "closed loops")) << out.error.message;
}

TEST(FitDesign, StraightLinesAloneLeaveTheWheelbase) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 6; ++i) {
    logs.push_back(make_log(t, {line(1000.0 + 300.0 * i)}, Truthing::end_only));
  }
  const FitOutcome out = fit_quietly(logs);
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "wheelbase_mm");
  EXPECT_TRUE(says(out.error.message, "hardly turn")) << out.error.message;
}

TEST(FitDesign, ArcsOfOneRadiusLeaveTheWheelDifferenceAgainstTheWheelbase) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 6; ++i) {
    // Every run on the same 1 m arc, of different lengths, measured at start and end.
    logs.push_back(make_log(t, {arc(1500.0 + 400.0 * i, 1000.0, t)}, Truthing::start_and_end));
  }
  const FitOutcome out = fit_quietly(logs);
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "wheelbase_mm");
  EXPECT_TRUE(says(out.error.message, "one curvature")) << out.error.message;
  EXPECT_FALSE(says(out.error.message, "closed loops")) << out.error.message;
}

TEST(FitDesign, TheArcModelWithOneKindOfTurningLeavesTheOtherWheelbase) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 4; ++i) {
    logs.push_back(make_log(t, {line(2000.0)}, Truthing::end_only));
    logs.push_back(make_log(t, {turn((i % 2 == 0 ? 3.0 : -3.0) * pi, t)}, Truthing::end_only));
  }
  // One wheelbase: lines and turns in place determine it.
  ASSERT_TRUE(fit_quietly(logs));
  const FitOutcome out = fit_quietly(logs, FitModelKind::arc_wheelbase);
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "wheelbase_arc_mm");
  EXPECT_TRUE(says(out.error.message, "one kind of turning")) << out.error.message;
}

// ---------------------------------------------- position and heading noise estimated apart

/// `count` tape-measure runs of varied paths (lines, squares both ways, arcs, turns) of the
/// default small robot, each end disturbed by sd_mm per axis and sd_deg.
std::vector<TickLog> tape_runs(int count, double sd_mm, double sd_deg, std::uint64_t seed) {
  const Truth t;
  Normal normal(seed);
  std::vector<TickLog> logs;
  for (int i = 0; i < count; ++i) {
    std::vector<Move> moves;
    switch (i % 4) {
      case 0:
        moves = {line(1500.0 + 20.0 * i)};
        break;
      case 1:
        moves = square(t, 1000.0, i % 8 == 1);
        break;
      case 2:
        moves = {arc(2000.0, (i % 8 == 2 ? 1.0 : -1.0) * 700.0, t)};
        break;
      default:
        moves = {line(800.0), turn(pi / 2, t), line(600.0)};
        break;
    }
    logs.push_back(make_log(t, moves, Truthing::end_only));
    disturb_end(logs.back(), normal, sd_mm, sd_deg);
  }
  return logs;
}

TEST(FitWeighting, EnoughRunsRecoverThePositionAndHeadingNoiseApart) {
  constexpr double sd_mm = 15.0, sd_deg = 1.0;  // 1° ≈ 15 mm × 3.8: the fixed weight's 5 mm
  const std::vector<TickLog> logs = tape_runs(40, sd_mm, sd_deg, 91u);
  FitOptions options;
  options.replicates = 0;
  const FitOutcome out = fit_geometry(logs, small_nominal(), options);
  ASSERT_TRUE(out) << out.error.message;
  const FitWeighting& w = out.result->weighting;
  ASSERT_TRUE(w.estimated) << w.reason;
  EXPECT_EQ(w.runs, 40u);
  // A standard deviation estimated from ν degrees of freedom is off by about 1/sqrt(2ν) of
  // itself (chi-square): four of those is the tolerance.
  ASSERT_GT(w.position_dof, 70.0);
  ASSERT_GT(w.heading_dof, 35.0);
  EXPECT_NEAR(w.position_sd_mm / sd_mm, 1.0, 4.0 / std::sqrt(2.0 * w.position_dof));
  EXPECT_NEAR(w.heading_sd_deg / sd_deg, 1.0, 4.0 / std::sqrt(2.0 * w.heading_dof));
  EXPECT_NEAR(w.heading_length_mm, w.position_sd_mm / (w.heading_sd_deg * pi / 180.0),
              0.01 * w.heading_length_mm);
  EXPECT_DOUBLE_EQ(out.result->heading_length_mm, w.heading_length_mm);
  const nlohmann::json j = fit_result_json(*out.result);
  EXPECT_EQ(j.at("weighting").at("method"), "estimated");
  EXPECT_NEAR(j.at("weighting").at("heading_sd_deg").get<double>(), w.heading_sd_deg, 1e-12);
  EXPECT_TRUE(says(fit_result_text(*out.result), "Weighting: heading x"));
}

TEST(FitWeighting, TooFewRunsOrTruthAlongThePathKeepTheFixedWeight) {
  FitOptions options;
  options.replicates = 0;
  const FitOutcome few = fit_geometry(tape_runs(5, 15.0, 1.0, 3u), small_nominal(), options);
  ASSERT_TRUE(few) << few.error.message;
  EXPECT_FALSE(few.result->weighting.estimated);
  EXPECT_DOUBLE_EQ(few.result->heading_length_mm, FitOptions{}.heading_length_mm);
  EXPECT_TRUE(says(few.result->weighting.reason, "needs 6")) << few.result->weighting.reason;
  EXPECT_EQ(fit_result_json(*few.result).at("weighting").at("method"), "fixed");
  // Six runs are enough.
  const FitOutcome six = fit_geometry(tape_runs(6, 15.0, 1.0, 3u), small_nominal(), options);
  ASSERT_TRUE(six) << six.error.message;
  EXPECT_TRUE(six.result->weighting.estimated) << six.result->weighting.reason;
  // Motion capture along the path: its rows are not independent measurements.
  const Truth t;
  std::vector<TickLog> path;
  for (int i = 0; i < 8; ++i) {
    path.push_back(make_log(t, square(t, 1000.0, i % 2 == 0), Truthing::every_third_row));
  }
  const FitOutcome along = fit_geometry(path, small_nominal(), options);
  ASSERT_TRUE(along) << along.error.message;
  EXPECT_FALSE(along.result->weighting.estimated);
  EXPECT_TRUE(says(along.result->weighting.reason, "along the path"));
}

}  // namespace
}  // namespace odocal::host
