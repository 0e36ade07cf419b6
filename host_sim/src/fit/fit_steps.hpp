#pragma once
// Internal to host_sim/src/fit: the steps of `odocal fit`, which fit.cpp puts together. Solving
// and the parameters of each model (fit_solve.cpp), what the runs drove (fit_design.cpp), what
// they determine (fit_determination.cpp), how heading weighs against position
// (fit_weighting.cpp), which model describes the robot (fit_model_choice.cpp), the intervals
// (fit_bootstrap.cpp, over fit_interval.cpp's cluster algebra) and the time lag (fit_lag.cpp).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fit_model.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host::fit_detail {

/// A reason's text: `fmt` (printf) with up to three numbers (fit_design, fit_model_choice).
[[nodiscard]] std::string reason_text(const char* fmt, double a, double b = 0.0, double c = 0.0);

// ------------------------------------------------------------------------- solving (fit_solve)

/// The JSON name of parameter i of a model.
[[nodiscard]] const char* parameter_name(FitModelKind kind, int i);

struct Solved {
  bool ok = false;
  Params p;
  Normal normal;                   ///< at p, with the Jacobian
  double heading_length_mm = 0.0;  ///< the weight `normal` was made with
  std::size_t iterations = 0;
};

/// Levenberg-Marquardt (Marquardt's diagonal scaling) from `start` on the units `pick`.
[[nodiscard]] Solved solve(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
                           const Params& start, const ModelSpec& k, double heading_length_mm);

[[nodiscard]] ModelSpec spec_for(FitModelKind kind, const FitNominal& nominal);
[[nodiscard]] Params params_of(const FitGeometry& g);
[[nodiscard]] FitGeometry geometry_of(const Params& p, FitModelKind kind);

/// Starting point of a model's fit from a one-wheelbase estimate (D_L, D_R, b).
[[nodiscard]] Params start_for(FitModelKind kind, const Params& one);

/// Whole runs as units.
[[nodiscard]] std::vector<Unit> whole_runs(const std::vector<TickLog>& logs);

/// 0, 1, ..., count − 1: every unit.
[[nodiscard]] std::vector<std::size_t> every_unit(std::size_t count);

// ------------------------------------------------------- what was driven (fit_design)

/// How the runs turn, by the nominal geometry: in place (arc weight below 1/3: radius under
/// b/4), on arcs (weight 1/3 to 0.95: radius up to about 10 b), in total (rad).
struct Turning {
  double total_rad = 0.0;
  double in_place_rad = 0.0;
  double arcs_rad = 0.0;
};

[[nodiscard]] Turning turning_of(const std::vector<TickLog>& runs, const FitNominal& nominal);

/// What the runs drove and what was measured, by the nominal geometry: what a refusal's cause is
/// read from (never from residuals).
struct Design {
  Turning turning;
  std::size_t runs = 0;
  std::size_t runs_with_xy = 0;  ///< runs with a position measured after their start
  /// Runs whose truth after the start is only at their end (the wheels not moving between those
  /// rows), measured in x and y, and that end within a tenth of their travel of where they
  /// started: closed loops measured only at the end.
  std::size_t closed_end_only = 0;
  std::size_t path_truth = 0;     ///< runs with ground truth along the path (not only at the end)
  std::size_t end_pose_runs = 0;  ///< runs measured at their end in x, y and heading
  double travel_mm = 0.0;         ///< the centre's travel, summed over runs with x/y truth
  double wheel_travel_mm = 0.0;   ///< the wheels' mean travel, over the same runs
  double left_mm = 0.0;           ///< each wheel's travel, all runs
  double right_mm = 0.0;
  /// The count increments of every row in one proportion (one curvature: every row the same arc,
  /// straight lines included): smallest over largest eigenvalue of Σ (n_L, n_R)(n_L, n_R)ᵀ.
  double count_spread = 0.0;
};

[[nodiscard]] Design design_of(const std::vector<TickLog>& runs, const FitNominal& nominal);

