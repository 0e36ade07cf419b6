#pragma once
/// @file
/// The project's one pseudo-random engine: xoshiro256** (Blackman & Vigna) seeded through
/// splitmix64. Header-only and dependency-free (integer arithmetic, no heap, no globals, no
/// libm), so the core (bootstrap), the simulated plant and the host tools share it while each
/// keeps its own layering: it sits in hal/include, the one include directory every library may
/// use. Integer arithmetic only: one seed gives the same sequence on every compiler, library and
/// machine (std:: distributions do not promise that).
///
/// The distributions built on it (normal deviates, bounded integers) live with their users,
/// because each user's sequences for a seed are part of its contract: `calib::Random` (Lemire
/// bounded integers, Marsaglia polar normals) and `sim::Random` (rejection bounded integers,
/// Box-Muller normals).

#include <cstdint>

namespace odocal::random {

/// One splitmix64 step: advances `state` and returns the next mixed 64-bit value.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  state += 0x9E3779B97F4A7C15u;
  std::uint64_t z = state;
  z = (z ^ (z >> 30u)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27u)) * 0x94D049BB133111EBu;
  return z ^ (z >> 31u);
}

/// xoshiro256**: 256-bit state, period 2^256 − 1. 32 bytes, trivially copyable.
class Xoshiro256 {
 public:
  /// Expands `seed` into the state with splitmix64 (any seed, including 0, is valid).
  constexpr explicit Xoshiro256(std::uint64_t seed = 1u) { reseed(seed); }

  /// Restarts the sequence from `seed`.
  constexpr void reseed(std::uint64_t seed) {
    for (auto& word : state_) {
      word = splitmix64(seed);
    }
  }

  /// Next 64 uniformly distributed bits.
  constexpr std::uint64_t next_u64() {
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

  /// Uniform double in [0, 1) from the top 53 bits of the next value.
  constexpr double uniform() { return static_cast<double>(next_u64() >> 11u) * 0x1.0p-53; }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, unsigned k) {
    return (x << k) | (x >> (64u - k));
  }

  std::uint64_t state_[4] = {0u, 0u, 0u, 0u};
};

}  // namespace odocal::random
