#pragma once
/// @file
/// The on-robot Maddahi procedure (eq. 4-5): the stop points of straight trials entered one by
/// one, each with the left-wheel rotation the robot measured during it, and the last solution.
/// Hardware-free, no heap.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/calib/lateral.hpp"

namespace odocal::calib {

class LateralSession {
 public:
  static constexpr std::size_t capacity = 32u;  ///< trials kept

  /// Why a trial was not added.
  enum class AddStatus : std::uint8_t {
    ok,
    full,             ///< `capacity` trials already
    length_mismatch,  ///< its commanded length differs from the trials already entered
    bad_trial,        ///< length or left-wheel rotation not finite and > 0
  };

  /// Forgets the trials and the solution.
  void clear();
  /// Adds one straight trial: where it stopped (start frame, mm), its commanded length L (mm),
  /// and the left wheel's measured rotation over it, θ_L (rad, > 0).
  [[nodiscard]] AddStatus add(const StopPoint& stop, double length_mm, double theta_l_rad);

  /// Eq. 4-5 over the entered trials with θ_L their mean; on `ok` the result is kept.
  /// @param left_diameter_mm, right_diameter_mm the diameters the trials were driven with.
  [[nodiscard]] LateralStatus solve(double wheelbase_mm, double left_diameter_mm,
                                    double right_diameter_mm);
  [[nodiscard]] bool solved() const { return solved_; }
  [[nodiscard]] const LateralResult& result() const { return result_; }
  /// The solution was applied: later trials run with the new factors.
  void applied() { clear(); }

  [[nodiscard]] std::size_t count() const { return count_; }
  [[nodiscard]] double length_mm() const { return length_mm_; }

 private:
  std::array<StopPoint, capacity> stops_{};
  std::size_t count_ = 0u;
  double length_mm_ = 0.0;
  double theta_l_sum_rad_ = 0.0;
  LateralResult result_{};
  bool solved_ = false;
};

}  // namespace odocal::calib
