#include "odocal/sim/random.hpp"

#include <cmath>
#include <numbers>

namespace odocal::sim {

std::uint64_t Random::below(std::uint64_t n) {
  if (n <= 1u) {
    return 0u;
  }
  // Reject the top partial block so every residue is equally likely.
  const std::uint64_t limit = (~std::uint64_t{0}) - ((~std::uint64_t{0}) % n);
  std::uint64_t x = next_u64();
  while (x >= limit) {
    x = next_u64();
  }
  return x % n;
}

double Random::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Box–Muller: u1 in (0, 1] so the logarithm is finite.
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

Random Random::derive(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t s = seed ^ 0xD1B54A32D192ED03u;
  const std::uint64_t mixed = random::splitmix64(s);
  s = mixed ^ (index * 0x9E3779B97F4A7C15u);
  return Random(random::splitmix64(s));
}

}  // namespace odocal::sim
