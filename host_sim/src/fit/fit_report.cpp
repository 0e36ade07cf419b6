// `odocal fit`: the result as JSON (contract keys) and as text, with the noise estimate beside it.

#include <cstdio>
#include <sstream>

#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"

namespace odocal::host {
namespace {

nlohmann::json figures_json(const FitFigures& f) {
  return {{"runs", f.runs},
          {"end_rms_before_mm", f.end_rms_before_mm},
          {"end_rms_after_mm", f.end_rms_after_mm},
          {"path_rms_before_mm", f.path_rms_before_mm},
          {"path_rms_after_mm", f.path_rms_after_mm}};
}

nlohmann::json interval_json(const std::optional<FitInterval>& i) {
  if (!i) {
    return nullptr;
  }
  return nlohmann::json::array({i->lo, i->hi});
}

std::string line(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, fmt, a, b, c, d);
  return text;
}

std::string figures_text(const char* what, const FitFigures& f) {
  char text[256];
  std::snprintf(text, sizeof text,
                "  %-8s %3zu %-4s: end RMS %8.2f -> %8.2f mm, path RMS %8.2f -> %8.2f mm\n", what,
                f.runs, f.runs == 1 ? "run" : "runs", f.end_rms_before_mm, f.end_rms_after_mm,
                f.path_rms_before_mm, f.path_rms_after_mm);
  return text;
}

}  // namespace

const char* interval_name(FitIntervalMethod method) {
  switch (method) {
    case FitIntervalMethod::wild_t:
      return "wild-bootstrap-t";
    case FitIntervalMethod::student_t:
      return "student-t";
    case FitIntervalMethod::percentile:
      return "percentile";
  }
  return "?";
}

nlohmann::json fit_result_json(const FitResult& r) {
  nlohmann::json j;
  j["wheel_diameter_left_mm"] = r.geometry.wheel_diameter_left_mm;
  j["wheel_diameter_right_mm"] = r.geometry.wheel_diameter_right_mm;
  j["wheelbase_mm"] = r.geometry.wheelbase_mm;
  j["c_l"] = r.c_l;
  j["c_r"] = r.c_r;
  j["e_d"] = r.e_d;
  j["e_b"] = r.e_b;
  j["ci"] = {{"wheel_diameter_left_mm", interval_json(r.ci_left_mm)},
             {"wheel_diameter_right_mm", interval_json(r.ci_right_mm)},
             {"wheelbase_mm", interval_json(r.ci_wheelbase_mm)},
             {"c_l", interval_json(r.ci_c_l)},
             {"c_r", interval_json(r.ci_c_r)}};
  if (r.geometry.model != FitModelKind::one_wheelbase) {
    const char* name = r.geometry.model == FitModelKind::arc_wheelbase ? "wheelbase_arc_mm"
                                                                       : "wheelbase_at_1radps_mm";
    j[name] = r.geometry.second_wheelbase_mm;
    j["ci"][name] = interval_json(r.ci_second_wheelbase_mm);
  }
  nlohmann::json candidates = nlohmann::json::array();
  for (const FitCandidate& c : r.model.candidates) {
    candidates.push_back({{"name", model_name(c.kind)},
                          {"tried", c.tried},
                          {"supported", c.supported},
                          {"heldout_path_rms_mm", c.tried ? nlohmann::json(c.heldout_path_rms_mm)
                                                          : nlohmann::json(nullptr)},
                          {"folds", c.folds},
                          {"note", c.note}});
  }
  j["model"] = {
      {"name", model_name(r.model.kind)},
      {"reason", r.model.reason},
      {"left_out", r.model.unit.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.model.unit)},
      {"candidates", candidates}};
  if (r.lag) {
    const int np = r.geometry.model == FitModelKind::one_wheelbase ? 3 : 4;
    const char* names[4] = {"wheel_diameter_left_mm", "wheel_diameter_right_mm", "wheelbase_mm",
                            r.geometry.model == FitModelKind::arc_wheelbase
                                ? "wheelbase_arc_mm"
                                : "wheelbase_at_1radps_mm"};
    nlohmann::json per = nlohmann::json::object();
    nlohmann::json at = nlohmann::json::object();
    for (int i = 0; i < np; ++i) {
      per[names[i]] = r.lag->per_50ms[i];
      at[names[i]] = r.lag->geometry_at_estimate[i];
    }
    j["time_lag"] = {{"estimate_s", r.lag->estimate_s},
                     {"per_50ms", per},
                     {"at_estimate", at},
                     {"within_intervals", r.lag->within_intervals}};
  } else {
    j["time_lag"] = nullptr;
  }
  j["fit"] = figures_json(r.fit);
  j["holdout"] = r.holdout ? figures_json(*r.holdout) : nlohmann::json(nullptr);
  j["nominal"] = {{"wheel_diameter_mm", r.nominal.wheel_diameter_mm},
                  {"wheelbase_mm", r.nominal.wheelbase_mm},
                  {"counts_per_rev", r.nominal.counts_per_rev}};
  j["bootstrap"] = {{"replicates", r.replicates},
                    {"units", r.bootstrap_units},
                    {"clusters", r.clusters},
                    {"redrawn", r.redrawn},
                    {"level", r.level},
                    {"seed", r.seed},
                    {"interval", interval_name(r.interval)},
                    {"widen", r.widen},
                    {"sd",
                     {{"wheel_diameter_left_mm", r.cluster_sd[0]},
                      {"wheel_diameter_right_mm", r.cluster_sd[1]},
                      {"wheelbase_mm", r.cluster_sd[2]}}},
                    {"dof",
                     {{"wheel_diameter_left_mm", r.dof[0]},
                      {"wheel_diameter_right_mm", r.dof[1]},
                      {"wheelbase_mm", r.dof[2]}}}};
  j["relative_sd"] = {{"wheel_diameter_left_mm", r.relative_sd[0]},
                      {"wheel_diameter_right_mm", r.relative_sd[1]},
                      {"wheelbase_mm", r.relative_sd[2]}};
  if (r.geometry.model != FitModelKind::one_wheelbase) {
    j["relative_sd"][r.geometry.model == FitModelKind::arc_wheelbase ? "wheelbase_arc_mm"
                                                                     : "wheelbase_at_1radps_mm"] =
        r.relative_sd[3];
  }
  j["heading_length_mm"] = r.heading_length_mm;
  const FitWeighting& w = r.weighting;
  const auto estimate = [&](double v) { return w.estimated ? nlohmann::json(v) : nullptr; };
  j["weighting"] = {{"method", w.estimated ? "estimated" : "fixed"},
                    {"heading_length_mm", w.heading_length_mm},
                    {"runs", w.runs},
                    {"position_sd_mm", estimate(w.position_sd_mm)},
                    {"heading_sd_deg", estimate(w.heading_sd_deg)},
                    {"position_dof", estimate(w.position_dof)},
                    {"heading_dof", estimate(w.heading_dof)},
                    {"reason", w.reason}};
  j["warnings"] = r.warnings;
  j["iterations"] = r.iterations;
  return j;
}

