#include "odocal/calib/lateral_session.hpp"

#include <cmath>

namespace odocal::calib {

void LateralSession::clear() {
  count_ = 0u;
  length_mm_ = 0.0f;
  theta_l_sum_rad_ = 0.0f;
  solved_ = false;
}

LateralSession::AddStatus LateralSession::add(const Stop& stop, float length_mm,
                                              float theta_l_rad) {
  if (!std::isfinite(length_mm) || !(length_mm > 0.0f) || !std::isfinite(theta_l_rad) ||
      !(theta_l_rad > 0.0f)) {
    return AddStatus::bad_trial;
  }
  if (count_ >= capacity) {
    return AddStatus::full;
  }
  // Eq. 4-5 assume one commanded length L for every trial (1 µm tolerance for float lengths).
  if (count_ > 0u && std::fabs(length_mm - length_mm_) > 1e-3f) {
    return AddStatus::length_mismatch;
  }
  stops_[count_++] = stop;
  length_mm_ = length_mm;
  theta_l_sum_rad_ += theta_l_rad;
  solved_ = false;
  return AddStatus::ok;
}

LateralStatus LateralSession::solve(float wheelbase_mm, float left_diameter_mm,
                                    float right_diameter_mm) {
  LateralInputOf<float> input;
  input.trials = stops_.data();
  input.trial_count = count_;
  input.length_mm = length_mm_;
  input.wheelbase_mm = wheelbase_mm;
  input.left_diameter_mm = left_diameter_mm;
  input.right_diameter_mm = right_diameter_mm;
  input.theta_l_rad = count_ > 0u ? theta_l_sum_rad_ / static_cast<float>(count_) : 0.0f;
  Result result;
  const LateralStatus status = solve_lateral(input, result);
  if (status == LateralStatus::ok) {
    result_ = result;
    solved_ = true;
  }
  return status;
}

}  // namespace odocal::calib
