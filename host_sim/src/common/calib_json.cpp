#include "odocal/host/calib_json.hpp"

#include <cmath>
#include <ctime>
#include <stdexcept>

namespace odocal::host {

std::string today_utc() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[16] = {};
  std::strftime(text, sizeof text, "%Y-%m-%d", &utc);
  return text;
}

nlohmann::json provenance_to_json(const Provenance& provenance) {
  nlohmann::json out = {
      {"method", provenance.method},
      {"runs", provenance.runs},
      {"interval", provenance.interval ? nlohmann::json(*provenance.interval) : nullptr},
      {"level", provenance.level ? nlohmann::json(*provenance.level) : nullptr},
      {"date", provenance.date},
  };
  if (provenance.extra.is_object()) {
    for (const auto& [key, value] : provenance.extra.items()) {
      out[key] = value;
    }
  }
  return out;
}

nlohmann::json umbmark_to_json(const calib::UmbmarkResult& r) {
  return {
      {"x_cg_cw", r.x_cg_cw},
      {"y_cg_cw", r.y_cg_cw},
      {"x_cg_ccw", r.x_cg_ccw},
      {"y_cg_ccw", r.y_cg_ccw},
      {"r_cg_cw", r.r_cg_cw},
      {"r_cg_ccw", r.r_cg_ccw},
      {"e_max_syst_mm", r.e_max_syst_mm},
      {"alpha_deg", r.alpha_deg},
      {"beta_deg", r.beta_deg},
      // β = 0: straight legs, infinite radius; JSON has no infinity, so null.
      {"radius_mm", std::isfinite(r.radius_mm) ? nlohmann::json(r.radius_mm) : nullptr},
      {"e_d", r.e_d},
      {"e_b", r.e_b},
      {"c_l", r.c_l},
      {"c_r", r.c_r},
      {"wheelbase_new_mm", r.wheelbase_new_mm},
      {"sem_mm", r.sem_mm},
      {"second_pass_recommended", r.second_pass_recommended},
      {"sigma_mm", r.sigma_mm},
  };
}

nlohmann::json accuracy_to_json(const std::vector<ScenarioAccuracy>& scenarios,
                                const std::string& baseline) {
  nlohmann::json list = nlohmann::json::array();
  for (const ScenarioAccuracy& s : scenarios) {
    list.push_back({
        {"name", s.name},
        {"trials", s.trials},
        {"rms_mm", s.rms_mm},
        {"improvement_pct", s.improvement_pct ? nlohmann::json(*s.improvement_pct) : nullptr},
    });
  }
  nlohmann::json out = {{"scenarios", list}};
  if (!baseline.empty()) {
    out["baseline"] = baseline;
  }
  return out;
}

std::vector<ScenarioAccuracy> compute_accuracy(const std::vector<AccuracyTrial>& trials,
                                               const std::string& baseline) {
  std::vector<std::string> names;
  std::vector<std::vector<calib::EndError>> groups;
  for (const AccuracyTrial& t : trials) {
    std::size_t i = 0;
    while (i < names.size() && names[i] != t.scenario) {
      ++i;
    }
    if (i == names.size()) {
      names.push_back(t.scenario);
      groups.emplace_back();
    }
    groups[i].push_back(t.error);
  }
  if (names.empty()) {
    throw std::invalid_argument("no trials");
  }
  std::vector<ScenarioAccuracy> out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    ScenarioAccuracy s;
    s.name = names[i];
    s.trials = groups[i].size();
    const calib::AccuracyStatus status =
        calib::rms_radial_error(groups[i].data(), groups[i].size(), s.rms_mm);
    if (status != calib::AccuracyStatus::ok) {
      throw std::invalid_argument("scenario '" + names[i] + "': " + calib::to_string(status));
    }
    out.push_back(s);
  }
  const std::string base = baseline.empty() ? names.front() : baseline;
  const ScenarioAccuracy* reference = nullptr;
  for (const ScenarioAccuracy& s : out) {
    if (s.name == base) {
      reference = &s;
    }
  }
  if (reference == nullptr) {
    throw std::invalid_argument("baseline scenario '" + base + "' has no trials");
  }
  const double reference_rms = reference->rms_mm;
  for (ScenarioAccuracy& s : out) {
    double pct = 0.0;
    const calib::AccuracyStatus status = calib::improvement_pct(s.rms_mm, reference_rms, pct);
    if (status == calib::AccuracyStatus::ok) {
      s.improvement_pct = pct;
    } else if (status != calib::AccuracyStatus::bad_baseline || reference_rms != 0.0) {
      // A zero baseline RMS leaves the improvement undefined (null); anything else is an error.
      throw std::invalid_argument("scenario '" + s.name + "': improvement against '" + base +
                                  "': " + calib::to_string(status));
    }
  }
  return out;
}

nlohmann::json lateral_to_json(const calib::LateralResult& result) {
  return {{"f_lat", result.f_lat}, {"f_lon", result.f_lon}, {"theta_l_rad", result.theta_l_rad}};
}

nlohmann::json bootstrap_to_json(const std::vector<calib::BootstrapEstimate>& estimates,
                                 const calib::BootstrapFit& fit) {
  nlohmann::json list = nlohmann::json::array();
  for (const calib::BootstrapEstimate& e : estimates) {
    list.push_back({
        {"lr_l", e.lr_l},
        {"lr_r", e.lr_r},
        {"boot_l", e.boot_l},
        {"boot_r", e.boot_r},
        {"ci_l", {e.ci_l_lo, e.ci_l_hi}},
        {"ci_r", {e.ci_r_lo, e.ci_r_hi}},
        {"r_l", e.r_l_defined ? nlohmann::json(e.r_l) : nullptr},
        {"r_r", e.r_r_defined ? nlohmann::json(e.r_r) : nullptr},
    });
  }
  nlohmann::json psi = nlohmann::json::array();
  for (int row = 0; row < 2; ++row) {
    psi.push_back({fit.psi(row, 0), fit.psi(row, 1), fit.psi(row, 2)});
  }
  return {
      {"unknowns", list},
      {"psi", psi},
      {"residual_scale", fit.residual_scale},
      {"residual_rms", fit.residual_rms},
      {"effective_level", fit.effective_level},
  };
}

nlohmann::json with_provenance(nlohmann::json object, const Provenance& provenance) {
  object["provenance"] = provenance_to_json(provenance);
  return object;
}

}  // namespace odocal::host
