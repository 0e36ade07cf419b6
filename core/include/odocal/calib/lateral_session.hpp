#pragma once
/// @file
/// The on-robot Maddahi procedure (eq. 4-5): the stop points of straight trials entered one by
/// one, each with the left-wheel rotation the robot measured during it, and the last solution.
/// Hardware-free, no heap; single precision (the robot links no double arithmetic).

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/calib/lateral.hpp"

namespace odocal::calib {

class LateralSession {
 public:
  using Stop = StopPointOf<float>;
  using Result = LateralResultOf<float>;
  static constexpr std::size_t capacity = 32u;  ///< trials kept

  /// Why a trial was not added.
  enum class AddStatus : std::uint8_t {
    ok,
    full,             ///< `capacity` trials already
    length_mismatch,  ///< its commanded length differs from the trials already entered
    bad_trial,        ///< length or left-wheel rotation not finite and > 0
  };

  /// Forgets the trials and the solution.
  [[gnu::noinline]] void clear();
  /// Adds one straight trial: where it stopped (start frame, mm), its commanded length L (mm),
  /// and the left wheel's measured rotation over it, θ_L (rad, > 0).
  [[nodiscard]] AddStatus add(const Stop& stop, float length_mm, float theta_l_rad);

  /// Eq. 4-5 over the entered trials with θ_L their mean; on `ok` the result is kept.
  /// @param left_diameter_mm, right_diameter_mm the diameters the trials were driven with.
  [[nodiscard]] LateralStatus solve(float wheelbase_mm, float left_diameter_mm,
                                    float right_diameter_mm);
  [[nodiscard]] bool solved() const { return solved_; }
  [[nodiscard]] const Result& result() const { return result_; }
  /// The solution was applied: later trials run with the new factors.
  void applied() { clear(); }

  [[nodiscard]] std::size_t count() const { return count_; }
  [[nodiscard]] float length_mm() const { return length_mm_; }

 private:
  std::array<Stop, capacity> stops_{};
  std::size_t count_ = 0u;
  float length_mm_ = 0.0f;
  float theta_l_sum_rad_ = 0.0f;
  Result result_{};
  bool solved_ = false;
};

}  // namespace odocal::calib
