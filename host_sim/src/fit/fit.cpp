// `odocal fit`: the steps put together (fit_steps.hpp): what the runs determine, the
// one-wheelbase fit, the model, its fit, the scores, the intervals and the time lag.

#include <cmath>
#include <optional>

#include "fit_steps.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host {
namespace {

using fit_detail::ModelSpec;
using fit_detail::Params;
using fit_detail::params_of;
using fit_detail::Solved;
using fit_detail::spec_for;
using fit_detail::Unit;
using fit_detail::whole_runs;

/// The result's figures from the chosen model's fit `main` and what the logs determine.
FitResult result_of(const Solved& main, const fit_detail::Determination& d,
                    const FitModelChoice& choice, const FitNominal& nominal, const FitOptions& o) {
  const int np = fit_detail::parameter_count(choice.kind);
  FitResult r;
  r.nominal = nominal;
  r.model = choice;
  r.geometry = fit_detail::geometry_of(main.p, choice.kind);
  r.c_l = main.p[0] / nominal.wheel_diameter_mm;
  r.c_r = main.p[1] / nominal.wheel_diameter_mm;
  r.e_d = main.p[1] / main.p[0];
  r.e_b = main.p[2] / nominal.wheelbase_mm;
  r.level = o.level;
  r.seed = o.seed;
  r.heading_length_mm = o.heading_length_mm;
  r.iterations = main.iterations;
  for (int i = 0; i < np; ++i) {
    r.relative_sd[i] = d.relative_sd[i];
    for (int j = 0; j < np; ++j) {
      r.relative_cov[i][j] = d.relative_cov[i][j];
    }
  }
  return r;
}

/// What the design leaves open at the nominal geometry: for one wheelbase, and for the model
/// asked for when it has more parameters.
std::optional<FitError> undetermined_at_start(const std::vector<Unit>& units,
                                              const FitNominal& nominal, const FitOptions& o,
                                              const fit_detail::Design& design,
                                              const Params& start) {
  std::vector<FitModelKind> kinds{FitModelKind::one_wheelbase};
  if (o.model && *o.model != FitModelKind::one_wheelbase) {
    kinds.push_back(*o.model);
  }
  for (const FitModelKind kind : kinds) {
    Solved at;
    at.p = fit_detail::start_for(kind, start);
    at.heading_length_mm = o.heading_length_mm;
    at.normal = fit_detail::normal_equations(units, fit_detail::every_unit(units.size()), at.p,
                                             spec_for(kind, nominal), o.heading_length_mm, true);
    const fit_detail::Determination d = fit_detail::determination(at, o, kind, &design);
    if (!d.ok) {
      return d.error;
    }
  }
  return std::nullopt;
}

/// Whether the fit with the counts shifted by the estimated lag stays inside the intervals.
void check_lag_within_intervals(FitResult& r, int np) {
  if (!r.lag || !r.ci_left_mm) {
    return;
  }
  const std::optional<FitInterval>* cis[4] = {&r.ci_left_mm, &r.ci_right_mm, &r.ci_wheelbase_mm,
                                              &r.ci_second_wheelbase_mm};
  for (int i = 0; i < np; ++i) {
    const double v = r.lag->geometry_at_estimate[i];
    if (*cis[i] && (v < (*cis[i])->lo || v > (*cis[i])->hi)) {
      r.lag->within_intervals = false;
    }
  }
}

}  // namespace

const char* model_name(FitModelKind kind) {
  switch (kind) {
    case FitModelKind::one_wheelbase:
      return "one-wheelbase";
    case FitModelKind::arc_wheelbase:
      return "arc-wheelbase";
    case FitModelKind::turn_rate_wheelbase:
      return "turn-rate-wheelbase";
  }
  return "?";
}

FitFigures score_runs(const std::vector<TickLog>& runs, const FitNominal& nominal,
                      const FitGeometry& g, double /*heading_length_mm*/) {
  FitFigures f;
  f.runs = runs.size();
  FitGeometry before_geometry{nominal.wheel_diameter_mm, nominal.wheel_diameter_mm,
                              nominal.wheelbase_mm, FitModelKind::one_wheelbase, 0.0};
  const std::vector<Unit> units = whole_runs(runs);
  for (int which = 0; which < 2; ++which) {
    const FitGeometry& geometry = which == 0 ? before_geometry : g;
    const ModelSpec spec = spec_for(geometry.model, nominal);
    const Params p = params_of(geometry);
    double end_sum = 0.0, path_sum = 0.0;
    std::size_t end_n = 0, path_n = 0;
    for (const Unit& u : units) {
      double last = -1.0;
      fit_detail::integrate(u, p, spec, false,
                            [&](const TickRow& row, const fit_detail::ModelState& s) {
                              if (row.has_xy) {
                                last = std::hypot(s.x - row.x_mm, s.y - row.y_mm);
                                path_sum += last * last;
                                ++path_n;
                              }
                            });
      if (last >= 0.0) {
        end_sum += last * last;
        ++end_n;
      }
    }
    const double end = end_n > 0 ? std::sqrt(end_sum / static_cast<double>(end_n)) : 0.0;
    const double path = path_n > 0 ? std::sqrt(path_sum / static_cast<double>(path_n)) : 0.0;
    (which == 0 ? f.end_rms_before_mm : f.end_rms_after_mm) = end;
    (which == 0 ? f.path_rms_before_mm : f.path_rms_after_mm) = path;
  }
  return f;
}

