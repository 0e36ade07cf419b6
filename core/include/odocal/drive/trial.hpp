#pragma once
/// @file
/// Trials: every motion that ends by itself (a path, or a `drive` with a duration), recorded from
/// its start to the end of its settling, with the encoder counts it moved and where odometry says
/// it ended. The tick records them (`TrialRecorder`); the main loop keeps the last few
/// (`TrialLog`). Both hardware-free, no heap.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/odometry.hpp"

namespace odocal::drive {

/// One finished trial.
struct TrialRecord {
  std::uint32_t number = 0u;       ///< 1, 2, ... since start-up; 0 = no trial yet
  PathId path = PathId::none;      ///< the path run, or PathId::drive for a timed drive
  float length_m = 0.0f;           ///< the path's length argument (line length, square side); 0
  std::uint32_t duration_ms = 0u;  ///< from the command taking effect to the end of settling
  std::int64_t count_l = 0;        ///< signed encoder counts moved during the trial, left wheel
  std::int64_t count_r = 0;        ///< right wheel
  Pose end{};                      ///< odometry pose at the end (as `odom` gives it)
};

/// Records trials in the tick. Tick context only.
///
/// A trial begins when a path or a timed drive takes effect and is abandoned by `stop`, another
/// motion command or a fault. When the motion ends by itself the trial stays open until both
/// wheels have moved no count for `still_ms` (the robot has come to rest), or at most
/// `max_settle_ms` after the motion ended, then closes.
class TrialRecorder {
 public:
  static constexpr std::uint32_t max_settle_ms = 3000u;

  /// A trial starts: @param counts_l, counts_r wide positions now; @param length_m its argument.
  [[gnu::noinline]] void begin(PathId path, float length_m, std::int64_t counts_l,
                               std::int64_t counts_r);
  /// The motion was abandoned: no trial is recorded.
  void abandon() { phase_ = Phase::none; }
  /// One tick. @param moving true while the path or drive still commands motion; @param dt_us the
  /// tick period; @param still_ms how long both wheels must be still after the motion.
  /// @return true when the trial closed this tick (then `last()` holds it).
  bool update(bool moving, std::int64_t counts_l, std::int64_t counts_r, const Pose& pose,
              std::uint32_t dt_us, float still_ms);
  /// The same, taking the end pose from `odometry` only when the trial closes (the tick's way:
  /// the heading's atan2 is not worth paying every tick).
  bool update(bool moving, std::int64_t counts_l, std::int64_t counts_r, const Odometry& odometry,
              std::uint32_t dt_us, float still_ms);

  /// True from `begin` until the trial closes or is abandoned.
  [[nodiscard]] bool open() const { return phase_ != Phase::none; }
  /// The last closed trial (number 0 before the first).
  [[nodiscard]] const TrialRecord& last() const { return last_; }

 private:
  enum class Phase : std::uint8_t { none, moving, settling };

  /// One tick's bookkeeping; true when the trial closes (everything but the end pose is set).
  bool advance(bool moving, std::int64_t counts_l, std::int64_t counts_r, std::uint32_t dt_us,
               float still_ms);

  Phase phase_ = Phase::none;
  PathId path_ = PathId::none;  ///< of the open trial
  float length_m_ = 0.0f;
  TrialRecord last_{};
  std::uint32_t next_number_ = 1u;
  std::int64_t start_l_ = 0;
  std::int64_t start_r_ = 0;
  std::int64_t seen_l_ = 0;
  std::int64_t seen_r_ = 0;
  std::uint64_t elapsed_us_ = 0u;
  std::uint32_t settle_us_ = 0u;  ///< since the motion ended
  std::uint32_t still_us_ = 0u;   ///< since a wheel last moved
};

/// The last `capacity` trials, for the console. Main-loop only.
class TrialLog {
 public:
  static constexpr std::size_t capacity = 32u;

  /// Keeps `record`, dropping the oldest when full.
  void push(const TrialRecord& record);
  /// Forgets every kept trial (numbers go on).
  void clear() { count_ = 0u; }
  [[nodiscard]] std::size_t size() const { return count_; }
  /// The i-th kept trial, oldest first (i < size()).
  [[nodiscard]] const TrialRecord& at(std::size_t i) const;
  /// The kept trial numbered `number`; nullptr when it is not kept.
  [[nodiscard]] const TrialRecord* find(std::uint32_t number) const;
  /// The newest kept trial; nullptr when none.
  [[nodiscard]] const TrialRecord* latest() const;

 private:
  std::array<TrialRecord, capacity> records_{};
  std::size_t first_ = 0u;
  std::size_t count_ = 0u;
};

}  // namespace odocal::drive
