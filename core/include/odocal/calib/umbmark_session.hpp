#pragma once
/// @file
/// The on-robot UMBmark procedure's state: the return errors entered per direction, the side of
/// the square, and the last solution. Hardware-free, no heap.

#include <array>
#include <cstddef>

#include "odocal/calib/umbmark.hpp"

namespace odocal::calib {

class UmbmarkSession {
 public:
  static constexpr std::size_t capacity = 16u;  ///< runs kept per direction

  /// Forgets the runs and the solution.
  void clear();
  /// Adds one return error (measured minus odometry, mm). @return false when that direction is
  /// full (nothing added).
  [[nodiscard]] bool add(bool clockwise, const ReturnError& error);
  /// The side of the square to solve with, mm; forgets the solution.
  void set_side_mm(double side_mm);
  /// A square of this side was just driven: solve with it from now on (the solution stays).
  void note_driven_side_mm(double side_mm) { side_mm_ = side_mm; }
  [[nodiscard]] double side_mm() const { return side_mm_; }

  /// Solves from the entered runs with the wheelbase in force. On `ok` the result is kept.
  [[nodiscard]] UmbmarkStatus solve(double wheelbase_mm, bool exact);
  [[nodiscard]] bool solved() const { return solved_; }
  [[nodiscard]] const UmbmarkResult& result() const { return result_; }
  /// The factors to put in force: the solution composed with the ones the runs were driven with.
  [[nodiscard]] WheelFactors next_factors(const WheelFactors& current) const {
    return compose(current, result_);
  }
  /// The solution was applied: the runs were measured with the old factors, so a second pass
  /// starts from new runs.
  void applied() { clear(); }

  [[nodiscard]] std::size_t cw_count() const { return cw_count_; }
  [[nodiscard]] std::size_t ccw_count() const { return ccw_count_; }

 private:
  std::array<ReturnError, capacity> cw_{};
  std::array<ReturnError, capacity> ccw_{};
  std::size_t cw_count_ = 0u;
  std::size_t ccw_count_ = 0u;
  double side_mm_ = 4000.0;
  UmbmarkResult result_{};
  bool solved_ = false;
};

}  // namespace odocal::calib
