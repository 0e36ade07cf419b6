// `odocal session --procedure fit`: runs logged with `stream ticks` into tick logs (the measured
// stop point on each log's last row), then `odocal fit`'s least squares for the true wheel
// diameters and wheelbase, applied as c_l = D_L/D, c_r = D_R/D and wheelbase_mm.
// The runs alternate a straight line (scale and wheel ratio) with left and right arcs (the
// wheelbase: an arc's end point moves with how far it turned), so that end points alone
// determine all three.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "auto_plan.hpp"
#include "model_in_force.hpp"
#include "odocal/calib/quantile.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "run_jury.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

std::string tick_log_csv(const RunRecord& r) {
  std::ostringstream out;
  out << "# odocal session: trial " << r.trial << " (" << r.path
      << "), counts from 'stream ticks'; last row: the measured stop point\n"
         "t_s,count_l,count_r,x_mm,y_mm,theta_deg\n";
  const double t0 =
      r.ticks.empty() ? 0.0 : r.ticks.front().t_ms;  // no rows: read_tick_log refuses it
  for (std::size_t i = 0; i < r.ticks.size(); ++i) {
    const TickSample& s = r.ticks[i];
    char line[160];
    std::snprintf(line, sizeof line, "%.3f,%lld,%lld,", (s.t_ms - t0) / 1000.0,
                  static_cast<long long>(s.count_l), static_cast<long long>(s.count_r));
    out << line;
    if (i + 1 == r.ticks.size()) {
      std::snprintf(line, sizeof line, "%.3f,%.3f,", r.measured.x_mm, r.measured.y_mm);
      out << line;
      if (r.measured.theta_deg) {
        std::snprintf(line, sizeof line, "%.3f", *r.measured.theta_deg);
        out << line;
      }
      out << "\n";
    } else {
      out << ",,\n";
    }
  }
  return out.str();
}

TickLog tick_log_of(const RunRecord& r, bool with_reading) {
  TickLog log;
  log.source = fmt::format("trial {} ({})", r.trial, r.path);
  const double t0 = r.ticks.empty() ? 0.0 : r.ticks.front().t_ms;
  for (const TickSample& s : r.ticks) {
    TickRow row;
    row.t_s = (s.t_ms - t0) / 1000.0;
    row.count_l = static_cast<double>(s.count_l);
    row.count_r = static_cast<double>(s.count_r);
    log.rows.push_back(row);
  }
  if (with_reading && !log.rows.empty()) {
    TickRow& end = log.rows.back();
    end.has_xy = true;
    end.x_mm = r.measured.x_mm;
    end.y_mm = r.measured.y_mm;
    end.has_theta = r.measured.theta_deg.has_value();
    end.theta_deg = r.measured.theta_deg.value_or(0.0);
  }
  return log;
}

