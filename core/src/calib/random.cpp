#include "odocal/calib/random.hpp"

#include <cmath>

namespace odocal::calib {

std::uint32_t Random::below(std::uint32_t bound) {
  if (bound == 0u) {
    return 0u;
  }
  // Lemire: the high word of a 32x32 product is uniform once the low word's biased zone is
  // rejected; the threshold is 2^32 mod bound.
  std::uint64_t product = static_cast<std::uint64_t>(next() >> 32) * bound;
  auto low = static_cast<std::uint32_t>(product);
  if (low < bound) {
    const std::uint32_t threshold = static_cast<std::uint32_t>(-bound) % bound;
    while (low < threshold) {
      product = static_cast<std::uint64_t>(next() >> 32) * bound;
      low = static_cast<std::uint32_t>(product);
    }
  }
  return static_cast<std::uint32_t>(product >> 32);
}

double Random::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_normal_;
  }
  double u = 0.0;
  double v = 0.0;
  double s = 0.0;
  do {
    u = 2.0 * uniform() - 1.0;
    v = 2.0 * uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_normal_ = v * factor;
  has_spare_ = true;
  return u * factor;
}

}  // namespace odocal::calib
