#pragma once
/// @file
/// The project's one sample quantile: the bootstrap's intervals (core), the fit's intervals and
/// noise estimate, and the Monte Carlo summaries (host) all take it from here.

#include <cstddef>

namespace odocal::calib {

/// Type-7 sample quantile (linear interpolation between the order statistics at
/// h = probability·(count − 1), R's default) of values[0..count). Reorders the values (partial
/// selection, no allocation). `count` >= 1 and `probability` in [0, 1]; at 0 and 1 it is the
/// minimum and the maximum.
[[nodiscard]] double sample_quantile(double* values, std::size_t count, double probability);

}  // namespace odocal::calib
