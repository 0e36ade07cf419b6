#include "odocal/console/kept_trials.hpp"

namespace odocal::console {
namespace {

// Out of line: one copy of the 64-bit compares for both wheels.
[[gnu::noinline]] std::int32_t saturate(std::int64_t counts) {
  constexpr std::int64_t top = 2147483647;
  return static_cast<std::int32_t>(counts > top ? top : (counts < -top ? -top : counts));
}

}  // namespace

void KeptTrials::push(const drive::TrialRecord& record) {
  // The slot after the newest; when full, that is the oldest's, and the next one becomes oldest.
  std::size_t slot = first_;
  if (count_ < capacity) {
    slot = (first_ + count_) % capacity;
    ++count_;
  } else {
    first_ = static_cast<std::uint8_t>((first_ + 1u) % capacity);
  }
  // Written in place, field by field (no zeroed copy first).
  KeptTrial& kept = records_[slot];
  kept.number = record.number;
  kept.duration_ms = record.duration_ms;
  kept.count_l = saturate(record.count_l);
  kept.count_r = saturate(record.count_r);
  kept.length_m = record.length_m;
  kept.end = record.end;
  kept.path = record.path;
}

const KeptTrial& KeptTrials::at(std::size_t i) const {
  return records_[(first_ + (i < count_ ? i : 0u)) % capacity];
}

const KeptTrial* KeptTrials::find(std::uint32_t number) const {
  for (std::size_t i = 0; i < count_; ++i) {
    if (at(i).number == number) {
      return &at(i);
    }
  }
  return nullptr;
}

}  // namespace odocal::console
