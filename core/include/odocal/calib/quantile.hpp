#pragma once
/// @file
/// The project's one sample quantile and its one Student-t quantile: the bootstrap's intervals
/// (core), the fit's intervals and noise estimate, the Monte Carlo summaries, the lateral and the
/// extended procedures' intervals (host) all take them from here.

#include <cstddef>

namespace odocal::calib {

/// Type-7 sample quantile (linear interpolation between the order statistics at
/// h = probability·(count − 1), R's default) of values[0..count). Reorders the values (partial
/// selection, no allocation). `count` >= 1 and `probability` in [0, 1]; at 0 and 1 it is the
/// minimum and the maximum.
[[nodiscard]] double sample_quantile(double* values, std::size_t count, double probability);

/// Standard normal distribution function Φ(z).
[[nodiscard]] double normal_cdf(double z);

/// Standard normal quantile Φ⁻¹(probability), probability in (0, 1) (Newton's method on Φ,
/// to ~1e-14).
[[nodiscard]] double normal_quantile(double probability);

/// Student-t quantile: the t with P(T_dof <= t) = probability. `probability` in (0, 1); `dof` > 0
/// and need not be whole (Welch and Bell-McCaffrey degrees of freedom are not); +infinity gives
/// the normal quantile. Accurate to ~1e-12 relative: the distribution function from the
/// regularized incomplete beta's continued fraction (Abramowitz & Stegun 26.7.1, 26.5.8),
/// inverted by bisection; from 1e5 degrees of freedom on, the Cornish-Fisher expansion in 1/dof
/// (A&S 26.7.5), whose first omitted term is below 1e-20 there. No allocation; NaN for arguments
/// outside those ranges.
[[nodiscard]] double student_t_quantile(double probability, double dof);

}  // namespace odocal::calib
