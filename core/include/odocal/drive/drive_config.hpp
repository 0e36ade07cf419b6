#pragma once
/// @file
/// Everything the drive stack is told about the robot and its controller, and the one table that
/// says, for each field, its console name, unit, closed range and default. The parameter table
/// (params/param_table.hpp), the drive's validity check and the console all derive from it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace odocal::drive {

/// Robot geometry, calibration factors, controller gains and motion limits.
/// Units are in the field names; every field has a closed valid range (`config_fields`).
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
  float stall_ms = 500.0f;          ///< duty above stall_duty, position within a count, this long
  float stall_duty = 0.3f;          ///< |duty| above which a wheel is expected to turn
  std::uint32_t max_illegal = 16u;  ///< illegal encoder transitions before the fault trips
  // Geometry, added later (the table is in stored-id order, so it comes last).
  /// Arc wheelbase b_arc: the wheelbase in force is b + w·(b_arc − b) with the blend weight
  /// w = |forward| / (|forward| + |differential|) wheel travel (0 turning in place, R/(R + b/2) on
  /// an arc of radius R, 1 straight), as `odocal fit`'s arc-wheelbase model. 0 = the same as
  /// wheelbase_mm (one wheelbase, the robot behaves as before the parameter existed); otherwise
  /// within 20 % of wheelbase_mm (`check`).
  float wheelbase_arc_mm = 0.0f;
  // Wiring.
  std::uint32_t wiring_fix = 0u;  ///< WiringFix bits: how the motors and encoders are connected
};

/// Bits of DriveConfig::wiring_fix: the firmware's fixes for a miswired robot (docs/wiring.md).
/// Applied once when the configuration is taken, at the loop's edge to the hardware: the tick
/// costs the same whatever they are.
enum WiringFix : std::uint32_t {
  invert_left_motor = 0x01,     ///< the left motor turns backwards for a forward duty
  invert_right_motor = 0x02,    ///< the right motor turns backwards for a forward duty
  invert_left_encoder = 0x04,   ///< the left encoder counts down going forward
  invert_right_encoder = 0x08,  ///< the right encoder counts down going forward
  swap_encoders = 0x10,         ///< the left encoder is on the right connector and vice versa
  swap_motors = 0x20,           ///< the left motor is on the right connector and vice versa
  wiring_fix_all = 0x3F,
};

/// One field of DriveConfig as the console and the store see it (also the console's
/// params::ParamInfo). 20 bytes a field: the field is found by its byte offset in DriveConfig.
struct ConfigField {
  const char* name;     ///< console name, lower case ("c_l")
  const char* unit;     ///< unit as printed ("mm", "1" for dimensionless)
  float min;            ///< smallest accepted value (inclusive)
  float max;            ///< largest accepted value (inclusive)
  std::uint8_t offset;  ///< offsetof(DriveConfig, the field)
  bool integer;         ///< a std::uint32_t field: only whole numbers are accepted; else float

  /// The field's value in `config`, as a float.
  [[nodiscard]] float get(const DriveConfig& config) const {
    const auto* bytes = reinterpret_cast<const unsigned char*>(&config) + offset;
    if (integer) {
      std::uint32_t whole = 0u;
      std::memcpy(&whole, bytes, sizeof(whole));
      return static_cast<float>(whole);
    }
    float real = 0.0f;
    std::memcpy(&real, bytes, sizeof(real));
    return real;
  }
  /// Writes `value` into `config` (a whole field takes the value truncated, never below 0).
  void set(DriveConfig& config, float value) const {
    auto* bytes = reinterpret_cast<unsigned char*>(&config) + offset;
    if (integer) {
      const std::uint32_t whole = value > 0.0f ? static_cast<std::uint32_t>(value) : 0u;
      std::memcpy(bytes, &whole, sizeof(whole));
    } else {
      std::memcpy(bytes, &value, sizeof(value));
    }
  }
  /// Default: the member initialiser of the field.
  [[nodiscard]] float default_value() const { return get(DriveConfig{}); }
};
static_assert(sizeof(DriveConfig) < 256u, "field offsets fit ConfigField::offset");

/// Number of fields (= number of console parameters).
inline constexpr std::size_t config_field_count = 23u;

