#pragma once
/// @file
/// The on-robot UMBmark procedure's state: the return errors entered per direction, the side of
/// the square, and the last solution. Hardware-free, no heap; single precision (the robot links no
/// double arithmetic).

#include <array>
#include <cstddef>

#include "odocal/calib/umbmark.hpp"

namespace odocal::calib {

class UmbmarkSession {
 public:
  using Error = ReturnErrorOf<float>;
  using Result = UmbmarkResultOf<float>;
  using Factors = WheelFactorsOf<float>;
  static constexpr std::size_t capacity = 16u;  ///< runs kept per direction

  /// Forgets the runs and the solution.
  void clear();
  /// Adds one return error (measured minus odometry, mm). @return false when that direction is
  /// full (nothing added).
  [[nodiscard]] bool add(bool clockwise, const Error& error);
  /// The side of the square to solve with, mm; forgets the solution.
  void set_side_mm(float side_mm);
  /// A square of this side was just driven: solve with it from now on (the solution stays).
  void note_driven_side_mm(float side_mm) { side_mm_ = side_mm; }
  [[nodiscard]] float side_mm() const { return side_mm_; }

  /// Solves from the entered runs with the wheelbase in force. On `ok` the result is kept.
  [[nodiscard]] UmbmarkStatus solve(float wheelbase_mm, bool exact);
  [[nodiscard]] bool solved() const { return solved_; }
  [[nodiscard]] const Result& result() const { return result_; }
  /// The factors to put in force: the solution composed with the ones the runs were driven with.
  [[nodiscard]] Factors next_factors(const Factors& current) const {
    return compose(current, result_);
  }
  /// The solution was applied: the runs were measured with the old factors, so a second pass
  /// starts from new runs.
  void applied() { clear(); }

  [[nodiscard]] std::size_t cw_count() const { return cw_count_; }
  [[nodiscard]] std::size_t ccw_count() const { return ccw_count_; }

 private:
  std::array<Error, capacity> cw_{};
  std::array<Error, capacity> ccw_{};
  std::size_t cw_count_ = 0u;
  std::size_t ccw_count_ = 0u;
  float side_mm_ = 4000.0f;
  Result result_{};
  bool solved_ = false;
};

}  // namespace odocal::calib
