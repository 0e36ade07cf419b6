#pragma once
/// @file
/// JSON of calibration results, exactly as `odocal umbmark|accuracy|lateral|bootstrap --json`
/// print them (DESIGN "Host program odocal"); the simulated procedures reuse these so that
/// `odocal sim` objects match the contract keys.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/calib/accuracy.hpp"
#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/calib/umbmark.hpp"

namespace odocal::host {

/// How a result was obtained; printed under the key `provenance`.
struct Provenance {
  std::string method;    ///< e.g. "umbmark", "umbmark-exact", "maddahi-eq4-5", "bootstrap"
  std::size_t runs = 0;  ///< measurements used (runs, trials or training rows)
  std::optional<std::string> interval;  ///< interval method, if the result has intervals
  std::optional<double> level;          ///< interval level, if any
  std::string date;                     ///< ISO date, YYYY-MM-DD (`--date` or today, UTC)
  nlohmann::json extra = nlohmann::json::object();  ///< method-specific details (seed, B, ...)
};

/// Today's date, UTC, YYYY-MM-DD.
[[nodiscard]] std::string today_utc();

/// `{method, runs, interval, level, date, ...extra}` (interval/level null when absent).
[[nodiscard]] nlohmann::json provenance_to_json(const Provenance& provenance);

/// The `odocal umbmark` object: keys x_cg_cw y_cg_cw x_cg_ccw y_cg_ccw r_cg_cw r_cg_ccw
/// e_max_syst_mm alpha_deg beta_deg radius_mm e_d e_b c_l c_r wheelbase_new_mm sem_mm
/// second_pass_recommended (plus sigma_mm). `radius_mm` is null when β = 0 (straight legs,
/// infinite radius). No provenance: add it with `with_provenance`.
[[nodiscard]] nlohmann::json umbmark_to_json(const calib::UmbmarkResult& result);

/// One scenario of an accuracy report.
struct ScenarioAccuracy {
  std::string name;
  std::size_t trials = 0;
  double rms_mm = 0.0;
  /// 100·(1 − rms/rms_baseline); empty (JSON null) when the baseline RMS is 0, so there is
  /// nothing to improve on.
  std::optional<double> improvement_pct;
};

/// `{"scenarios": [{name, trials, rms_mm, improvement_pct}, ...]}` in the given order
/// (plus "baseline": NAME when `baseline` is not empty).
[[nodiscard]] nlohmann::json accuracy_to_json(const std::vector<ScenarioAccuracy>& scenarios,
                                              const std::string& baseline = {});

/// One trial of an accuracy report.
struct AccuracyTrial {
  std::string scenario;
  calib::EndError error;
};

/// Groups trials by scenario (first-appearance order), computes each RMS and the improvement
/// against `baseline` (default: the first scenario); a baseline RMS of 0 leaves every
/// improvement empty. Throws std::invalid_argument when `baseline` names no scenario, or a
/// scenario's figures cannot be computed or are not finite (the message says why).
[[nodiscard]] std::vector<ScenarioAccuracy> compute_accuracy(
    const std::vector<AccuracyTrial>& trials, const std::string& baseline = {});

/// `{"f_lat": .., "f_lon": .., "theta_l_rad": ..}`.
[[nodiscard]] nlohmann::json lateral_to_json(const calib::LateralResult& result);

/// `{"unknowns": [{lr_l, lr_r, boot_l, boot_r, ci_l:[lo,hi], ci_r:[lo,hi], r_l, r_r}, ...],
///   (r_l / r_r null where the ratio is undefined: that wheel's LR estimate is 0)
///   "psi": [[..3..],[..3..]], "residual_scale": .., "effective_level": ..}`.
[[nodiscard]] nlohmann::json bootstrap_to_json(
    const std::vector<calib::BootstrapEstimate>& estimates, const calib::BootstrapFit& fit);

/// Why JSON text was refused.
struct JsonProblem {
  std::size_t line = 0;  ///< 1-based line of the fault, 0 when it cannot be told
  std::string key;       ///< the key at fault, empty when the fault is not in one value
  std::string message;   ///< what is wrong, in the project's words
};

/// Parses JSON text strictly, for every JSON file a host program reads: refuses a key given twice
/// in one object (nlohmann would keep the last one silently), and names the key whose number is
/// beyond a double instead of passing on the library's exception text. False (and `problem`
/// filled) when the text is refused; `doc` is set only on success.
[[nodiscard]] bool parse_json_strict(const std::string& text, nlohmann::json& doc,
                                     JsonProblem& problem);

/// Copies `object` and adds `provenance`.
[[nodiscard]] nlohmann::json with_provenance(nlohmann::json object, const Provenance& provenance);

}  // namespace odocal::host