/// The table, in the order of the stored parameter ids (params::ParamId): never reorder, only
/// append. Ranges are what a robot can run with; one cross-field rule comes on top (`check`).
inline constexpr std::array<ConfigField, config_field_count> config_fields{{
    {"wheel_diameter_mm", "mm", 5.0f, 1000.0f, offsetof(DriveConfig, wheel_diameter_mm), false},
    {"wheelbase_mm", "mm", 10.0f, 5000.0f, offsetof(DriveConfig, wheelbase_mm), false},
    {"counts_per_rev", "counts", 4.0f, 1.0e6f, offsetof(DriveConfig, counts_per_rev), false},
    {"c_l", "1", 0.5f, 2.0f, offsetof(DriveConfig, c_l), false},
    {"c_r", "1", 0.5f, 2.0f, offsetof(DriveConfig, c_r), false},
    {"f_lat", "1", 0.5f, 2.0f, offsetof(DriveConfig, f_lat), false},
    {"f_lon", "1", 0.5f, 2.0f, offsetof(DriveConfig, f_lon), false},
    {"control_hz", "Hz", 50.0f, 20000.0f, offsetof(DriveConfig, control_hz), false},
    {"kp", "duty*s/rad", 0.0f, 100.0f, offsetof(DriveConfig, kp), false},
    {"ki", "duty/rad", 0.0f, 10000.0f, offsetof(DriveConfig, ki), false},
    {"kff", "duty*s/rad", 0.0f, 10.0f, offsetof(DriveConfig, kff), false},
    {"max_wheel_radps", "rad/s", 0.1f, 1000.0f, offsetof(DriveConfig, max_wheel_radps), false},
    {"cmd_timeout_ms", "ms", 10.0f, 60000.0f, offsetof(DriveConfig, cmd_timeout_ms), false},
    {"v_max_mps", "m/s", 0.001f, 10.0f, offsetof(DriveConfig, v_max_mps), false},
    {"w_max_radps", "rad/s", 0.01f, 50.0f, offsetof(DriveConfig, w_max_radps), false},
    {"accel_mps2", "m/s2", 0.01f, 50.0f, offsetof(DriveConfig, accel_mps2), false},
    {"alpha_radps2", "rad/s2", 0.01f, 500.0f, offsetof(DriveConfig, alpha_radps2), false},
    {"settle_ms", "ms", 0.0f, 10000.0f, offsetof(DriveConfig, settle_ms), false},
    {"stall_ms", "ms", 10.0f, 60000.0f, offsetof(DriveConfig, stall_ms), false},
    {"stall_duty", "1", 0.0f, 1.0f, offsetof(DriveConfig, stall_duty), false},
    {"max_illegal", "count", 0.0f, 1.0e6f, offsetof(DriveConfig, max_illegal), true},
    {"wheelbase_arc_mm", "mm", 0.0f, 5000.0f, offsetof(DriveConfig, wheelbase_arc_mm), false},
    {"wiring_fix", "bits", 0.0f, 63.0f, offsetof(DriveConfig, wiring_fix), true},
}};

/// Why a configuration was refused.
enum class ConfigError : std::uint8_t {
  none,             ///< accepted
  out_of_range,     ///< field `field` is not finite or outside its range
  wheelbase_short,  ///< wheelbase_mm <= wheel_diameter_mm / 4
  wheelbase_arc,    ///< wheelbase_arc_mm neither 0 nor within 20 % of wheelbase_mm
};

/// How far the arc wheelbase may be from wheelbase_mm, relative (a tyre's contact patch moving
/// across its width: the OptiOdom robot's differ by 0.8 %). It also bounds the blend's inverse
/// kinematics (DiffDriveKinematics).
inline constexpr float wheelbase_arc_tolerance = 0.2f;

/// The outcome of checking a configuration: a code and, for `out_of_range`, which field.
struct [[nodiscard]] ConfigCheck {
  ConfigError error = ConfigError::none;
  std::size_t field = 0u;  ///< index into config_fields (out_of_range only)

  [[nodiscard]] constexpr bool ok() const { return error == ConfigError::none; }
  constexpr explicit operator bool() const { return ok(); }
};

/// True when `value` is finite, inside [min, max] of field `index`, and whole for an integer field.
[[nodiscard]] bool field_accepts(std::size_t index, float value);

/// Checks every field against its range, then the cross-field rule.
[[nodiscard]] ConfigCheck check(const DriveConfig& config);

/// True when `check` accepts the configuration.
[[nodiscard]] inline bool valid(const DriveConfig& config) {
  return check(config).ok();
}

/// A short English reason for a refusal ("wheelbase_mm must exceed wheel_diameter_mm/4").
[[nodiscard]] const char* to_string(const ConfigCheck& result);

}  // namespace odocal::drive
