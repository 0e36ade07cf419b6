#include "odocal/calib/quantile.hpp"

#include <algorithm>
#include <cmath>

namespace odocal::calib {

double sample_quantile(double* values, std::size_t count, double probability) {
  const double h = probability * static_cast<double>(count - 1);
  const auto below = static_cast<std::size_t>(std::floor(h));
  std::nth_element(values, values + below, values + count);
  const double low = values[below];
  if (below + 1 >= count) {
    return low;
  }
  const double high = *std::min_element(values + below + 1, values + count);
  return low + (h - static_cast<double>(below)) * (high - low);
}

}  // namespace odocal::calib