namespace {

/// The fit's runs: a line, a left arc, a right arc, repeated, each logged with `stream ticks` and
/// judged by the others as it is measured (run_jury.hpp: a run that disagrees and is driven again
/// is followed by another of its kind). The logs the fit may use (the measured stop point on each
/// log's last row).
std::vector<TickLog> drive_fit_runs(Context& c, std::size_t n, double length_m, RunJury& jury) {
  const double cruise = c.get(ParamId::v_max_mps);
  c.log << "Fit: " << n << " runs logged with 'stream ticks' (a " << fmt::format("{:.2f}", length_m)
        << " m line, a left arc, a right arc, repeated); measure the stop point of each, with "
           "its heading if you can.\n";
  const auto drive = [&](const std::string& label) {
    RunRecord r;
    if (label == "line") {
      r = c.run("line", Motion::line(length_m), c.path_seconds(length_m, 0.0, 1), true);
    } else {
      // ~140° arcs of 0.3 m radius at 0.75 of the cruise speed.
      const double v = 0.75 * cruise;
      const double w = (label == "arc-left" ? 1.0 : -1.0) * v / 0.3;
      const int ms = static_cast<int>(std::lround(2.5 / std::fabs(w) * 1000.0));
      r = c.run(label, Motion::timed(v, w, ms), ms / 1000.0 + 2.0, true);
    }
    c.write_file(fmt::format("fit_run_{:02d}.csv", jury.size() + 1), tick_log_csv(r));
    jury.add(c.runs.size() - 1);
    return jury.settle();
  };
  static const char* const kinds[3] = {"line", "arc-left", "arc-right"};
  std::vector<std::size_t> again;  // runs that disagreed, to drive again
  for (;;) {
    // The plan's runs (those driven again not counted), in order; --resume: the run recorded
    // next is taken as it was.
    const std::size_t planned = jury.size() - jury.driven_again();
    std::string label;
    if (c.runs.size() < c.options.replay.size()) {
      label = c.options.replay[c.runs.size()].label;
    } else if (!again.empty()) {
      label = c.runs[again.front()].label;
      again.erase(again.begin());
    } else if (planned < n) {
      label = kinds[planned % 3];
    } else {
      break;
    }
    const std::vector<std::size_t> more = drive(label);
    again.insert(again.end(), more.begin(), more.end());
  }
  return jury.logs_in_use();
}

/// What the fit changes, by the parts of the geometry it measures (the one composition rule): the
/// scale (the mean wheel diameter), the wheel ratio D_R/D_L, and the turn geometry (the
/// wheelbase over the mean diameter: what sets every turn's angle). Each part whose fitted value
/// lies outside about 2 standard deviations (the fit's linearised covariance) of the value in
/// force replaces it; a part within keeps the value in force (a fit of a few runs does not
/// replace a better UMBmark ratio by its noise). A new scale keeps the turn geometry, so the
/// wheelbase scales with it and every turn keeps its angle. The arc-wheelbase model replaces the
/// whole geometry (the data chose it by held-out prediction). `shown` says which parts change,
/// `text` why. The geometry in force is the robot odometry's (F_lat and F_lon folded in).
/// `any`: something is to change.
Factors fit_choice(const FitResult& result, const Factors& in_force, double d,
                   nlohmann::json& shown, bool& any, std::ostream& text) {
  const drive::model::Geometry<double> now = geometry_in_force(in_force, d);
  const FitGeometry& f = result.geometry;
  // Parts in logs: (ln D_L + ln D_R)/2, ln D_R − ln D_L, ln b − scale; their rows on the fit's
  // log-parameters (ln D_L, ln D_R, ln b).
  const double rows[3][3] = {{0.5, 0.5, 0.0}, {-1.0, 1.0, 0.0}, {-0.5, -0.5, 1.0}};
  const auto parts = [](double l, double r, double b) {
    const double scale = 0.5 * (std::log(l) + std::log(r));
    return std::array<double, 3>{scale, std::log(r) - std::log(l), std::log(b) - scale};
  };
  const std::array<double, 3> fitted =
      parts(f.wheel_diameter_left_mm, f.wheel_diameter_right_mm, f.wheelbase_mm);
  const std::array<double, 3> was = parts(now.left_diameter, now.right_diameter, now.wheelbase);
  static const char* const names[3] = {"scale (mean wheel diameter)", "wheel ratio D_R/D_L",
                                       "turn geometry (wheelbase / mean diameter)"};
  static const char* const keys[3] = {"scale", "wheel_ratio", "turn_geometry"};
  const bool arc_model = f.model == FitModelKind::arc_wheelbase;
  std::array<double, 3> chosen{};
  shown = nlohmann::json::object();
  any = arc_model;  // the data chose a second wheelbase (held-out prediction): it goes in force
  // How far each part may be from the fit by chance: the larger of the linearised figure and the
  // runs' own scatter (the cluster-robust standard errors over runs, taken as independent: the
  // linearised one misses slip that is the same along a run), times Student's t at the runs'
  // degrees of freedom (two-sided 95 %).
  const double dof = std::max(1.0, std::min({result.dof[0], result.dof[1], result.dof[2]}));
  const double t = result.dof[0] > 0.0 ? calib::student_t_quantile(0.975, dof) : 2.0;
  for (int k = 0; k < 3; ++k) {
    double var = 0.0;
    double runs_var = 0.0;
    for (int a = 0; a < 3; ++a) {
      runs_var += rows[k][a] * rows[k][a] * result.cluster_sd[a] * result.cluster_sd[a];
      for (int b = 0; b < 3; ++b) {
        var += rows[k][a] * rows[k][b] * result.relative_cov[a][b];
      }
    }
    const double sd = std::sqrt(std::max({var, runs_var, 0.0}));
    const bool outside = !(std::fabs(fitted[k] - was[k]) <= t * sd) || arc_model;
    chosen[k] = outside ? fitted[k] : was[k];
    shown[keys[k]] = outside;
    any = any || outside;
    text << fmt::format("  {:<42} fitted {:+.3f} % ±{:.3f} % (95 %) from the one in force: {}\n",
                        names[k], 100.0 * (fitted[k] - was[k]), 100.0 * t * sd,
                        outside ? "changed" : "kept");
  }
  const double left = std::exp(chosen[0] - 0.5 * chosen[1]);
  const double right = std::exp(chosen[0] + 0.5 * chosen[1]);
  const double wheelbase = std::exp(chosen[2] + chosen[0]);
  return factors_for_fit(drive::model::Geometry<double>{left, right, wheelbase,
                                                        arc_model ? f.second_wheelbase_mm : 0.0},
                         d);
}

}  // namespace

