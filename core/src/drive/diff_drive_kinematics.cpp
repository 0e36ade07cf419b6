#include "odocal/drive/diff_drive_kinematics.hpp"

#include <cmath>
#include <numbers>

#include "odocal/drive/robot_model.hpp"

namespace odocal::drive {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;
}

void DiffDriveKinematics::configure(const DriveConfig& config) {
  // The one model's geometry in force (robot_model.hpp): UMBmark eq. 6.35 (c_L, c_R on
  // counts-to-distance) and Maddahi eq. 7 (F_lat on the left wheel, F_lon on both) folded into
  // effective diameters, the wheelbases scaled with them so that F_lat, F_lon keep turn angles.
  const model::Geometry<float> g = model::geometry_in_force(model::Parameters<float>{
      config.wheel_diameter_mm * 1e-3f, config.wheelbase_mm * 1e-3f,
      config.wheelbase_arc_mm * 1e-3f, config.c_l, config.c_r, config.f_lat, config.f_lon});
  left_diameter_m_ = g.left_diameter;
  right_diameter_m_ = g.right_diameter;
  wheelbase_m_ = g.wheelbase;
  arc_gap_m_ = g.wheelbase_arc == 0.0f ? 0.0f : g.wheelbase_arc - wheelbase_m_;
  left_m_per_count_ = kPi * left_diameter_m_ / config.counts_per_rev;
  right_m_per_count_ = kPi * right_diameter_m_ / config.counts_per_rev;

  // Maddahi eq. 6/7 in the body frame: θ̇ = (2v ∓ bω)/D. Element by element: Eigen's comma
  // initialiser costs 200 B of checking code in the robot image.
  inverse_(0, 0) = 2.0f / left_diameter_m_;
  inverse_(0, 1) = -wheelbase_m_ / left_diameter_m_;
  inverse_(1, 0) = 2.0f / right_diameter_m_;
  inverse_(1, 1) = wheelbase_m_ / right_diameter_m_;
}

float DiffDriveKinematics::blend_rates_m(float left, float right) const {
  // At rest the weight is 0 (as the fit takes it); nothing turns then anyway.
  return wheelbase_m_ + arc_gap_m_ * model::arc_weight(left, right);
}

float DiffDriveKinematics::blend_twist_m(const Twist& twist) const {
  // w·(|v| + u·(b + w·g)) = |v| with u = |ω|/2, g = b_arc − b: the positive root of
  // g·u·w² + (|v| + u·b)·w − |v| = 0, written without cancellation. Its discriminant stays
  // positive for |g| <= 0.2·b (drive_config: wheelbase_arc_tolerance).
  const float v = std::fabs(twist.v_mps);
  if (v == 0.0f) {
    return wheelbase_m_;  // turning in place (or at rest): w = 0
  }
  const float u = 0.5f * std::fabs(twist.w_radps);
  const float p = v + u * wheelbase_m_;
  const float w = 2.0f * v / (p + std::sqrt(p * p + 4.0f * arc_gap_m_ * u * v));
  return wheelbase_m_ + arc_gap_m_ * w;
}

WheelRates DiffDriveKinematics::inverse(const Twist& twist) const {
  // The ω column is proportional to the wheelbase: scaled to the one in force.
  float w = twist.w_radps;
  if (arc_gap_m_ != 0.0f) {
    w *= blend_twist_m(twist) / wheelbase_m_;
  }
  return WheelRates{inverse_(0, 0) * twist.v_mps + inverse_(0, 1) * w,
                    inverse_(1, 0) * twist.v_mps + inverse_(1, 1) * w};
}

Twist DiffDriveKinematics::forward(const WheelRates& rates) const {
  // Maddahi eq. 1-2: v = (D_L θ̇_L + D_R θ̇_R)/4, ω = (D_R θ̇_R − D_L θ̇_L)/(2b). Computed here, not
  // kept: the tick never needs it (the robot's RAM and flash).
  const float scale = wheelbase_m_ / wheelbase_for_rates_m(rates.left_radps, rates.right_radps);
  const float two_b = 2.0f * wheelbase_m_;
  return Twist{
      left_diameter_m_ / 4.0f * rates.left_radps + right_diameter_m_ / 4.0f * rates.right_radps,
      (-left_diameter_m_ / two_b * rates.left_radps +
       right_diameter_m_ / two_b * rates.right_radps) *
          scale};
}

}  // namespace odocal::drive
