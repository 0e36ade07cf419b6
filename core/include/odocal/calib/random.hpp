#pragma once
/// @file
/// A small deterministic pseudo-random generator for the bootstrap: the project's one
/// xoshiro256** engine (odocal/random/xoshiro256.hpp) with the bootstrap's distributions. One seed
/// gives the same sequence on every compiler, library and machine. No heap, no globals.

#include <cstdint>

#include "odocal/random/xoshiro256.hpp"

namespace odocal::calib {

/// xoshiro256** (Blackman & Vigna) with bounded integers and normal deviates.
class Random {
 public:
  /// Expands `seed` into the state with splitmix64 (any seed, including 0, is valid).
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  /// Next 64 uniformly distributed bits.
  std::uint64_t next() { return engine_.next_u64(); }

  /// A uniform integer in [0, bound), bound > 0, without modulo bias (Lemire's multiply-shift
  /// with rejection). Returns 0 when bound is 0.
  std::uint32_t below(std::uint32_t bound);

  /// A uniform double in [0, 1) with 53 random bits.
  double uniform() { return engine_.uniform(); }

  /// A standard normal deviate (Marsaglia polar method); for tests and simulators.
  double normal();

 private:
  random::Xoshiro256 engine_;
  double spare_normal_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace odocal::calib
