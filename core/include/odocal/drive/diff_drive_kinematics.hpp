#pragma once
/// @file
/// Differential-drive kinematics with the UMBmark and Maddahi calibration factors.

#include <cmath>

#include <Eigen/Core>

#include "odocal/drive/drive_config.hpp"

namespace odocal::drive {

/// Body twist: forward speed and yaw rate (counter-clockwise positive).
struct Twist {
  float v_mps = 0.0f;
  float w_radps = 0.0f;
};

/// Wheel angular speeds, rad/s, positive forward.
struct WheelRates {
  float left_radps = 0.0f;
  float right_radps = 0.0f;
};

/// The speed limit: scales both wheels of `rates` down by one factor (keeping the curvature)
/// when the faster exceeds `max_radps`, so that it turns at `max_radps`. @return whether it did;
/// `scale` is then the factor (else unchanged). The tick applies it; the console's `drive`
/// reports the twist that will really be driven (the twist times `scale`).
inline bool limit_wheel_speeds(WheelRates& rates, float max_radps, float& scale) {
  const float peak = std::fmax(std::fabs(rates.left_radps), std::fabs(rates.right_radps));
  const bool clipped = peak > max_radps;
  if (clipped) {
    scale = max_radps / peak;
    rates.left_radps *= scale;
    rates.right_radps *= scale;
  }
  return clipped;
}

/// Maps between wheel rotation and body motion.
///
/// The calibrated robot is the one model in force (robot_model.hpp, `geometry_in_force`):
///   D_L,eff = D_a·c_L/(F_lat·F_lon),  D_R,eff = D_a·c_R/F_lon,  b_eff = s·wheelbase_mm,
///   s = (c_L/(F_lat·F_lon) + c_R/F_lon)/(c_L + c_R)   (1 when F_lat = F_lon = 1).
/// c_L and c_R scale each wheel's counts-to-distance (UMBmark eq. 6.35); `wheelbase_mm` is the
/// corrected wheelbase (UMBmark eq. 6.33, b_new = E_b · b). The inverse map is Maddahi eq. 7
/// read as DESIGN says, with the wheelbase in force:
///   θ̇_L = F_lon·F_lat·(2/D_L)·v − F_lon·F_lat·(b_eff/D_L)·ω,
///   θ̇_R = F_lon·(2/D_R)·v + F_lon·(b_eff/D_R)·ω,   D_L = D_a·c_L, D_R = D_a·c_R.
/// The paper's eq. 7 has b where this has b_eff: there F_lon scales turn rates too, so a factor
/// fitted on straight lines would turn every turn by F_lon's error; b_eff keeps turn angles
/// (docs/architecture.md, "One model"). The forward map (odometry) uses the same effective
/// geometry, so forward and inverse are exact inverses for any factors: the robot's belief about
/// where it went matches what it commanded.
///
/// Arc wheelbase (`wheelbase_arc_mm` ≠ 0, `odocal fit`'s arc-wheelbase model): the wheelbase in
/// force is b_w = b + w·(b_arc − b) with the blend weight w = |θ̇_L + θ̇_R| / (|θ̇_L + θ̇_R| +
/// |θ̇_R − θ̇_L|) of the wheel rotation (counts, as the fit counts them): 0 turning in place,
/// R/(R + b/2) on an arc of radius R, 1 straight. Odometry takes w from the measured wheel rates
/// (`wheelbase_for_rates_m`), the inverse map from the commanded twist, w = |v| / (|v| +
/// |ω|·b_w/2), solved with b_w itself (`wheelbase_for_twist_m`): the wheel rates it commands then
/// give that w back, so forward and inverse stay inverses. With wheelbase_arc_mm = 0 both are b
/// (one branch, no arithmetic).
class DiffDriveKinematics {
 public:
  explicit DiffDriveKinematics(const DriveConfig& config = DriveConfig{}) { configure(config); }

  /// Recomputes the maps from a (valid) configuration.
  void configure(const DriveConfig& config);

  /// Body twist -> wheel rates (Maddahi eq. 7).
  [[nodiscard]] WheelRates inverse(const Twist& twist) const;
  /// Wheel rates -> body twist (Maddahi eq. 1-2 with the effective diameters).
  [[nodiscard]] Twist forward(const WheelRates& rates) const;

  /// Distance a wheel's contact point moves per encoder count, m.
  [[nodiscard]] float left_m_per_count() const { return left_m_per_count_; }
  [[nodiscard]] float right_m_per_count() const { return right_m_per_count_; }
  /// Effective diameters and wheelbase, m.
  [[nodiscard]] float left_diameter_m() const { return left_diameter_m_; }
  [[nodiscard]] float right_diameter_m() const { return right_diameter_m_; }
  [[nodiscard]] float wheelbase_m() const { return wheelbase_m_; }
  /// b_arc − b, m; 0 when the robot has one wheelbase (wheelbase_arc_mm = 0).
  [[nodiscard]] float arc_gap_m() const { return arc_gap_m_; }

  /// Wheelbase in force, m, while the wheels turn at `left` and `right` (any unit common to both:
  /// rad/s, counts). Tick context.
  [[nodiscard]] float wheelbase_for_rates_m(float left, float right) const {
    return arc_gap_m_ == 0.0f ? wheelbase_m_ : blend_rates_m(left, right);
  }
  /// Wheelbase in force, m, for a commanded body twist.
  [[nodiscard]] float wheelbase_for_twist_m(const Twist& twist) const {
    return arc_gap_m_ == 0.0f ? wheelbase_m_ : blend_twist_m(twist);
  }

  /// The 2x2 map [θ̇_L; θ̇_R] = J·[v; ω] (eq. 7 in body frame: cos θ ẋ + sin θ ẏ = v).
  [[nodiscard]] const Eigen::Matrix2f& inverse_jacobian() const { return inverse_; }

 private:
  // Every element is written by `configure`, which the constructor calls.
  Eigen::Matrix2f inverse_;
  float left_diameter_m_ = 0.06f;
  float right_diameter_m_ = 0.06f;
  float wheelbase_m_ = 0.15f;
  float arc_gap_m_ = 0.0f;

  [[nodiscard]] float blend_rates_m(float left, float right) const;
  [[nodiscard]] float blend_twist_m(const Twist& twist) const;
  float left_m_per_count_ = 0.0f;
  float right_m_per_count_ = 0.0f;
};

}  // namespace odocal::drive