/// Why the design fixes the direction `dir` (eigenvector of the column-scaled JᵀJ) only to the
/// relative standard deviation `sd` at the noise floor: the cause read from the design.
[[nodiscard]] FitError undetermined(const Params& dir, double sd, FitModelKind kind,
                                    const Design& design);

// -------------------------------------------- what the logs determine (fit_determination)

/// Relative (log-parameter) covariance directions: what the data determine, and how well.
struct Determination {
  bool ok = true;
  FitError error;
  double relative_sd[4] = {0, 0, 0, 0};
  double relative_cov[4][4] = {};
  /// The residual scatter leaves a direction looser than FitOptions::max_relative_sd (not a
  /// refusal: the design determines it): one line naming the scatter, or "".
  std::string warning;
};

/// The position and heading noise a fit's covariance is judged with.
struct Noise {
  double position_mm = 0.0;
  double heading_rad = 0.0;
};

/// Whether the design determines every direction at the noise floor (FitOptions::noise_floor_mm,
/// noise_floor_deg), whatever the weighting of `s` was. With `design`, a refusal names its
/// cause; without (bootstrap resamples), only ok matters.
[[nodiscard]] Determination determination(const Solved& s, const FitOptions& o, FitModelKind kind,
                                          const Design* design);

/// The covariance of the fit `s` with the noise in force (`noise`), and the warning when the
/// scatter leaves a direction looser than FitOptions::max_relative_sd.
void add_scatter(Determination& d, const Solved& s, const FitOptions& o, FitModelKind kind,
                 const Noise& noise);

// ------------------------------------------------------ heading against position (fit_weighting)

/// The weighting (fixed, or estimated from the end residuals and refitted until it settles) and
/// the one-wheelbase fit with it; `fit` is the fit with the fixed weight on entry.
[[nodiscard]] FitWeighting choose_weighting(const std::vector<Unit>& units, const ModelSpec& spec,
                                            const FitOptions& o, const Design& design, Solved& fit);

/// The noise a fit's covariance uses: the estimates, or the residual RMS (at least the floor)
/// shared by position and heading in the proportion of the fixed weight.
[[nodiscard]] Noise noise_in_force(const FitWeighting& w, const Solved& s, const FitOptions& o);

// ------------------------------------------------------------- the model (fit_model_choice)

/// The data set of each run: FitOptions::sets, or the folder of the log's source.
[[nodiscard]] std::vector<std::string> set_names(const std::vector<TickLog>& runs,
                                                 const FitOptions& o);

/// The names, sorted, each once.
[[nodiscard]] std::vector<std::string> distinct(std::vector<std::string> names);

/// Held-out prediction of each candidate model, and the choice (docs/calibration.md "Models").
[[nodiscard]] FitModelChoice choose_model(const std::vector<TickLog>& runs,
                                          const FitNominal& nominal, const FitOptions& o,
                                          const std::vector<Unit>& units, const Params& one_start);

// ------------------------------------------------------------------ intervals (fit_bootstrap)

/// Fills the intervals of `r` (the fit `main` of model `k` on `runs`) by FitOptions::interval;
/// nothing with B = 0. False (and `error`) when no bootstrap resample determines the geometry.
[[nodiscard]] bool add_intervals(FitResult& r, const std::vector<TickLog>& runs, const Solved& main,
                                 const ModelSpec& k, const FitOptions& o, FitError& error);

// ----------------------------------------------------------------------- time lag (fit_lag)

/// Lag estimate: refits with the counts shifted by ±50 ms, the parabola through the three costs
/// (`cost0`: the cost unshifted). Empty when the logs cannot show a lag.
[[nodiscard]] std::optional<FitLag> estimate_lag(const std::vector<TickLog>& runs, const Params& p,
                                                 const ModelSpec& spec, const FitOptions& o,
                                                 double cost0);

}  // namespace odocal::host::fit_detail
