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
      return "a trial error or the result is NaN or infinite";
    case AccuracyStatus::bad_baseline:
      return "baseline RMS must be finite and > 0";
  }
  return "unknown status";
}

AccuracyStatus rms_radial_error(const EndError* trials, std::size_t count, double& rms_mm) {
  if (trials == nullptr || count == 0) {
    return AccuracyStatus::no_trials;
  }
  // r = hypot(x, y) (Maddahi Tables 3-4, r_e) cannot overflow where x² + y² would; the squares
  // are summed relative to the largest r, so the RMS is finite whenever every r is.
  double largest = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double r = std::hypot(trials[i].x_mm, trials[i].y_mm);
    if (!std::isfinite(trials[i].x_mm) || !std::isfinite(trials[i].y_mm) || !std::isfinite(r)) {
      return AccuracyStatus::non_finite;
    }
    largest = r > largest ? r : largest;
  }
  if (largest == 0.0) {
    rms_mm = 0.0;
    return AccuracyStatus::ok;
  }
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double ratio = std::hypot(trials[i].x_mm, trials[i].y_mm) / largest;
    sum_sq += ratio * ratio;
  }
  const double rms = largest * std::sqrt(sum_sq / static_cast<double>(count));
  if (!std::isfinite(rms)) {
    return AccuracyStatus::non_finite;
  }
  rms_mm = rms;
  return AccuracyStatus::ok;
}

AccuracyStatus improvement_pct(double rms_mm, double baseline_rms_mm, double& percent) {
  if (!std::isfinite(rms_mm)) {
    return AccuracyStatus::non_finite;
  }
  if (!std::isfinite(baseline_rms_mm) || baseline_rms_mm <= 0.0) {
    return AccuracyStatus::bad_baseline;
  }
  // k_I of Tables 3 and 4, as a reduction; the ratio overflows for a tiny baseline.
  const double value = 100.0 * (1.0 - rms_mm / baseline_rms_mm);
  if (!std::isfinite(value)) {
    return AccuracyStatus::non_finite;
  }
  percent = value == 0.0 ? 0.0 : value;  // never -0
  return AccuracyStatus::ok;
}

}  // namespace odocal::calib
