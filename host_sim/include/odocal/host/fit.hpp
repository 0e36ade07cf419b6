#pragma once
/// @file
/// `odocal fit`: least-squares estimate of a differential-drive robot's true left and right wheel
/// diameters and wheelbase from tick logs (DESIGN "Tick log", "Host program: sessions and fits"),
/// with bootstrap intervals over runs and in-sample / held-out accuracy figures.
///
/// Model: the odometry of each run is integrated row by row from the count increments, each row
/// an exact circular arc (as core/src/drive/odometry.cpp), with the parameters D_L, D_R, b. It
/// starts at the ground-truth pose of the run's first row, or at (0, 0, 0) when that row has none.
/// Residuals, at every row with ground truth: x and y in mm, and the heading (wrapped difference,
/// so unwrapped logs work) times a length: the fixed FitOptions::heading_length_mm, or the ratio
/// of the position and heading noise estimated from the runs (FitWeighting). Levenberg-Marquardt
/// with an analytic Jacobian. Host code: dynamic containers, exceptions only for unreadable input.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace odocal::host {

/// One row of a tick log: cumulative encoder counts at a time, and the ground truth if measured.
struct TickRow {
  std::size_t line = 0;  ///< 1-based line in the file (0 for logs built in memory)
  double t_s = 0.0;
  double count_l = 0.0;  ///< cumulative counts (x4), signed
  double count_r = 0.0;
  bool has_xy = false;  ///< x_mm, y_mm measured at this instant
  double x_mm = 0.0;
  double y_mm = 0.0;
  bool has_theta = false;  ///< theta_deg measured at this instant (may be unwrapped past ±180°)
  double theta_deg = 0.0;
};

/// One run: a tick log file (or one built in memory by a simulator).
struct TickLog {
  std::string source;  ///< file name, for messages
  std::vector<TickRow> rows;
};

/// Reads a tick log CSV: header `t_s,count_l,count_r` or `t_s,count_l,count_r,x_mm,y_mm,theta_deg`
/// (UTF-8 BOM and CRLF accepted, '#' lines and blank lines skipped). Empty ground-truth cells mean
/// "not measured at this row"; x_mm and y_mm are given together or not at all.
/// Throws InputError ("FILE:LINE: field 'NAME': why") for: no file, missing or unknown header
/// columns, wrong field count, a field that is not a plain finite number, absurd magnitudes,
/// time going backwards (equal times are accepted), fewer than 2 rows, no ground truth after the
/// first row, a first row with x/y but no heading (the start pose needs all three).
[[nodiscard]] TickLog read_tick_log(const std::string& path);

/// Checks a log built in memory by the same rules as read_tick_log; throws InputError.
void check_tick_log(const TickLog& log);

/// Writes `log` as CSV with the ground-truth columns (empty cells where a row has none), numbers
/// in full precision: what read_tick_log reads back.
void write_tick_log(const TickLog& log, std::ostream& out);

/// What the firmware is told (the geometry "before" the fit).
struct FitNominal {
  double wheel_diameter_mm = 60.0;  ///< nominal (average) wheel diameter D
  double wheelbase_mm = 150.0;      ///< nominal wheelbase b
  double counts_per_rev = 1440.0;   ///< counts per wheel turn after x4 decoding; may be fractional
};

/// Which geometry describes the robot (docs/calibration.md "Models"; DESIGN "Real-robot model").
enum class FitModelKind {
  one_wheelbase,  ///< D_L, D_R and one wheelbase b
  /// D_L, D_R, b (turns in place) and wheelbase_arc_mm: the wheelbase in force over a stretch is
  /// b + w·(b_arc − b), w = |n_L + n_R| / (|n_L + n_R| + |n_R − n_L|) from its encoder counts
  /// (0 turning in place, R/(R + b/2) on an arc of radius R, 1 straight).
  arc_wheelbase,
  /// D_L, D_R, b (at rest) and the wheelbase at 1 rad/s of turn rate, linear in |ω| between (|ω|
  /// from the counts and the nominal geometry): a comparison candidate (slip growing with the
  /// turn rate).
  turn_rate_wheelbase,
};

