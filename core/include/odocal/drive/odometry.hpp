#pragma once
/// @file
/// Dead-reckoning pose from wheel increments, by exact arc integration.

namespace odocal::drive {

/// Planar pose in the start frame: x along the initial heading, y to the left, θ CCW.
struct Pose {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float theta_rad = 0.0f;  ///< wrapped to [-π, π]
};

/// Integrates wheel travel into a pose. Each increment is taken as a circular arc (constant
/// curvature over the tick), which is exact for the motion the wheels describe (not Euler):
///   Δx = Δs·sinc(Δθ/2)·cos(θ + Δθ/2),  Δy = Δs·sinc(Δθ/2)·sin(θ + Δθ/2).
/// The heading is kept twice: as a compensated (Kahan) sum of the increments, wrapped to ±π,
/// which is the reference, and as a unit vector (cos θ, sin θ) rotated by each increment, so the
/// tick needs no sin/cos of large angles. Every `resync_period` updates the vector is recomputed
/// from the reference, so rounding in the rotations cannot accumulate. x and y are summed with
/// compensation too, so millions of small single-precision steps lose no accuracy.
class Odometry {
 public:
  /// Sets the pose (odom reset). The odometer (`distance_m`, `rotation_rad`) keeps counting.
  void reset(const Pose& pose = Pose{});

  /// Adds one tick of travel. @param left_m, @param right_m distance each wheel's contact point
  /// moved, m; @param wheelbase_m the (calibrated) wheelbase, m, > 0. Tick context.
  void update(float left_m, float right_m, float wheelbase_m);

  /// The pose; θ is computed from the heading vector (atan2). Any context that owns the object.
  [[nodiscard]] Pose pose() const;
  /// Odometer: path length of the robot centre since construction, m (backwards subtracts).
  [[nodiscard]] float distance_m() const { return distance_m_; }
  /// Odometer: rotation since construction, rad, not wrapped.
  [[nodiscard]] float rotation_rad() const { return rotation_rad_; }

 private:
  float x_m_ = 0.0f, x_comp_ = 0.0f;
  float y_m_ = 0.0f, y_comp_ = 0.0f;
  static constexpr unsigned resync_period = 64u;
  float heading_ = 0.0f, heading_comp_ = 0.0f;  ///< rad, wrapped to ±π
  float cos_ = 1.0f, sin_ = 0.0f;
  unsigned since_resync_ = 0u;
  float distance_m_ = 0.0f, distance_comp_ = 0.0f;
  float rotation_rad_ = 0.0f, rotation_comp_ = 0.0f;
};

}  // namespace odocal::drive
