#include "odocal/params/param_table.hpp"

#include <cstring>
#include <type_traits>

#include "odocal/name_list.hpp"

namespace odocal::params {
namespace {

static_assert(param_count == drive::config_field_count,
              "one parameter per DriveConfig field (drive/drive_config.hpp)");

// DriveConfig is the parameters in id order, four bytes each: the float fields convert to and from
// ParamSet::values as one block copy, and only the whole-number fields need a conversion.
constexpr bool fields_in_id_order() {
  for (std::size_t i = 0; i < param_count; ++i) {
    if (drive::config_fields[i].offset != 4u * i) {
      return false;
    }
  }
  return sizeof(drive::DriveConfig) == 4u * param_count;
}
static_assert(fields_in_id_order(), "DriveConfig must hold the parameters in id order");
static_assert(std::is_trivially_copyable_v<drive::DriveConfig>, "DriveConfig is copied as bytes");

constexpr std::size_t integer_field_count() {
  std::size_t n = 0u;
  for (const drive::ConfigField& field : drive::config_fields) {
    n += field.integer ? 1u : 0u;
  }
  return n;
}

// The ids of the whole-number fields.
constexpr std::array<std::uint8_t, integer_field_count()> integer_fields() {
  std::array<std::uint8_t, integer_field_count()> ids{};
  std::size_t n = 0u;
  for (std::size_t i = 0; i < param_count; ++i) {
    if (drive::config_fields[i].integer) {
      ids[n++] = static_cast<std::uint8_t>(i);
    }
  }
  return ids;
}
constexpr auto kIntegerFields = integer_fields();

}  // namespace

const ParamInfo& param_info(ParamId id) {
  const auto index = static_cast<std::size_t>(id);
  return drive::config_fields[index < param_count ? index : 0u];
}

bool find_param(const char* name, std::size_t length, ParamId& id) {
  if (name == nullptr) {
    return false;
  }
  for (std::size_t i = 0; i < param_count; ++i) {
    const char* candidate = drive::config_fields[i].name;
    if (std::strlen(candidate) == length && std::memcmp(candidate, name, length) == 0) {
      id = static_cast<ParamId>(i);
      return true;
    }
  }
  return false;
}

float default_value(ParamId id) {
  const auto index = static_cast<std::size_t>(id);
  return index < param_count ? drive::config_fields[index].default_value() : 0.0f;
}

bool in_range(ParamId id, float value) {
  return drive::field_accepts(static_cast<std::size_t>(id), value);
}

const char* method_name(FactorMethod method) {
  // In FactorMethod's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char names[] =
      "defaults\0manual\0umbmark\0umbmark-exact\0migrated\0maddahi\0fit\0maddahi-bootstrap";
  static_assert(nul_count(names) == static_cast<std::size_t>(last_factor_method) + 1u,
                "one name per FactorMethod, in its order");
  const auto n = static_cast<unsigned>(method);
  return name_at(names, n <= static_cast<unsigned>(last_factor_method) ? n : 0u);
}

ParamSet default_params() {
  ParamSet set;
  from_drive_config(drive::DriveConfig{}, set);
  return set;
}

bool all_in_range(const ParamSet& set) {
  for (std::size_t i = 0; i < param_count; ++i) {
    if (!in_range(static_cast<ParamId>(i), set.values[i])) {
      return false;
    }
  }
  return true;
}

drive::DriveConfig to_drive_config(const ParamSet& set) {
  drive::DriveConfig config;
  std::memcpy(static_cast<void*>(&config), set.values.data(), sizeof config);
  for (const std::uint8_t i : kIntegerFields) {
    drive::config_fields[i].set(config, set.values[i]);
  }
  return config;
}

void from_drive_config(const drive::DriveConfig& config, ParamSet& set) {
  std::memcpy(set.values.data(), &config, sizeof config);
  for (const std::uint8_t i : kIntegerFields) {
    set.values[i] = drive::config_fields[i].get(config);
  }
}

// No padding anywhere (Provenance names its spare byte), so equal bytes are equal members, the
// floats compared bitwise.
static_assert(sizeof(Provenance) == 12u && sizeof(ParamSet) == 4u * param_count + 24u,
              "ParamSet must have no padding for same()");

bool same(const ParamSet& a, const ParamSet& b) {
  return std::memcmp(&a, &b, sizeof(ParamSet)) == 0;
}

}  // namespace odocal::params