/// "one-wheelbase", "arc-wheelbase", "turn-rate-wheelbase".
[[nodiscard]] const char* model_name(FitModelKind kind);

/// The estimated geometry.
struct FitGeometry {
  double wheel_diameter_left_mm = 0.0;
  double wheel_diameter_right_mm = 0.0;
  double wheelbase_mm = 0.0;  ///< the wheelbase for turns in place (or the one wheelbase)
  FitModelKind model = FitModelKind::one_wheelbase;
  /// arc_wheelbase: wheelbase_arc_mm; turn_rate_wheelbase: the wheelbase at 1 rad/s; else unused.
  double second_wheelbase_mm = 0.0;
};

/// Receives one-line progress messages during the bootstrap ("fit: bootstrap 200/1000").
using FitProgressFn = std::function<void(const std::string&)>;

/// How the intervals are made (FitOptions::interval).
enum class FitIntervalMethod {
  wild_t,      ///< wild cluster bootstrap-t over runs, each end at least as far out as
               ///< student_t's (default, see docs/calibration.md)
  student_t,   ///< CR2 standard error × Student t with Bell-McCaffrey degrees of freedom
  percentile,  ///< percentile of refits of runs resampled with replacement, widened
};

struct FitOptions {
  FitIntervalMethod interval = FitIntervalMethod::wild_t;
  std::uint32_t replicates = 500;  ///< bootstrap B (0: no intervals)
  /// With B = 0, still the runs' CR2 covariance and degrees of freedom (FitResult::cluster_sd,
  /// dof, cluster_cov; no intervals): what session auto judges its precision with between runs.
  bool cluster_covariance = false;
  std::uint64_t seed = 1;  ///< bootstrap resampling seed (same seed, same intervals)
  double level = 0.95;     ///< interval level, in (0, 1)
  /// The fixed weight: heading residuals are scaled to mm by this length, 2 mm / 0.4° (UMBmark's
  /// calibrator), so one degree of heading weighs as much as 5 mm of position. Used where the
  /// runs cannot tell their own position and heading noise (FitWeighting).
  double heading_length_mm = 286.4789;
  /// Weigh heading against position by the noise of each estimated from the runs' end residuals
  /// where there are min_weighting_runs runs measured at their end in x, y and heading and no run
  /// has ground truth along its path (docs/calibration.md "Weights").
  bool estimate_weighting = true;
  std::size_t min_weighting_runs = 6;
  /// Identifiability: the design of the runs (what was driven, what was measured) must determine
  /// each parameter direction (in relative terms, from the eigen-decomposition of the
  /// column-scaled JᵀJ, i.e. the scaled Jacobian's SVD) to this relative standard deviation or
  /// better...
  double max_relative_sd = 0.01;
  /// ... with measurements as good as a tape measure or motion capture can be (the noise floor):
  /// this much in x and y (mm) and noise_floor_deg in heading. Judged at the nominal geometry and
  /// at the fitted one. Residual scatter above the floor widens the intervals and adds a warning
  /// (FitResult::warnings), never a refusal.
  double noise_floor_mm = 2.0;
  double noise_floor_deg = 0.4;
  /// Bootstrap units: runs. When there are fewer than this many runs, runs with ground truth
  /// along the path are cut into pieces (each restarting at its first row's ground truth) so that
  /// there are about this many units to resample.
  std::size_t min_units = 6;
  /// The model: forced, or (empty) chosen by held-out prediction (FitModelChoice).
  std::optional<FitModelKind> model;
  /// Data set of each run (same length as the runs, or empty: the folder of each log's source).
  /// Model selection leaves out one set at a time when there are 3 sets or more, else one run.
  std::vector<std::string> sets;
  /// A richer model is chosen only when its held-out path RMS is below the simpler one's by this
  /// fraction or more.
  double min_gain = 0.02;
  /// A model with two wheelbases is tried only when the logs fix each to this relative CR2
  /// standard error over runs or better (a fifth of the 1.3 mm between the June robot's turns in
  /// place and arcs, relative to its 200 mm).
  double max_wheelbase_sd = 0.0013;
  /// Estimate the time lag between counts and ground truth (two refits per probe).
  bool estimate_lag = true;
  FitProgressFn progress;  ///< called from the calling thread only (the bootstrap uses two)
};

