#include "odocal/drive/odometry.hpp"

#include <cmath>
#include <numbers>

#include "odocal/drive/robot_model.hpp"
#include "odocal/math/bounded_trig.hpp"

namespace odocal::drive {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Kahan summation: adds `value` to `sum`, carrying the lost low-order bits in `compensation`.
void add_compensated(float& sum, float& compensation, float value) {
  const float y = value - compensation;
  const float t = sum + y;
  compensation = (t - sum) - y;
  sum = t;
}

}  // namespace

void Odometry::reset(const Pose& pose) {
  x_m_ = pose.x_m;
  y_m_ = pose.y_m;
  x_comp_ = 0.0f;
  y_comp_ = 0.0f;
  heading_ = math::wrap_pi(pose.theta_rad);
  heading_comp_ = 0.0f;
  const math::SinCos sc = math::sin_cos(heading_);
  cos_ = sc.cos;
  sin_ = sc.sin;
  since_resync_ = 0u;
}

void Odometry::update(float left_m, float right_m, float wheelbase_m) {
  // The one model's exact-arc step (robot_model.hpp, model::advance), written here with the
  // heading kept as a unit vector: the tick needs no sin/cos of large angles.
  const float ds = 0.5f * (left_m + right_m);
  const float dtheta = (right_m - left_m) / wheelbase_m;
  const model::HalfTurn<float> half = model::half_turn(0.5f * dtheta);

  // Heading at the middle of the arc: the chord of a circular arc points there.
  const float mid_cos = cos_ * half.cos - sin_ * half.sin;
  const float mid_sin = sin_ * half.cos + cos_ * half.sin;
  const float chord = ds * half.sinc;  // chord length of an arc of length ds turning dtheta
  add_compensated(x_m_, x_comp_, chord * mid_cos);
  add_compensated(y_m_, y_comp_, chord * mid_sin);

  add_compensated(heading_, heading_comp_, dtheta);
  if (heading_ > kPi) {
    heading_ -= 2.0f * kPi;
  } else if (heading_ < -kPi) {
    heading_ += 2.0f * kPi;
  }
  if (++since_resync_ >= resync_period) {
    // Recompute the vector from the reference heading: rotation rounding never accumulates.
    since_resync_ = 0u;
    const math::SinCos sc = math::sin_cos(heading_);
    cos_ = sc.cos;
    sin_ = sc.sin;
  } else {
    // Rotate to the end heading and renormalise.
    const float c = mid_cos * half.cos - mid_sin * half.sin;
    const float s = mid_sin * half.cos + mid_cos * half.sin;
    const float inverse_norm = 1.0f / std::sqrt(c * c + s * s);
    cos_ = c * inverse_norm;
    sin_ = s * inverse_norm;
  }

  add_compensated(distance_m_, distance_comp_, ds);
  add_compensated(rotation_rad_, rotation_comp_, dtheta);
}

Pose Odometry::pose() const {
  return Pose{x_m_, y_m_, math::arctan2(sin_, cos_)};
}

}  // namespace odocal::drive