FitOutcome fit_geometry(const std::vector<TickLog>& runs, const FitNominal& nominal,
                        const FitOptions& o, const std::vector<TickLog>& holdout) {
  FitOutcome out;
  if (runs.empty()) {
    out.error = FitError{"", "no runs to fit"};
    return out;
  }
  if (!(nominal.wheel_diameter_mm > 0.0 && nominal.wheelbase_mm > 0.0 &&
        nominal.counts_per_rev > 0.0) ||
      !(o.level > 0.0 && o.level < 1.0) || !(o.heading_length_mm >= 0.0) ||
      !(o.noise_floor_mm > 0.0 && o.noise_floor_deg > 0.0)) {
    out.error = FitError{"", "the nominal geometry and options must be positive"};
    return out;
  }
  const ModelSpec one_spec = fit_detail::spec_for(FitModelKind::one_wheelbase, nominal);
  const std::vector<Unit> units = fit_detail::whole_runs(runs);
  const std::vector<std::size_t> all = fit_detail::every_unit(units.size());
  const fit_detail::Design design = fit_detail::design_of(runs, nominal);
  Params start(3);
  start << nominal.wheel_diameter_mm, nominal.wheel_diameter_mm, nominal.wheelbase_mm;
  // What the runs' design can determine, judged first at the nominal geometry: where a parameter
  // is undetermined the fit may wander along it and hide which one it was.
  if (const std::optional<FitError> open =
          undetermined_at_start(units, nominal, o, design, start)) {
    out.error = *open;
    return out;
  }
  Solved one = fit_detail::solve(units, all, start, one_spec, o.heading_length_mm);
  if (!one.ok) {
    out.error = FitError{"",
                         "the fit did not converge to a physical geometry (check the logs' "
                         "units: counts, mm, degrees)"};
    return out;
  }
  // Heading against position: estimated from the runs where they can tell, then used throughout.
  const FitWeighting weighting = fit_detail::choose_weighting(units, one_spec, o, design, one);
  FitOptions ow = o;
  ow.heading_length_mm = weighting.heading_length_mm;
  const FitModelChoice choice = fit_detail::choose_model(runs, nominal, ow, units, one.p);
  const FitModelKind kind = choice.kind;
  const ModelSpec k = fit_detail::spec_for(kind, nominal);
  const Solved main = kind == FitModelKind::one_wheelbase
                          ? one
                          : fit_detail::solve(units, all, fit_detail::start_for(kind, one.p), k,
                                              ow.heading_length_mm);
  if (!main.ok) {
    out.error = FitError{"", std::string("the ") + model_name(kind) +
                                 " fit did not converge to a physical geometry"};
    return out;
  }
  fit_detail::Determination d = fit_detail::determination(main, ow, kind, &design);
  if (!d.ok) {
    out.error = d.error;
    return out;
  }
  fit_detail::add_scatter(d, main, ow, kind, fit_detail::noise_in_force(weighting, main, ow));
  FitResult r = result_of(main, d, choice, nominal, ow);
  r.weighting = weighting;
  if (!d.warning.empty()) {
    r.warnings.push_back(d.warning);
  }
  r.fit = score_runs(runs, nominal, r.geometry, ow.heading_length_mm);
  if (!holdout.empty()) {
    r.holdout = score_runs(holdout, nominal, r.geometry, ow.heading_length_mm);
  }
  if (!fit_detail::add_intervals(r, runs, main, k, ow, out.error)) {
    return out;
  }
  if (o.estimate_lag) {
    r.lag = fit_detail::estimate_lag(runs, main.p, k, ow, main.normal.cost);
    check_lag_within_intervals(r, fit_detail::parameter_count(kind));
  }
  out.result = r;
  return out;
}

}  // namespace odocal::host
