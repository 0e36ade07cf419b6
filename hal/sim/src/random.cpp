#include "odocal/sim/random.hpp"

#include <cmath>

namespace odocal::sim {
namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
  x += 0x9E3779B97F4A7C15u;
  std::uint64_t z = x;
  z = (z ^ (z >> 30u)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27u)) * 0x94D049BB133111EBu;
  return z ^ (z >> 31u);
}

std::uint64_t rotl(std::uint64_t x, unsigned k) {
  return (x << k) | (x >> (64u - k));
}

}  // namespace

void Random::reseed(std::uint64_t seed) {
  std::uint64_t s = seed;
  for (auto& word : state_) {
    word = splitmix64(s);
  }
  has_spare_ = false;
  spare_ = 0.0;
}

std::uint64_t Random::next_u64() {
  const std::uint64_t result = rotl(state_[1] * 5u, 7u) * 9u;
  const std::uint64_t t = state_[1] << 17u;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotl(state_[3], 45u);
  return result;
}

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
  const double angle = 6.283185307179586476925 * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

Random Random::derive(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t s = seed ^ 0xD1B54A32D192ED03u;
  std::uint64_t mixed = splitmix64(s);
  s = mixed ^ (index * 0x9E3779B97F4A7C15u);
  return Random(splitmix64(s));
}

}  // namespace odocal::sim
