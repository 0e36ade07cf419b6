#pragma once
/// @file
/// Every measured run judged by all the others (DESIGN "Readings judged by all the runs"): each
/// run's measured end is compared with what the *other* runs predict for it through the robot's
/// model (leave-one-out), on the scale the tape's noise, the robot's random drift estimated
/// without the run being judged, and what the others leave unknown about the geometry allow.
/// A wrong reading cannot hide itself: it never takes part in its own prediction, and the drift
/// that scales its judgement is estimated from the other runs alone.
///
/// The model: the arc-wheelbase geometry (D_L, D_R, the wheelbase for turns in place, the arc
/// wheelbase; fit_model.hpp's exact-arc odometry on the logged counts), linearised about a
/// centre (the geometry in force) and refined by Gauss-Newton, with a prior that says how far a
/// real robot can be from the centre (what no run constrains stays at the prior's width, so a run
/// whose parameters only it measures is never judged on them). Each run's end is noisy by the
/// tape (position and heading) and by Chong & Kleeman's per-wheel random walk (fit_noise.hpp),
/// one k for both wheels, and by a slip held over each run (each wheel's size off by a share for
/// the whole run), both estimated by maximum likelihood from the runs in the prediction.
/// docs/calibration.md, "Every run judged by the others", derives it.

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "odocal/host/fit.hpp"

namespace odocal::host {

struct AgreementOptions {
  double tape_sigma_mm = 2.0;     ///< a reading's position noise, per axis
  double tape_sigma_deg = 0.5;    ///< a reading's heading noise (two marks on the robot)
  double prior_scale = 0.025;     ///< 1 sigma, relative: the wheels' mean size
  double prior_ratio = 0.01;      ///< 1 sigma: ln(D_R / D_L)
  double prior_wheelbase = 0.04;  ///< 1 sigma, relative: the wheelbase for turns in place
  double prior_arc_share = 0.02;  ///< 1 sigma: ln(b_arc / b)
  /// The drift k (mm²/mm) has a floor below which no run is judged: a robot never scatters less
  /// than this however well its other runs agree (few runs can agree by chance).
  double min_k_mm = 2.0e-4;
  /// Each run's end is also allowed this share of its own size (path length, turning) as a
  /// run-to-run scatter the random-walk model does not have (slip that holds over a stretch).
  double relative_scatter = 0.001;        ///< of the length driven, mm per mm
  double relative_turn_scatter = 0.0015;  ///< of the angle turned
  /// A run disagrees when its squared Mahalanobis distance from the others' prediction is above
  /// this (chi-square: 2 or 3 degrees of freedom; 30 is past 5 sigma for 3), widened by 1 + 4/v
  /// for a noise estimated from v readings more than the parameters.
  double threshold = 30.0;
};

/// What the other runs predict for one run's measured end.
struct RunJudgement {
  std::size_t index = 0;  ///< into the logs
  /// The predicted end (x mm, y mm, heading rad, unwrapped as the odometry counts it) and the
  /// covariance of a reading about it (the prediction's own uncertainty, the run's drift and the
  /// tape's noise; mm, mm, rad).
  Eigen::Vector3d predicted = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  /// The reading's squared Mahalanobis distance from the prediction (heading wrapped) and its
  /// degrees of freedom (3 with a heading, 2 without).
  double distance2 = 0.0;
  int dof = 2;
  /// The squared distance a reading may have and agree: AgreementOptions::threshold widened for
  /// a noise estimated from few readings.
  double allowed2 = 0.0;
  /// The noise used, from the runs in the prediction: the random walk k (mm²/mm) and the slip
  /// held over a run (relative sd of each wheel's size).
  double k_mm = 0.0;
  double slip = 0.0;
};

/// A run that disagrees with the others.
struct Disagreement {
  RunJudgement judgement;
  /// Runs whose leaving out alone would make it agree: when there are any, the others cannot
  /// tell whether this run or one of these is the wrong one (ordered by how well each
  /// explains it, best first).
  std::vector<std::size_t> partners;
};

struct AgreementResult {
  std::vector<RunJudgement> runs;  ///< every run with a measured end, judged by the others
  /// The runs that disagree, worst first; each judged without the runs named before it.
  std::vector<Disagreement> disagreements;
};

/// The squared Mahalanobis distance of a reading (x mm, y mm, heading deg or none) from a
/// judgement's prediction (heading wrapped to the nearest turn of the predicted one).
[[nodiscard]] double reading_distance2(const RunJudgement& j, double x_mm, double y_mm,
                                       std::optional<double> theta_deg);

/// Judges every run of `logs` whose last row holds a measured end (x, y; heading optional) by
/// all the others, about the geometry `centre` (its second wheelbase: the arc wheelbase, 0 for the
/// same as the first). `left_out[i]` (when given): run i predicts nothing (it is still judged).
/// `exempt[i]` (when given): run i is never named as disagreeing (the owner kept it).
[[nodiscard]] AgreementResult judge_runs(const std::vector<TickLog>& logs,
                                         const FitNominal& nominal, const FitGeometry& centre,
                                         const AgreementOptions& options,
                                         const std::vector<bool>& left_out = {},
                                         const std::vector<bool>& exempt = {});

/// What the runs `logs` (all predicting; `left_out` as above) predict for the end of `log`,
/// whose own reading (if its last row has one) is not used.
[[nodiscard]] RunJudgement predict_run(const std::vector<TickLog>& logs, const TickLog& log,
                                       const FitNominal& nominal, const FitGeometry& centre,
                                       const AgreementOptions& options,
                                       const std::vector<bool>& left_out = {});

}  // namespace odocal::host