std::string fit_result_text(const FitResult& r) {
  std::ostringstream out;
  out << line("Geometry fitted to the logs (nominal D %.3f mm, b %.3f mm, %.6g counts/rev)\n",
              r.nominal.wheel_diameter_mm, r.nominal.wheelbase_mm, r.nominal.counts_per_rev);
  const auto row = [&](const char* name, double value, const std::optional<FitInterval>& ci,
                       const char* unit) {
    char text[128];
    std::snprintf(text, sizeof text, "  %-24s %12.5f %-2s", name, value, unit);
    std::string shown = text;
    shown.erase(ci ? shown.size() : shown.find_last_not_of(' ') + 1);
    out << shown;
    if (ci) {
      out << line("   %.0f %% interval [%.5f, %.5f]", 100.0 * r.level, ci->lo, ci->hi);
    }
    out << '\n';
  };
  row("wheel_diameter_left_mm", r.geometry.wheel_diameter_left_mm, r.ci_left_mm, "mm");
  row("wheel_diameter_right_mm", r.geometry.wheel_diameter_right_mm, r.ci_right_mm, "mm");
  row("wheelbase_mm", r.geometry.wheelbase_mm, r.ci_wheelbase_mm, "mm");
  if (r.geometry.model == FitModelKind::arc_wheelbase) {
    row("wheelbase_arc_mm", r.geometry.second_wheelbase_mm, r.ci_second_wheelbase_mm, "mm");
  } else if (r.geometry.model == FitModelKind::turn_rate_wheelbase) {
    row("wheelbase_at_1radps_mm", r.geometry.second_wheelbase_mm, r.ci_second_wheelbase_mm, "mm");
  }
  row("c_l", r.c_l, r.ci_c_l, "");
  row("c_r", r.c_r, r.ci_c_r, "");
  row("e_d", r.e_d, std::nullopt, "");
  row("e_b", r.e_b, std::nullopt, "");
  if (r.replicates > 0) {
    out << "  bootstrap: B = " << r.replicates << " over " << r.bootstrap_units << " "
        << (r.clusters == "set" ? "data set(s)" : "unit(s)") << ", seed " << r.seed << ", "
        << interval_name(r.interval) << " intervals";
    if (r.interval == FitIntervalMethod::percentile) {
      out << line(" widened x%.3f (small sample)\n", r.widen);
    } else {
      out << line(" (degrees of freedom %.1f, %.1f, %.1f)\n", r.dof[0], r.dof[1], r.dof[2]);
    }
  } else if (r.bootstrap_units > 0) {
    out << "  no intervals: a single run shows no scatter between runs (give more runs)\n";
  } else {
    out << "  no bootstrap (B = 0): no intervals\n";
  }
  if (r.weighting.estimated) {
    out << line("Weighting: heading x %.1f mm/rad = position noise %.3g mm / heading noise %.3g°",
                r.weighting.heading_length_mm, r.weighting.position_sd_mm,
                r.weighting.heading_sd_deg)
        << " (" << r.weighting.reason << ")\n";
  } else if (!r.weighting.reason.empty()) {
    out << "Weighting: " << r.weighting.reason << '\n';
  }
  for (const std::string& warning : r.warnings) {
    out << "Warning: " << warning << '\n';
  }
  out << "Model: " << model_name(r.model.kind) << " (" << r.model.reason << ")\n";
  for (const FitCandidate& c : r.model.candidates) {
    out << "  " << model_name(c.kind) << ": "
        << (c.tried ? line("held-out path RMS %.2f mm", c.heldout_path_rms_mm) : "")
        << (c.tried && !c.note.empty() ? "; " : "") << c.note << '\n';
  }
  if (r.lag) {
    out << line(
               "Time lag of the counts behind the ground truth: %+.3f s (diameters move "
               "%+.3f / %+.3f mm",
               r.lag->estimate_s, r.lag->per_50ms[0], r.lag->per_50ms[1])
        << line(", the wheelbase %+.3f mm per +50 ms)\n", r.lag->per_50ms[2])
        << (r.lag->within_intervals ? ""
                                    : "  warning: corrected for that lag the fit leaves its "
                                      "intervals: check the clocks of counts and ground truth\n");
  }
  out << "Accuracy, nominal -> fitted geometry:\n";
  out << figures_text("fit", r.fit);
  if (r.holdout) {
    out << figures_text("holdout", *r.holdout);
  } else {
    out << "  holdout  none (give --holdout FILE... to test the fit on runs it has not seen)\n";
  }
  out << "Firmware: set c_l " << line("%.6f", r.c_l) << ", set c_r " << line("%.6f", r.c_r)
      << ", set wheelbase_mm " << line("%.4f", r.geometry.wheelbase_mm) << '\n';
  if (r.geometry.model == FitModelKind::arc_wheelbase) {
    out << "  (wheelbase_mm is the turn-in-place wheelbase; on an arc of radius R the robot turns "
           "with b + w·(b_arc − b), w = R/(R + b/2): set wheelbase_arc_mm "
        << line("%.4f", r.geometry.second_wheelbase_mm)
        << " too, or 'fit apply c_l c_r b 0 0 arc b_arc' (docs/console.md))\n";
  }
  return out.str();
}

NoiseEstimate noise_for_fit(const std::vector<TickLog>& runs, const FitResult& fit,
                            const FitOptions& options) {
  NoiseOptions noise_options;
  noise_options.seed = options.seed;
  noise_options.level = options.level;
  // The measurement noise's shape is the fixed one (a tape measure's 2 mm against 0.4°): the
  // noise model tells measurement from drift itself, whatever weighting the geometry was fitted
  // with.
  noise_options.heading_length_mm = options.heading_length_mm;
  noise_options.replicates = options.replicates > 0u ? noise_options.replicates : 0u;
  return estimate_wheel_noise(runs, fit.nominal, fit.geometry, noise_options);
}

nlohmann::json fit_json(const FitResult& fit, const NoiseEstimate& noise) {
  nlohmann::json j = fit_result_json(fit);
  j["noise"] = noise_json(noise);
  return j;
}

std::string fit_text(const FitResult& fit, const NoiseEstimate& noise) {
  return fit_result_text(fit) + noise_text(noise);
}

}  // namespace odocal::host
