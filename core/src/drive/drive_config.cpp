#include "odocal/drive/drive_config.hpp"

#include <cmath>

namespace odocal::drive {
namespace {
bool in(float value, float lo, float hi) {
  return std::isfinite(value) && value >= lo && value <= hi;
}
}  // namespace

bool valid(const DriveConfig& c) {
  return in(c.wheel_diameter_mm, 5.0f, 1000.0f) && in(c.wheelbase_mm, 10.0f, 5000.0f) &&
         in(c.counts_per_rev, 4.0f, 1.0e6f) && in(c.c_l, 0.5f, 2.0f) && in(c.c_r, 0.5f, 2.0f) &&
         in(c.f_lat, 0.5f, 2.0f) && in(c.f_lon, 0.5f, 2.0f) && in(c.control_hz, 50.0f, 20000.0f) &&
         in(c.kp, 0.0f, 100.0f) && in(c.ki, 0.0f, 10000.0f) && in(c.kff, 0.0f, 10.0f) &&
         in(c.max_wheel_radps, 0.1f, 1000.0f) && in(c.cmd_timeout_ms, 10.0f, 60000.0f) &&
         in(c.v_max_mps, 0.001f, 10.0f) && in(c.w_max_radps, 0.01f, 50.0f) &&
         in(c.accel_mps2, 0.01f, 50.0f) && in(c.alpha_radps2, 0.01f, 500.0f) &&
         in(c.settle_ms, 0.0f, 10000.0f) && in(c.stall_ms, 10.0f, 60000.0f) &&
         in(c.stall_duty, 0.0f, 1.0f) && c.wheelbase_mm > c.wheel_diameter_mm * 0.25f;
}

}  // namespace odocal::drive
