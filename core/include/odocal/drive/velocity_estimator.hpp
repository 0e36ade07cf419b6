#pragma once
/// @file
/// Wheel position and speed from decoder snapshots (M/T method).

#include <cstdint>

#include "odocal/drive/quadrature_decoder.hpp"

namespace odocal::drive {

/// Turns successive snapshots into a wide position and an angular speed.
///
/// Method (M/T): speed = counts moved / time between the last edges of two windows. Counting
/// whole edges and timing them to the edge makes it exact for a constant speed both at high speed
/// (many edges per tick) and at low speed (one edge every few ticks). While no edge arrives the
/// estimate decays as 1 count / time since the last edge (an upper bound on the true speed), and
/// is zero after `stop_timeout_us`.
class VelocityEstimator {
 public:
  /// @param counts_per_rev counts per wheel revolution (x4), > 0
  /// @param stop_timeout_us no edge for this long means standstill
  explicit VelocityEstimator(float counts_per_rev = 1440.0f,
                             std::uint32_t stop_timeout_us = 200000u);

  /// Changes the resolution (keeps position and estimate).
  void set_counts_per_rev(float counts_per_rev);

  /// Forgets history; the next update only initialises.
  [[gnu::noinline]] void reset(const EncoderSnapshot& snapshot, std::uint32_t now_us);

  /// Processes one tick's snapshot taken at `now_us`. Tick context.
  void update(const EncoderSnapshot& snapshot, std::uint32_t now_us);

  /// Position since reset, in counts (wide: does not wrap in the robot's lifetime).
  [[nodiscard]] std::int64_t position_counts() const { return position_; }
  /// Counts moved during the last update (signed).
  [[nodiscard]] std::int32_t delta_counts() const { return delta_; }
  /// Wheel angular speed estimate, rad/s.
  [[nodiscard]] float speed_radps() const { return speed_radps_; }
  /// Time since the last edge, in microseconds (saturates at 2^32-1).
  [[nodiscard]] std::uint32_t since_edge_us() const { return since_edge_us_; }

 private:
  float rad_per_count_;
  std::uint32_t stop_timeout_us_;
  bool initialised_ = false;
  std::uint32_t last_count_ = 0u;
  std::uint32_t window_edge_us_ = 0u;  ///< last edge time at the end of the previous window
  std::int64_t position_ = 0;
  std::int32_t delta_ = 0;
  std::int32_t pending_counts_ = 0;  ///< counts since window_edge_us_ (not yet timed)
  float speed_radps_ = 0.0f;
  std::uint32_t since_edge_us_ = 0u;
};

}  // namespace odocal::drive