/// Accuracy of a set of runs under the nominal ("before") and fitted ("after") geometry.
struct FitFigures {
  std::size_t runs = 0;
  double end_rms_before_mm = 0.0;  ///< RMS over runs of the last x/y ground truth's radial error
  double end_rms_after_mm = 0.0;
  double path_rms_before_mm = 0.0;  ///< RMS over every x/y ground-truth row of all runs
  double path_rms_after_mm = 0.0;
};

/// Interval [lo, hi] at FitOptions::level.
struct FitInterval {
  double lo = 0.0;
  double hi = 0.0;
};

/// One model tried: its held-out path RMS (mm; every ground-truth row of every left-out set or
/// run, each predicted by a fit of the others), or why it was not tried.
struct FitCandidate {
  FitModelKind kind = FitModelKind::one_wheelbase;
  bool tried = false;      ///< held-out prediction computed
  bool supported = false;  ///< the logs determine its parameters: it may be chosen
  double heldout_path_rms_mm = 0.0;
  std::size_t folds = 0;
  std::string note;  ///< why not tried or not supported, or ""
};

/// Which model was used and why.
struct FitModelChoice {
  FitModelKind kind = FitModelKind::one_wheelbase;
  std::string reason;
  std::string unit;  ///< "set" or "run": what each fold left out ("" when nothing was compared)
  std::vector<FitCandidate> candidates;
};

/// Time lag between counts and ground truth: the shift of the counts' clock that fits best, and
/// how much each parameter moves per 50 ms of shift (the result's sensitivity to it).
struct FitLag {
  double estimate_s = 0.0;  ///< > 0: the counts were stamped late (count at t happened at t − lag)
  double per_50ms[4] = {0, 0, 0, 0};              ///< D_L, D_R, b, second wheelbase: mm per +50 ms
  double geometry_at_estimate[4] = {0, 0, 0, 0};  ///< the fit with the counts shifted by it
  bool within_intervals = true;                   ///< the shifted fit stays inside the intervals
};

/// How heading residuals are weighed against position residuals.
struct FitWeighting {
  /// True: from the runs' end residuals (position_sd_mm / heading_sd_deg); false: the fixed
  /// FitOptions::heading_length_mm.
  bool estimated = false;
  double heading_length_mm = 0.0;  ///< in force: mm of position per rad of heading
  std::size_t runs = 0;            ///< runs measured at their end in x, y and heading
  /// The estimates (0 when not estimated): the end position's noise per axis and the heading's,
  /// each at least the noise floor, with their degrees of freedom (residuals less leverage).
  double position_sd_mm = 0.0;
  double heading_sd_deg = 0.0;
  double position_dof = 0.0;
  double heading_dof = 0.0;
  std::string reason;  ///< why estimated or fixed
};

