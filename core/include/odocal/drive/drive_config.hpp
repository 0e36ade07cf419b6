#pragma once
/// @file
/// Everything the drive stack is told about the robot and its controller, and the one table that
/// says, for each field, its console name, unit, closed range and default. The parameter table
/// (params/param_table.hpp), the drive's validity check and the console all derive from it.

#include <array>
#include <cstddef>
#include <cstdint>

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
  float stall_ms = 500.0f;          ///< duty above stall_duty with no encoder edge this long
  float stall_duty = 0.3f;          ///< |duty| above which a wheel is expected to turn
  std::uint32_t max_illegal = 16u;  ///< illegal encoder transitions before the fault trips
};

/// One field of DriveConfig as the console and the store see it. Exactly one of `real` and
/// `whole` points at the field.
struct ConfigField {
  const char* name;         ///< console name, lower case ("c_l")
  const char* unit;         ///< unit as printed ("mm", "1" for dimensionless)
  float min;                ///< smallest accepted value (inclusive)
  float max;                ///< largest accepted value (inclusive)
  const char* description;  ///< one short phrase for `params`
  float DriveConfig::*real;
  std::uint32_t DriveConfig::*whole;

  /// The field's value in `config`, as a float.
  [[nodiscard]] constexpr float get(const DriveConfig& config) const {
    return real != nullptr ? config.*real : static_cast<float>(config.*whole);
  }
  /// Writes `value` into `config` (a whole field takes the value truncated, never below 0).
  constexpr void set(DriveConfig& config, float value) const {
    if (real != nullptr) {
      config.*real = value;
    } else {
      config.*whole = value > 0.0f ? static_cast<std::uint32_t>(value) : 0u;
    }
  }
  /// Default: the member initialiser of the field.
  [[nodiscard]] constexpr float default_value() const { return get(DriveConfig{}); }
  [[nodiscard]] constexpr bool integer() const { return whole != nullptr; }
};

/// Number of fields (= number of console parameters).
inline constexpr std::size_t config_field_count = 21u;

/// The table, in the order of the stored parameter ids (params::ParamId): never reorder, only
/// append. Ranges are what a robot can run with; one cross-field rule comes on top (`check`).
inline constexpr std::array<ConfigField, config_field_count> config_fields{{
    {"wheel_diameter_mm", "mm", 5.0f, 1000.0f, "average wheel diameter D_a",
     &DriveConfig::wheel_diameter_mm, nullptr},
    {"wheelbase_mm", "mm", 10.0f, 5000.0f, "wheelbase b (UMBmark corrected)",
     &DriveConfig::wheelbase_mm, nullptr},
    {"counts_per_rev", "counts", 4.0f, 1.0e6f, "encoder counts per wheel rev (x4)",
     &DriveConfig::counts_per_rev, nullptr},
    {"c_l", "1", 0.5f, 2.0f, "UMBmark left wheel factor", &DriveConfig::c_l, nullptr},
    {"c_r", "1", 0.5f, 2.0f, "UMBmark right wheel factor", &DriveConfig::c_r, nullptr},
    {"f_lat", "1", 0.5f, 2.0f, "Maddahi lateral factor", &DriveConfig::f_lat, nullptr},
    {"f_lon", "1", 0.5f, 2.0f, "Maddahi longitudinal factor", &DriveConfig::f_lon, nullptr},
    {"control_hz", "Hz", 50.0f, 20000.0f, "control tick rate", &DriveConfig::control_hz, nullptr},
    {"kp", "duty*s/rad", 0.0f, 100.0f, "wheel PI proportional gain", &DriveConfig::kp, nullptr},
    {"ki", "duty/rad", 0.0f, 10000.0f, "wheel PI integral gain", &DriveConfig::ki, nullptr},
    {"kff", "duty*s/rad", 0.0f, 10.0f, "wheel speed feed-forward", &DriveConfig::kff, nullptr},
    {"max_wheel_radps", "rad/s", 0.1f, 1000.0f, "wheel speed set-point limit",
     &DriveConfig::max_wheel_radps, nullptr},
    {"cmd_timeout_ms", "ms", 10.0f, 60000.0f, "drive command timeout", &DriveConfig::cmd_timeout_ms,
     nullptr},
    {"v_max_mps", "m/s", 0.001f, 10.0f, "path cruise speed", &DriveConfig::v_max_mps, nullptr},
    {"w_max_radps", "rad/s", 0.01f, 50.0f, "path turn rate", &DriveConfig::w_max_radps, nullptr},
    {"accel_mps2", "m/s2", 0.01f, 50.0f, "path linear acceleration", &DriveConfig::accel_mps2,
     nullptr},
    {"alpha_radps2", "rad/s2", 0.01f, 500.0f, "path angular acceleration",
     &DriveConfig::alpha_radps2, nullptr},
    {"settle_ms", "ms", 0.0f, 10000.0f, "standstill between segments", &DriveConfig::settle_ms,
     nullptr},
    {"stall_ms", "ms", 10.0f, 60000.0f, "stall fault delay", &DriveConfig::stall_ms, nullptr},
    {"stall_duty", "1", 0.0f, 1.0f, "duty above which a wheel must turn", &DriveConfig::stall_duty,
     nullptr},
    {"max_illegal", "count", 0.0f, 1.0e6f, "illegal encoder transitions before fault", nullptr,
     &DriveConfig::max_illegal},
}};

/// Why a configuration was refused.
enum class ConfigError : std::uint8_t {
  none,             ///< accepted
  out_of_range,     ///< field `field` is not finite or outside its range
  wheelbase_short,  ///< wheelbase_mm <= wheel_diameter_mm / 4
};

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
