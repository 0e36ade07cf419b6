#pragma once
/// @file
/// Positional accuracy of a set of trials (Maddahi & Zareinia, Tables 3 and 4): RMS of the radial
/// end error r = sqrt(x² + y²) and the improvement against a baseline scenario.
/// Hardware-free, no heap.

#include <cstddef>
#include <cstdint>

namespace odocal::calib {

/// End-point error of one trial, mm (desired minus reached, or the reverse: only |r| matters).
struct EndError {
  double x_mm = 0.0;
  double y_mm = 0.0;
};

/// Why an accuracy figure was refused. Nothing is written unless `ok`.
enum class AccuracyStatus : std::uint8_t {
  ok,
  no_trials,     ///< zero trials
  non_finite,    ///< a NaN or Inf in a trial, or a result that would not be finite
  bad_baseline,  ///< baseline RMS not finite or not > 0
};

/// A short lower-case message for a status.
[[nodiscard]] const char* to_string(AccuracyStatus status);

/// RMS of the radial errors: sqrt(mean(x² + y²)), mm. Computed with hypot and relative to the
/// largest error, so it is finite for any finite errors (no overflow of x²).
[[nodiscard]] AccuracyStatus rms_radial_error(const EndError* trials, std::size_t count,
                                              double& rms_mm);

/// Improvement against a baseline, percent: 100·(1 − rms/rms_baseline) (Tables 3 and 4, k_I).
/// Negative when the scenario is worse than the baseline. `bad_baseline` when the baseline RMS
/// is 0 (nothing to improve on: the caller reports "no figure", not 0 %); `non_finite` when the
/// ratio overflows.
[[nodiscard]] AccuracyStatus improvement_pct(double rms_mm, double baseline_rms_mm,
                                             double& percent);

}  // namespace odocal::calib
