#pragma once
/// @file
/// Deterministic random numbers for the simulated robot: the project's one xoshiro256** engine
/// (odocal/random/xoshiro256.hpp) with the simulator's distributions. The same seed gives the
/// same sequence on every machine and compiler (no std:: distributions, whose algorithms are
/// unspecified).

#include <cstdint>

#include "odocal/random/xoshiro256.hpp"

namespace odocal::sim {

/// xoshiro256** generator (Blackman & Vigna), seeded through splitmix64, with uniform, bounded
/// and normal deviates. No heap.
class Random {
 public:
  /// Seeds the generator; any 64-bit value (including 0) gives a valid state.
  explicit Random(std::uint64_t seed = 1u) { reseed(seed); }

  /// Restarts the sequence from `seed`.
  void reseed(std::uint64_t seed) {
    engine_.reseed(seed);
    has_spare_ = false;
    spare_ = 0.0;
  }

  /// Next 64 random bits.
  std::uint64_t next_u64() { return engine_.next_u64(); }

  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return engine_.uniform(); }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Uniform integer in [0, n) (n > 0), by rejection so that it carries no modulo bias.
  std::uint64_t below(std::uint64_t n);

  /// Standard normal N(0, 1) by the Box–Muller transform (the second value of each pair is kept
  /// for the next call).
  double normal();

  /// Normal with mean 0 and standard deviation `sigma`.
  double normal(double sigma) { return sigma * normal(); }

  /// An independent generator for a sub-task (e.g. robot `index` of a Monte Carlo run): its seed
  /// is derived from this generator's seed and `index`, so the order of derivation does not matter.
  [[nodiscard]] static Random derive(std::uint64_t seed, std::uint64_t index);

 private:
  random::Xoshiro256 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace odocal::sim
