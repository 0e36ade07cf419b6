#pragma once
/// @file
/// Everything the drive stack is told about the robot and its controller. The parameter table
/// (console) fills it; its defaults are the defaults of the parameters of the same name.

#include <cstdint>

namespace odocal::drive {

/// Robot geometry, calibration factors, controller gains and motion limits.
/// Units are in the field names; every field has a closed valid range checked by `valid()`.
struct DriveConfig {
  // Geometry the firmware is told (nominal).
  float wheel_diameter_mm = 60.0f;  ///< average wheel diameter D_a
  float wheelbase_mm = 150.0f;      ///< wheelbase b (distance between wheel contact points)
  float counts_per_rev = 1440.0f;   ///< encoder counts per wheel revolution after x4 decoding

  // Calibration factors.
  float c_l = 1.0f;    ///< UMBmark left-wheel scale of counts-to-distance (eq. 6.35)
  float c_r = 1.0f;    ///< UMBmark right-wheel scale of counts-to-distance (eq. 6.35)
  float f_lat = 1.0f;  ///< Maddahi lateral factor: scales the left wheel (eq. 7)
  float f_lon = 1.0f;  ///< Maddahi longitudinal factor: scales both wheels (eq. 7)

  // Wheel-velocity loop. Duty is the signed PWM fraction in [-1, 1].
  float control_hz = 1000.0f;     ///< tick rate
  float kp = 0.05f;               ///< proportional gain, duty per (rad/s) of wheel speed error
  float ki = 1.0f;                ///< integral gain, duty per rad of accumulated wheel angle error
  float kff = 0.033f;             ///< feed-forward, duty per (rad/s) of wheel speed set-point
  float max_wheel_radps = 25.0f;  ///< wheel speed set-points are clamped to +- this
  float cmd_timeout_ms = 500.0f;  ///< a `drive` command older than this stops the wheels

  // Motion limits used by paths.
  float v_max_mps = 0.2f;     ///< cruise speed on lines and arcs
  float w_max_radps = 1.5f;   ///< cruise turn rate for turns in place
  float accel_mps2 = 0.5f;    ///< linear acceleration limit
  float alpha_radps2 = 4.0f;  ///< angular acceleration limit
  float settle_ms = 200.0f;   ///< pause at standstill between segments

  // Faults.
  float stall_ms = 500.0f;          ///< duty above stall_duty with no encoder edge this long
  float stall_duty = 0.3f;          ///< |duty| above which a wheel is expected to turn
  std::uint32_t max_illegal = 16u;  ///< illegal encoder transitions before the fault trips
};

/// True when every field is finite and inside its documented range.
[[nodiscard]] bool valid(const DriveConfig& config);

}  // namespace odocal::drive
