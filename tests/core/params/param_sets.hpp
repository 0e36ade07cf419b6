// Parameter sets and a small flash for the parameter store's tests.
#pragma once

#include <cstdint>
#include <random>

#include "odocal/params/param_table.hpp"
#include "odocal/sim/ram_block_store.hpp"

namespace odocal::params::test_sets {

// Small sectors (4 slots each) so the workloads below wrap between A and B many times.
using SmallFlash = sim::StaticRamBlockStore<1024, 4, 4>;

/// A set with every parameter drawn uniformly within its range, and made-up provenance.
inline ParamSet random_set(std::mt19937& rng) {
  ParamSet set = default_params();
  for (std::size_t i = 0; i < param_count; ++i) {
    const auto id = static_cast<ParamId>(i);
    const ParamInfo& info = param_info(id);
    std::uniform_real_distribution<float> pick(info.min, info.max);
    float value = pick(rng);
    if (info.integer) {
      value = static_cast<float>(static_cast<std::uint32_t>(value));
    }
    set.set(id, value);
  }
  set.wheel.method = FactorMethod::umbmark;
  set.wheel.runs = static_cast<std::uint16_t>(rng() % 64u);
  set.wheel.date_unix_s = rng();
  set.wheel.quality_mm = static_cast<float>(rng() % 1000u) * 0.1f;
  set.lateral.method = FactorMethod::manual;
  return set;
}

}  // namespace odocal::params::test_sets
