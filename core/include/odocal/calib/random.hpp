#pragma once
/// @file
/// A small deterministic pseudo-random generator for the bootstrap: xoshiro256** seeded through
/// splitmix64. Integer arithmetic only, so one seed gives the same sequence on every compiler,
/// library and machine (std:: distributions do not promise that). No heap, no globals.

#include <cstdint>

namespace odocal::calib {

/// xoshiro256** (Blackman & Vigna): 256-bit state, period 2^256 − 1.
class Random {
 public:
  /// Expands `seed` into the state with splitmix64 (any seed, including 0, is valid).
  explicit Random(std::uint64_t seed);

  /// Next 64 uniformly distributed bits.
  std::uint64_t next();

  /// A uniform integer in [0, bound), bound > 0, without modulo bias (Lemire's multiply-shift
  /// with rejection). Returns 0 when bound is 0.
  std::uint32_t below(std::uint32_t bound);

  /// A uniform double in [0, 1) with 53 random bits.
  double uniform();

  /// A standard normal deviate (Marsaglia polar method); for tests and simulators.
  double normal();

 private:
  std::uint64_t state_[4];
  double spare_normal_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace odocal::calib
