#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::drive {
namespace {
constexpr float kPi = 3.14159265358979323846f;
}

void DiffDriveKinematics::configure(const DriveConfig& config) {
  const float average_m = config.wheel_diameter_mm * 1e-3f;
  // UMBmark eq. 6.35 (c_L, c_R on counts-to-distance) and Maddahi eq. 7 (F_lat on the left
  // wheel, F_lon on both) folded into effective diameters.
  left_diameter_m_ = average_m * config.c_l / (config.f_lat * config.f_lon);
  right_diameter_m_ = average_m * config.c_r / config.f_lon;
  wheelbase_m_ = config.wheelbase_mm * 1e-3f;
  left_m_per_count_ = kPi * left_diameter_m_ / config.counts_per_rev;
  right_m_per_count_ = kPi * right_diameter_m_ / config.counts_per_rev;

  // Maddahi eq. 6/7 in the body frame: θ̇ = (2v ∓ bω)/D.
  inverse_ << 2.0f / left_diameter_m_, -wheelbase_m_ / left_diameter_m_, 2.0f / right_diameter_m_,
      wheelbase_m_ / right_diameter_m_;
  // Maddahi eq. 1-2: v = (D_L θ̇_L + D_R θ̇_R)/4, ω = (D_R θ̇_R − D_L θ̇_L)/(2b).
  forward_ << left_diameter_m_ / 4.0f, right_diameter_m_ / 4.0f,
      -left_diameter_m_ / (2.0f * wheelbase_m_), right_diameter_m_ / (2.0f * wheelbase_m_);
}

WheelRates DiffDriveKinematics::inverse(const Twist& twist) const {
  const Eigen::Vector2f rates = inverse_ * Eigen::Vector2f(twist.v_mps, twist.w_radps);
  return WheelRates{rates.x(), rates.y()};
}

Twist DiffDriveKinematics::forward(const WheelRates& rates) const {
  const Eigen::Vector2f body = forward_ * Eigen::Vector2f(rates.left_radps, rates.right_radps);
  return Twist{body.x(), body.y()};
}

}  // namespace odocal::drive
