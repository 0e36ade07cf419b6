#pragma once
/// @file
/// The trials the console keeps for `trial` / `trials` / `lateral add`: the last 32, in a compact
/// form (36 bytes each instead of drive::TrialRecord's 48). Main-loop only; no heap.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/drive/trial.hpp"

namespace odocal::console {

/// One kept trial. The counts are 32-bit: a trial that moves a wheel by more than
/// ±2,147,483,647 counts (e.g. a 10-minute drive at 100 rad/s with a 10^6-count encoder)
/// saturates there instead of wrapping.
struct KeptTrial {
  std::uint32_t number = 0u;       ///< as drive::TrialRecord
  std::uint32_t duration_ms = 0u;  ///< as drive::TrialRecord
  std::int32_t count_l = 0;        ///< signed counts moved, left wheel, saturating
  std::int32_t count_r = 0;        ///< right wheel
  float length_m = 0.0f;           ///< the path's length argument
  drive::Pose end{};               ///< odometry pose at the end
  drive::PathId path = drive::PathId::none;
};

/// The last `capacity` trials, oldest first. Main-loop only.
class KeptTrials {
 public:
  static constexpr std::size_t capacity = 32u;

  /// Keeps `record` (its counts saturated to 32 bits), dropping the oldest when full.
  void push(const drive::TrialRecord& record);
  /// Forgets every kept trial (numbers go on).
  void clear() { count_ = 0u; }
  [[nodiscard]] std::size_t size() const { return count_; }
  /// The i-th kept trial, oldest first (i < size()). Out of line: three callers.
  [[nodiscard, gnu::noinline]] const KeptTrial& at(std::size_t i) const;
  /// The kept trial numbered `number`; nullptr when it is not kept.
  [[nodiscard]] const KeptTrial* find(std::uint32_t number) const;
  /// The newest kept trial; nullptr when none.
  [[nodiscard]] const KeptTrial* latest() const {
    return count_ == 0u ? nullptr : &at(count_ - 1u);
  }

 private:
  std::array<KeptTrial, capacity> records_{};
  std::uint8_t first_ = 0u;
  std::uint8_t count_ = 0u;
};

}  // namespace odocal::console