struct FitResult {
  FitGeometry geometry;
  FitWeighting weighting;
  /// What the user should know about a result that is given anyway (e.g. residual scatter far
  /// above the noise floor: wide intervals), one line each.
  std::vector<std::string> warnings;
  FitModelChoice model;
  std::optional<FitInterval> ci_second_wheelbase_mm;  ///< the model's second wheelbase
  std::optional<FitLag> lag;
  FitNominal nominal;
  double c_l = 1.0;  ///< D_L / D (the firmware's c_l)
  double c_r = 1.0;  ///< D_R / D
  double e_d = 1.0;  ///< D_R / D_L
  double e_b = 1.0;  ///< b fitted / b nominal
  /// Intervals at `level` by FitOptions::interval (absent when B = 0, or with a single unit).
  std::optional<FitInterval> ci_left_mm, ci_right_mm, ci_wheelbase_mm, ci_c_l, ci_c_r;
  FitIntervalMethod interval = FitIntervalMethod::wild_t;
  std::size_t bootstrap_units = 0;  ///< runs (or pieces of runs, or data sets) resampled
  /// What the intervals treat as independent: "run" (runs or pieces of runs), or "set" (with 3
  /// data sets or more, FitOptions::sets: the intervals hold across sets).
  std::string clusters = "run";
  std::uint32_t replicates = 0;  ///< B
  std::uint32_t redrawn = 0;     ///< percentile: resamples drawn again (determined nothing)
  double widen = 1.0;  ///< percentile: each end's distance from the estimate × sqrt(n/(n − 3))
  /// wild_t, student_t: D_L, D_R, b relative CR2 standard errors over runs and their
  /// Bell-McCaffrey degrees of freedom.
  double cluster_sd[4] = {0, 0, 0, 0};
  double dof[4] = {0, 0, 0, 0};
  /// Their covariance (relative, as relative_cov): with intervals, or with B = 0 when
  /// FitOptions::cluster_covariance asks for it; zero otherwise.
  double cluster_cov[4][4] = {};
  double level = 0.95;
  std::uint64_t seed = 0;
  double heading_length_mm = 0.0;        ///< the weight in force (= weighting.heading_length_mm)
  std::size_t iterations = 0;            ///< Levenberg-Marquardt iterations of the main fit
  double relative_sd[4] = {0, 0, 0, 0};  ///< D_L, D_R, b (, second) relative sd (linearised)
  /// Their covariance (of ln D_L, ln D_R, ln b, ln second; linearised, the same noise): what a
  /// prediction from the fitted geometry is unsure of (session --procedure auto).
  double relative_cov[4][4] = {};
  FitFigures fit;                     ///< on the logs fitted
  std::optional<FitFigures> holdout;  ///< on the held-out logs, when given
};

/// Why the data cannot give a result.
struct FitError {
  /// The parameter the data cannot determine: "wheelbase_mm", "wheel_diameter_left_mm",
  /// "wheel_diameter_right_mm", "scale" (all three together: the overall size), a model's second
  /// wheelbase ("wheelbase_arc_mm", "wheelbase_at_1radps_mm"), or "" for other failures (no
  /// runs, the fit diverged).
  std::string parameter;
  std::string message;  ///< one line: names the parameter and the cause found in the runs' design
};

/// A result or the reason there is none.
struct FitOutcome {
  std::optional<FitResult> result;
  FitError error;
  explicit operator bool() const { return result.has_value(); }
};

/// Fits D_L, D_R and b to `runs` (each checked as by check_tick_log beforehand), then bootstraps
/// over runs, and scores `holdout` (may be empty: FitResult::holdout stays empty).
/// Fails (no exception) when the design of the runs cannot determine a parameter at the noise
/// floor (e.g. straight lines alone and the wheelbase; closed loops measured only at the end and
/// the overall scale; one curvature and the wheels' difference against the wheelbase), or the fit
/// does not converge to a physical geometry. Residual scatter never refuses: it widens the
/// intervals and adds a warning.
[[nodiscard]] FitOutcome fit_geometry(const std::vector<TickLog>& runs, const FitNominal& nominal,
                                      const FitOptions& options,
                                      const std::vector<TickLog>& holdout = {});

/// Accuracy of `runs` under the nominal geometry and under `geometry`.
[[nodiscard]] FitFigures score_runs(const std::vector<TickLog>& runs, const FitNominal& nominal,
                                    const FitGeometry& geometry, double heading_length_mm);

/// The contract JSON (DESIGN "odocal fit"): wheel_diameter_left_mm wheel_diameter_right_mm
/// wheelbase_mm c_l c_r e_d e_b ci{...} fit holdout (null without held-out logs), plus
/// nominal, bootstrap and relative_sd details.
[[nodiscard]] nlohmann::json fit_result_json(const FitResult& result);

/// "wild-bootstrap-t", "student-t", "percentile" (the JSON's bootstrap.interval).
[[nodiscard]] const char* interval_name(FitIntervalMethod method);

/// The same for people.
[[nodiscard]] std::string fit_result_text(const FitResult& result);

}  // namespace odocal::host
