#include "odocal/params/param_table.hpp"

#include <cmath>
#include <cstring>

namespace odocal::params {
namespace {

// Ranges agree with drive::valid(): a value `set` accepts is one the drive accepts (the one
// cross-field rule of valid(), wheelbase > diameter / 4, is checked when the set is applied).
constexpr std::array<ParamInfo, param_count> kTable{{
    {"wheel_diameter_mm", "mm", 5.0f, 1000.0f, false, "average wheel diameter D_a"},
    {"wheelbase_mm", "mm", 10.0f, 5000.0f, false, "wheelbase b (UMBmark corrected)"},
    {"counts_per_rev", "counts", 4.0f, 1.0e6f, false, "encoder counts per wheel rev (x4)"},
    {"c_l", "1", 0.5f, 2.0f, false, "UMBmark left wheel factor"},
    {"c_r", "1", 0.5f, 2.0f, false, "UMBmark right wheel factor"},
    {"f_lat", "1", 0.5f, 2.0f, false, "Maddahi lateral factor"},
    {"f_lon", "1", 0.5f, 2.0f, false, "Maddahi longitudinal factor"},
    {"control_hz", "Hz", 50.0f, 20000.0f, false, "control tick rate"},
    {"kp", "duty*s/rad", 0.0f, 100.0f, false, "wheel PI proportional gain"},
    {"ki", "duty/rad", 0.0f, 10000.0f, false, "wheel PI integral gain"},
    {"kff", "duty*s/rad", 0.0f, 10.0f, false, "wheel speed feed-forward"},
    {"max_wheel_radps", "rad/s", 0.1f, 1000.0f, false, "wheel speed set-point limit"},
    {"cmd_timeout_ms", "ms", 10.0f, 60000.0f, false, "drive command timeout"},
    {"v_max_mps", "m/s", 0.001f, 10.0f, false, "path cruise speed"},
    {"w_max_radps", "rad/s", 0.01f, 50.0f, false, "path turn rate"},
    {"accel_mps2", "m/s2", 0.01f, 50.0f, false, "path linear acceleration"},
    {"alpha_radps2", "rad/s2", 0.01f, 500.0f, false, "path angular acceleration"},
    {"settle_ms", "ms", 0.0f, 10000.0f, false, "standstill between segments"},
    {"stall_ms", "ms", 10.0f, 60000.0f, false, "stall fault delay"},
    {"stall_duty", "1", 0.0f, 1.0f, false, "duty above which a wheel must turn"},
    {"max_illegal", "count", 0.0f, 1.0e6f, true, "illegal encoder transitions before fault"},
}};

float field(const drive::DriveConfig& c, ParamId id) {
  switch (id) {
    case ParamId::wheel_diameter_mm:
      return c.wheel_diameter_mm;
    case ParamId::wheelbase_mm:
      return c.wheelbase_mm;
    case ParamId::counts_per_rev:
      return c.counts_per_rev;
    case ParamId::c_l:
      return c.c_l;
    case ParamId::c_r:
      return c.c_r;
    case ParamId::f_lat:
      return c.f_lat;
    case ParamId::f_lon:
      return c.f_lon;
    case ParamId::control_hz:
      return c.control_hz;
    case ParamId::kp:
      return c.kp;
    case ParamId::ki:
      return c.ki;
    case ParamId::kff:
      return c.kff;
    case ParamId::max_wheel_radps:
      return c.max_wheel_radps;
    case ParamId::cmd_timeout_ms:
      return c.cmd_timeout_ms;
    case ParamId::v_max_mps:
      return c.v_max_mps;
    case ParamId::w_max_radps:
      return c.w_max_radps;
    case ParamId::accel_mps2:
      return c.accel_mps2;
    case ParamId::alpha_radps2:
      return c.alpha_radps2;
    case ParamId::settle_ms:
      return c.settle_ms;
    case ParamId::stall_ms:
      return c.stall_ms;
    case ParamId::stall_duty:
      return c.stall_duty;
    case ParamId::max_illegal:
      return static_cast<float>(c.max_illegal);
    case ParamId::count:
      break;
  }
  return 0.0f;
}

void set_field(drive::DriveConfig& c, ParamId id, float v) {
  switch (id) {
    case ParamId::wheel_diameter_mm:
      c.wheel_diameter_mm = v;
      break;
    case ParamId::wheelbase_mm:
      c.wheelbase_mm = v;
      break;
    case ParamId::counts_per_rev:
      c.counts_per_rev = v;
      break;
    case ParamId::c_l:
      c.c_l = v;
      break;
    case ParamId::c_r:
      c.c_r = v;
      break;
    case ParamId::f_lat:
      c.f_lat = v;
      break;
    case ParamId::f_lon:
      c.f_lon = v;
      break;
    case ParamId::control_hz:
      c.control_hz = v;
      break;
    case ParamId::kp:
      c.kp = v;
      break;
    case ParamId::ki:
      c.ki = v;
      break;
    case ParamId::kff:
      c.kff = v;
      break;
    case ParamId::max_wheel_radps:
      c.max_wheel_radps = v;
      break;
    case ParamId::cmd_timeout_ms:
      c.cmd_timeout_ms = v;
      break;
    case ParamId::v_max_mps:
      c.v_max_mps = v;
      break;
    case ParamId::w_max_radps:
      c.w_max_radps = v;
      break;
    case ParamId::accel_mps2:
      c.accel_mps2 = v;
      break;
    case ParamId::alpha_radps2:
      c.alpha_radps2 = v;
      break;
    case ParamId::settle_ms:
      c.settle_ms = v;
      break;
    case ParamId::stall_ms:
      c.stall_ms = v;
      break;
    case ParamId::stall_duty:
      c.stall_duty = v;
      break;
    case ParamId::max_illegal:
      c.max_illegal = v > 0.0f ? static_cast<std::uint32_t>(v) : 0u;
      break;
    case ParamId::count:
      break;
  }
}

bool same_provenance(const Provenance& a, const Provenance& b) {
  return a.method == b.method && a.runs == b.runs && a.date_unix_s == b.date_unix_s &&
         std::memcmp(&a.quality_mm, &b.quality_mm, sizeof(float)) == 0;
}

}  // namespace

const ParamInfo& param_info(ParamId id) {
  const auto index = static_cast<std::size_t>(id);
  return index < param_count ? kTable[index] : kTable[0];
}

bool find_param(const char* name, std::size_t length, ParamId& id) {
  if (name == nullptr) {
    return false;
  }
  for (std::size_t i = 0; i < param_count; ++i) {
    const char* candidate = kTable[i].name;
    if (std::strlen(candidate) == length && std::memcmp(candidate, name, length) == 0) {
      id = static_cast<ParamId>(i);
      return true;
    }
  }
  return false;
}

float default_value(ParamId id) {
  return field(drive::DriveConfig{}, id);
}

bool in_range(ParamId id, float value) {
  const auto index = static_cast<std::size_t>(id);
  if (index >= param_count || !std::isfinite(value)) {
    return false;
  }
  const ParamInfo& info = kTable[index];
  if (value < info.min || value > info.max) {
    return false;
  }
  return !info.integer || std::floor(value) == value;
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
    set_field(config, static_cast<ParamId>(i), set.values[i]);
  }
  return config;
}

void from_drive_config(const drive::DriveConfig& config, ParamSet& set) {
  for (std::size_t i = 0; i < param_count; ++i) {
    set.values[i] = field(config, static_cast<ParamId>(i));
  }
}

bool same(const ParamSet& a, const ParamSet& b) {
  return std::memcmp(a.values.data(), b.values.data(), sizeof(float) * param_count) == 0 &&
         same_provenance(a.wheel, b.wheel) && same_provenance(a.lateral, b.lateral);
}

}  // namespace odocal::params
