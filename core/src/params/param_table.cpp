#include "odocal/params/param_table.hpp"

#include <cstring>

namespace odocal::params {
namespace {

static_assert(param_count == drive::config_field_count,
              "one parameter per DriveConfig field (drive/drive_config.hpp)");

bool same_provenance(const Provenance& a, const Provenance& b) {
  return a.method == b.method && a.runs == b.runs && a.date_unix_s == b.date_unix_s &&
         std::memcmp(&a.quality_mm, &b.quality_mm, sizeof(float)) == 0;
}

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
  switch (method) {
    case FactorMethod::manual:
      return "manual";
    case FactorMethod::umbmark:
      return "umbmark";
    case FactorMethod::umbmark_exact:
      return "umbmark-exact";
    case FactorMethod::migrated:
      return "migrated";
    case FactorMethod::maddahi:
      return "maddahi";
    case FactorMethod::fit:
      return "fit";
    case FactorMethod::bootstrap:
      return "maddahi-bootstrap";
    case FactorMethod::defaults:
      break;
  }
  return "defaults";
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
  for (std::size_t i = 0; i < param_count; ++i) {
    drive::config_fields[i].set(config, set.values[i]);
  }
  return config;
}

void from_drive_config(const drive::DriveConfig& config, ParamSet& set) {
  for (std::size_t i = 0; i < param_count; ++i) {
    set.values[i] = drive::config_fields[i].get(config);
  }
}

bool same(const ParamSet& a, const ParamSet& b) {
  return std::memcmp(a.values.data(), b.values.data(), sizeof(float) * param_count) == 0 &&
         same_provenance(a.wheel, b.wheel) && same_provenance(a.lateral, b.lateral);
}

}  // namespace odocal::params
