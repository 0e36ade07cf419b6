#pragma once
// Internal to host_sim/src/fit: the steps of `odocal fit`, which fit.cpp puts together. Solving
// and the parameters of each model (fit_solve.cpp), what the logs determine
// (fit_determination.cpp), which model describes the robot (fit_model_choice.cpp), the intervals
// (fit_bootstrap.cpp, over fit_interval.cpp's cluster algebra) and the time lag (fit_lag.cpp).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fit_model.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host::fit_detail {

// ------------------------------------------------------------------------- solving (fit_solve)

/// The JSON name of parameter i of a model.
[[nodiscard]] const char* parameter_name(FitModelKind kind, int i);

struct Solved {
  bool ok = false;
  Params p;
  Normal normal;  ///< at p, with the Jacobian
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

// -------------------------------------------- what the logs determine (fit_determination)

/// Relative (log-parameter) covariance directions: what the data determine, and how well.
struct Determination {
  bool ok = true;
  FitError error;
  double relative_sd[4] = {0, 0, 0, 0};
  double relative_cov[4][4] = {};
};

/// @param turned_rad how much the runs turn (nominal geometry), to say why the wheelbase is not
///        determined.
/// @param use_residuals take the residual scatter as the noise when it exceeds the floor (at the
///        fitted geometry; at the nominal one the residuals are the systematic error itself).
[[nodiscard]] Determination determination(const Solved& s, const FitOptions& o, FitModelKind kind,
                                          double turned_rad, bool use_residuals = true);

// ------------------------------------------------------------- the model (fit_model_choice)

/// How the runs turn, by the nominal geometry: in place (arc weight below 1/3: radius under
/// b/4), on arcs (weight 1/3 to 0.95: radius up to about 10 b), in total (rad).
struct Turning {
  double total_rad = 0.0;
  double in_place_rad = 0.0;
  double arcs_rad = 0.0;
};

[[nodiscard]] Turning turning_of(const std::vector<TickLog>& runs, const FitNominal& nominal);

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
