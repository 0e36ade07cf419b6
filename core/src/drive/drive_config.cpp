#include "odocal/drive/drive_config.hpp"

#include "odocal/math/numeric.hpp"

#include <cmath>

namespace odocal::drive {

bool field_accepts(std::size_t index, float value) {
  if (index >= config_field_count || !std::isfinite(value)) {
    return false;
  }
  const ConfigField& field = config_fields[index];
  if (value < field.min || value > field.max) {
    return false;
  }
  return !field.integer || math::is_whole(value);
}

ConfigCheck check(const DriveConfig& config) {
  for (std::size_t i = 0; i < config_field_count; ++i) {
    if (!field_accepts(i, config_fields[i].get(config))) {
      return ConfigCheck{ConfigError::out_of_range, i};
    }
  }
  if (!(config.wheelbase_mm > config.wheel_diameter_mm * 0.25f)) {
    return ConfigCheck{ConfigError::wheelbase_short, 0u};
  }
  const float arc_gap = config.wheelbase_arc_mm - config.wheelbase_mm;
  if (config.wheelbase_arc_mm != 0.0f &&
      !(std::fabs(arc_gap) <= wheelbase_arc_tolerance * config.wheelbase_mm)) {
    return ConfigCheck{ConfigError::wheelbase_arc, 0u};
  }
  return ConfigCheck{};
}

const char* to_string(const ConfigCheck& result) {
  switch (result.error) {
    case ConfigError::none:
      return "accepted";
    case ConfigError::out_of_range:
      return "a value is outside its range";
    case ConfigError::wheelbase_short:
      return "wheelbase_mm must exceed wheel_diameter_mm/4";
    case ConfigError::wheelbase_arc:
      return "wheelbase_arc_mm must be 0 or within 20% of wheelbase_mm";
  }
  return "refused";
}

}  // namespace odocal::drive