Outcome run_fit(Context& c) {
  const std::size_t n = c.options.runs.value_or(6);
  const double length_m = c.options.side_m.value_or(1.5);
  c.need_measurements(n, "the fit (" + std::to_string(n) + " runs)");
  c.planned = n;
  FitNominal nominal;
  nominal.wheel_diameter_mm = c.get(ParamId::wheel_diameter_mm);
  nominal.wheelbase_mm = c.get(ParamId::wheelbase_mm);
  nominal.counts_per_rev = c.get(ParamId::counts_per_rev);
  const std::size_t first_run = c.runs.size() + 1;
  RunJury jury(c, nominal,
               fit_geometry_of(geometry_in_force(c.initial, nominal.wheel_diameter_mm)));
  const std::vector<TickLog> logs = drive_fit_runs(c, n, length_m, jury);

  FitOptions options;
  options.seed = c.options.seed;
  options.progress = [&c](const std::string& message) { c.log << "  " << message << "\n"; };
  const FitOutcome fitted = fit_geometry(logs, nominal, options);
  if (!fitted) {
    throw std::runtime_error("fit: " + fitted.error.message + " (nothing applied)");
  }
  const FitResult& result = *fitted.result;
  Outcome outcome;
  // The JSON of `odocal fit` on these logs (noise included): what `odocal ros2 --from` reads.
  const NoiseEstimate noise = noise_for_fit(logs, result, options);
  outcome.result = fit_json(result, noise);
  outcome.text = fit_text(result, noise);
  c.log << outcome.text;
  std::ostringstream text;
  nlohmann::json shown;
  bool any = false;
  const Factors next = fit_choice(result, c.factors(), nominal.wheel_diameter_mm, shown, any, text);
  outcome.result["shown"] = shown;
  // A run the fitted geometry cannot explain as it explains the others (auto's rule): named, so
  // that the owner checks its reading before trusting what is applied.
  std::string named;
  std::vector<auto_plan::SuspectRun> suspects =
      auto_plan::suspect_runs(logs, nominal, result.geometry);
  const std::vector<std::size_t> numbered = jury.runs_in_use();
  for (auto_plan::SuspectRun& s : suspects) {
    s.index = numbered[s.index] + 1 - first_run;  // describe_suspects counts from first_run
  }
  outcome.result["suspect_runs"] = auto_plan::describe_suspects(suspects, c, first_run, named);
  outcome.result["disagreeing_runs"] = jury.record();
  outcome.result["run_checks"] = jury.checks();
  const std::string refusal = implausible_factors(next, c.initial.wheelbase_mm);
  if (!refusal.empty()) {
    throw std::runtime_error(
        "fit: " + refusal + ". Nothing applied: check the wiring (docs/wiring.md) and the " +
        (named.empty() ? std::string("measurements.")
                       : "readings of the runs that disagree with the others: " + named +
                             " (correct them in measurements.csv and --resume)."));
  }
  if (!named.empty()) {
    text << "WARNING: runs that do not agree with the others: " << named
         << ". Check their readings (a heading's sign, a typo): what the fit changes is bent by "
            "them; answer n to the save question, correct them in measurements.csv and "
            "--resume.\n";
  }
  if (!any) {
    text << "The runs show nothing wrong with the geometry in force: nothing changed.\n";
    c.log << text.str();
    outcome.text += text.str();
    return outcome;
  }
  // `fit apply` puts the geometry in force at once with provenance `fit` (docs/console.md), the
  // session's date and its runs.
  if (apply_fit(c, next, text)) {
    outcome.result["f_reset"] = true;
  }
  c.log << text.str();
  outcome.text += text.str();
  outcome.applied = true;
  return outcome;
}

}  // namespace odocal::host::session
