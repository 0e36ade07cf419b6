#include "odocal/host/calib_json.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ctime>
#include <map>
#include <set>
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

namespace {

/// 1-based line of the `nth` (1-based) place where `key` is written as an object key; 0 when it
/// is not found as written (e.g. the file spells it with escapes).
std::size_t key_line(const std::string& text, const std::string& key, std::size_t nth) {
  const std::string quoted = '"' + key + '"';
  std::size_t found = 0;
  for (std::size_t pos = text.find(quoted); pos != std::string::npos;
       pos = text.find(quoted, pos + 1)) {
    std::size_t after = pos + quoted.size();
    while (after < text.size() && std::isspace(static_cast<unsigned char>(text[after])) != 0) {
      ++after;
    }
    const bool is_key =
        after < text.size() && text[after] == ':' && (pos == 0 || text[pos - 1] != '\\');
    if (is_key && ++found == nth) {
      return 1u + static_cast<std::size_t>(std::count(
                      text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
    }
  }
  return 0u;
}

}  // namespace

bool parse_json_strict(const std::string& text, nlohmann::json& doc, JsonProblem& problem) {
  // The parser's callback sees every key as it is read, in document order: one set of keys per
  // open object finds a key given twice in the same object, and the last key read names the value
  // whose number overflows.
  std::vector<std::set<std::string>> open_objects;
  std::map<std::string, std::size_t> occurrences;
  std::string duplicate;
  std::size_t duplicate_nth = 0;
  std::string last_key;
  const nlohmann::json::parser_callback_t watch = [&](int, nlohmann::json::parse_event_t event,
                                                      nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::object_start) {
      open_objects.emplace_back();
    } else if (event == nlohmann::json::parse_event_t::object_end && !open_objects.empty()) {
      open_objects.pop_back();
    } else if (event == nlohmann::json::parse_event_t::key && parsed.is_string()) {
      last_key = parsed.get<std::string>();
      const std::size_t nth = ++occurrences[last_key];
      if (!open_objects.empty() && !open_objects.back().insert(last_key).second &&
          duplicate.empty()) {
        duplicate = last_key;
        duplicate_nth = nth;
      }
    }
    return true;
  };
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos) {
    // The parser would stop there and report an early end of input.
    problem.line = 1u + static_cast<std::size_t>(std::count(
                            text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n'));
    problem.message = "contains a NUL byte (a binary file, or a text file in UTF-16?)";
    return false;
  }
  nlohmann::json parsed;
  try {
    parsed = nlohmann::json::parse(text, watch);
  } catch (const nlohmann::json::out_of_range&) {
    problem.key = last_key;
    problem.line = last_key.empty() ? 0u : key_line(text, last_key, occurrences[last_key]);
    problem.message = "number out of range (beyond +-1.8e308)";
    return false;
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is the 1-based offset of the fault: count the lines before it.
    const std::size_t end = std::min<std::size_t>(e.byte > 0 ? e.byte - 1u : 0u, text.size());
    problem.line = 1u + static_cast<std::size_t>(std::count(
                            text.begin(), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
    // Drop the library's "[json.exception.parse_error.101] " tag.
    std::string what = e.what();
    const std::size_t tag = what.find("] ");
    problem.message =
        "not valid JSON: " + (tag == std::string::npos ? what : what.substr(tag + 2u));
    return false;
  } catch (const nlohmann::json::exception& e) {
    problem.message = std::string("not valid JSON: ") + e.what();
    return false;
  }
  if (!duplicate.empty()) {
    problem.key = duplicate;
    problem.line = key_line(text, duplicate, duplicate_nth);
    problem.message = "given more than once (only one value per key is taken)";
    return false;
  }
  doc = std::move(parsed);
  return true;
}

nlohmann::json with_provenance(nlohmann::json object, const Provenance& provenance) {
  object["provenance"] = provenance_to_json(provenance);
  return object;
}

}  // namespace odocal::host
