#pragma once
/// @file
/// The parameter table: every value the console can `get`/`set` and the store persists, with its
/// unit, default and closed valid range, and the conversion to and from drive::DriveConfig.

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/drive/drive_config.hpp"

namespace odocal::params {

/// Stable parameter identifiers. The numeric value is the id written in stored records: never
/// renumber, only append (before `count`).
enum class ParamId : std::uint8_t {
#define ODOCAL_PARAM_ID(type, name, initial, unit, min, max, group) name,
  ODOCAL_DRIVE_PARAMETERS(ODOCAL_PARAM_ID)
#undef ODOCAL_PARAM_ID
      count,
};

/// Number of parameters.
inline constexpr std::size_t param_count = static_cast<std::size_t>(ParamId::count);

/// Static description of one parameter: name, unit, range, whole or real (the drive's own
/// table entry, so the robot image holds one table).
using ParamInfo = drive::ConfigField;

/// Description of parameter `id` (`id` < count; anything else returns the first entry).
[[nodiscard]] const ParamInfo& param_info(ParamId id);
/// The parameter called `name` (exact, case-sensitive, `length` bytes, no terminator needed).
/// @return false when no parameter has that name.
[[nodiscard]] bool find_param(const char* name, std::size_t length, ParamId& id);
/// Default of parameter `id`: the member initialiser of the DriveConfig field of the same name.
[[nodiscard]] float default_value(ParamId id);
/// True when `value` is finite, inside [min, max], and whole if the parameter is an integer.
[[nodiscard]] bool in_range(ParamId id, float value);

/// How a group of calibration factors was obtained (stored with them).
enum class FactorMethod : std::uint8_t {
  defaults = 0,       ///< never changed from the defaults
  manual = 1,         ///< typed with `set` (or computed off the robot and typed)
  umbmark = 2,        ///< `umbmark solve` + `umbmark apply` on the robot
  umbmark_exact = 3,  ///< the same, exact square geometry (no small-angle approximation)
  migrated = 4,       ///< loaded from an older record format that kept no provenance
  maddahi = 5,        ///< `lateral solve` + `lateral apply` on the robot (Maddahi eq. 4-5)
  fit = 6,            ///< `fit apply`: wheel factors from a host's least-squares fit (odocal fit)
  bootstrap = 7,      ///< `lateral set`: F_lat, F_lon from a host's bootstrap (Maddahi eq. 9-17)
};
/// The highest method a stored record may hold (append new methods before changing it).
inline constexpr FactorMethod last_factor_method = FactorMethod::bootstrap;

/// Console spelling of a method ("umbmark", ...).
[[nodiscard]] const char* method_name(FactorMethod method);

/// Provenance of one group of factors.
struct Provenance {
  FactorMethod method = FactorMethod::defaults;
  /// Always 0. Names the byte that would otherwise be padding, so that every byte of a ParamSet
  /// is a member and `same` compares two sets as bytes.
  std::uint8_t reserved = 0u;
  std::uint16_t runs = 0u;         ///< calibration runs used (cw + ccw for UMBmark)
  std::uint32_t date_unix_s = 0u;  ///< when they were applied, Unix seconds; 0 = unknown
  float quality_mm = 0.0f;         ///< UMBmark: E_max,syst of the runs solved, mm; 0 otherwise
};

/// Everything the store persists: one value per parameter and the provenance of the computed
/// factors. `wheel` covers c_l, c_r, wheelbase_mm,
/// wheelbase_arc_mm (UMBmark, fit); `lateral` covers f_lat, f_lon.
struct ParamSet {
  std::array<float, param_count> values{};
  Provenance wheel{};
  Provenance lateral{};

  [[nodiscard]] float get(ParamId id) const { return values[static_cast<std::size_t>(id)]; }
  void set(ParamId id, float value) { values[static_cast<std::size_t>(id)] = value; }
};

/// The defaults of every parameter, provenance `defaults`.
[[nodiscard]] ParamSet default_params();
/// True when every value is in range (see in_range).
[[nodiscard]] bool all_in_range(const ParamSet& set);
/// The drive configuration holding these values.
[[nodiscard]] drive::DriveConfig to_drive_config(const ParamSet& set);
/// Copies the configuration's fields into `set.values` (provenance untouched).
void from_drive_config(const drive::DriveConfig& config, ParamSet& set);
/// True when both sets hold the same values and provenance (bitwise on the floats).
[[nodiscard]] bool same(const ParamSet& a, const ParamSet& b);

}  // namespace odocal::params
