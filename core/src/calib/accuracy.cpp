#include "odocal/calib/accuracy.hpp"

#include <cmath>

namespace odocal::calib {

const char* to_string(AccuracyStatus status) {
  switch (status) {
    case AccuracyStatus::ok:
      return "ok";
    case AccuracyStatus::no_trials:
      return "no trials";
    case AccuracyStatus::non_finite:
      return "a trial error is NaN or infinite";
    case AccuracyStatus::bad_baseline:
      return "baseline RMS must be finite and > 0";
  }
  return "unknown status";
}

AccuracyStatus rms_radial_error(const EndError* trials, std::size_t count, double& rms_mm) {
  if (trials == nullptr || count == 0) {
    return AccuracyStatus::no_trials;
  }
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(trials[i].x_mm) || !std::isfinite(trials[i].y_mm)) {
      return AccuracyStatus::non_finite;
    }
    // r² = x² + y² (Maddahi Tables 3-4, r_e); RMS over the trials.
    sum_sq += trials[i].x_mm * trials[i].x_mm + trials[i].y_mm * trials[i].y_mm;
  }
  rms_mm = std::sqrt(sum_sq / static_cast<double>(count));
  return AccuracyStatus::ok;
}

AccuracyStatus improvement_pct(double rms_mm, double baseline_rms_mm, double& percent) {
  if (!std::isfinite(rms_mm)) {
    return AccuracyStatus::non_finite;
  }
  if (!std::isfinite(baseline_rms_mm) || baseline_rms_mm <= 0.0) {
    return AccuracyStatus::bad_baseline;
  }
  percent = 100.0 * (1.0 - rms_mm / baseline_rms_mm);  // k_I of Tables 3 and 4, as a reduction
  return AccuracyStatus::ok;
}

}  // namespace odocal::calib
