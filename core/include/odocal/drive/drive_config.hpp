#pragma once
/// @file
/// Everything the drive stack is told about the robot and its controller, and the one table that
/// says, for each field, its console name, unit, closed range and default. The parameter table
/// (params/param_table.hpp), the drive's validity check and the console all derive from it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace odocal::drive {

/// Every parameter, declared once: X(type, name, default, unit, min, max, group), in the order of
/// the stored parameter ids (params::ParamId): never reorder, only append. From this list come the
/// DriveConfig member (type, name, default), the console's and the store's table row
/// (`config_fields`: name, unit, closed range, whole or real, factor group), the stored id
/// (`ParamId`) and the host's record of the factors in force. `group` is the calibration group
/// the parameter belongs to (FactorGroup: `wheel` for what UMBmark and `fit apply` put in force,
/// `lateral` for Maddahi's factors, `none` for everything else); each group has one provenance.
/// Units are in the names; a `std::uint32_t` parameter takes whole numbers only. Ranges are what a
/// robot can run with; the cross-field rules come on top (`check`). A new parameter is one line
/// here (docs/architecture.md, "How to add").
// clang-format off
#define ODOCAL_DRIVE_PARAMETERS(X)                                                                 \
  /* Geometry the firmware is told (nominal). */                                                   \
  X(float, wheel_diameter_mm, 60.0f, "mm", 5.0f, 1000.0f, none) /* average wheel diameter D_a */   \
  X(float, wheelbase_mm, 150.0f, "mm", 10.0f, 5000.0f, wheel) /* b, between contact points */      \
  X(float, counts_per_rev, 1440.0f, "counts", 4.0f, 1.0e6f, none) /* per wheel turn after x4 */    \
  /* Calibration factors. */                                                                       \
  X(float, c_l, 1.0f, "1", 0.5f, 2.0f, wheel) /* UMBmark left counts-to-distance, 6.35 */          \
  X(float, c_r, 1.0f, "1", 0.5f, 2.0f, wheel) /* UMBmark right counts-to-distance, 6.35 */         \
  X(float, f_lat, 1.0f, "1", 0.5f, 2.0f, lateral) /* Maddahi lateral: the left wheel, eq. 7 */     \
  X(float, f_lon, 1.0f, "1", 0.5f, 2.0f, lateral)       /* Maddahi longitudinal: both, eq. 7 */    \
  /* Wheel-velocity loop; duty is the signed PWM fraction in [-1, 1]. */                           \
  X(float, control_hz, 1000.0f, "Hz", 50.0f, 20000.0f, none) /* tick rate */                       \
  X(float, kp, 0.05f, "duty*s/rad", 0.0f, 100.0f, none) /* duty per rad/s of speed error */        \
  X(float, ki, 1.0f, "duty/rad", 0.0f, 10000.0f, none)  /* duty per rad of accumulated error */    \
  X(float, kff, 0.033f, "duty*s/rad", 0.0f, 10.0f, none) /* feed-forward, duty per rad/s */        \
  X(float, max_wheel_radps, 25.0f, "rad/s", 0.1f, 1000.0f, none) /* set-points clamped to +- */    \
  X(float, cmd_timeout_ms, 500.0f, "ms", 10.0f, 60000.0f, none) /* a `drive` older stops */        \
  /* Motion limits of paths. */                                                                    \
  X(float, v_max_mps, 0.2f, "m/s", 0.001f, 10.0f, none) /* cruise speed, lines and arcs */         \
  X(float, w_max_radps, 1.5f, "rad/s", 0.01f, 50.0f, none) /* cruise turn rate, turns in place */  \
  X(float, accel_mps2, 0.5f, "m/s2", 0.01f, 50.0f, none) /* linear acceleration limit */           \
  X(float, alpha_radps2, 4.0f, "rad/s2", 0.01f, 500.0f, none) /* angular acceleration limit */     \
  X(float, settle_ms, 200.0f, "ms", 0.0f, 10000.0f, none) /* standstill between segments */        \
  /* Faults. */                                                                                    \
  X(float, stall_ms, 500.0f, "ms", 10.0f, 60000.0f, none) /* duty > stall_duty, no net motion */   \
  X(float, stall_duty, 0.3f, "1", 0.0f, 1.0f, none)     /* |duty| a turning wheel needs */         \
  X(std::uint32_t, max_illegal, 16u, "count", 0.0f, 1.0e6f, none) /* illegal transitions, fault */ \
  /* Added later. wheelbase_arc_mm: the arc wheelbase b_arc, the wheelbase in force being          \
     b + w·(b_arc − b), w = |forward| / (|forward| + |differential|) wheel travel (0 turning in    \
     place, R/(R + b/2) on an arc of radius R, 1 straight), as `odocal fit`'s arc model; 0: the    \
     same as wheelbase_mm, else within 20 % of it (`check`). */                                    \
  X(float, wheelbase_arc_mm, 0.0f, "mm", 0.0f, 5000.0f, wheel)                                     \
  X(std::uint32_t, wiring_fix, 0u, "bits", 0.0f, 63.0f, none) /* WiringFix bits */
// clang-format on

/// The calibration group of a parameter (the `group` column of ODOCAL_DRIVE_PARAMETERS). A
/// group's factors are applied together and share one provenance (params::ParamSet).
enum class FactorGroup : std::uint8_t {
  none,     ///< not a calibration factor
  wheel,    ///< c_l, c_r, wheelbase_mm, wheelbase_arc_mm: UMBmark, `fit apply`
  lateral,  ///< f_lat, f_lon: Maddahi, `lateral apply` / `lateral set`
};

/// Robot geometry, calibration factors, controller gains and motion limits: one member per
/// parameter of ODOCAL_DRIVE_PARAMETERS, with its default.
struct DriveConfig {
#define ODOCAL_DRIVE_MEMBER(type, name, initial, unit, min, max, group) type name = initial;
  ODOCAL_DRIVE_PARAMETERS(ODOCAL_DRIVE_MEMBER)
#undef ODOCAL_DRIVE_MEMBER
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
  FactorGroup group;    ///< the calibration group it belongs to (none for most)

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
inline constexpr std::size_t config_field_count =
#define ODOCAL_DRIVE_ONE(type, name, initial, unit, min, max, group) 1u +
    ODOCAL_DRIVE_PARAMETERS(ODOCAL_DRIVE_ONE) 0u;
#undef ODOCAL_DRIVE_ONE

/// The table, in the order of the stored parameter ids (params::ParamId).
inline constexpr std::array<ConfigField, config_field_count> config_fields{{
#define ODOCAL_DRIVE_FIELD(type, name, initial, unit, min, max, group) \
  {#name,                                                              \
   unit,                                                               \
   min,                                                                \
   max,                                                                \
   offsetof(DriveConfig, name),                                        \
   std::is_same_v<type, std::uint32_t>,                                \
   FactorGroup::group},
    ODOCAL_DRIVE_PARAMETERS(ODOCAL_DRIVE_FIELD)
#undef ODOCAL_DRIVE_FIELD
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
