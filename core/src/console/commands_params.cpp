// Console commands on the parameters: params, get, set, save, load, defaults, provenance.

#include <cmath>

#include "odocal/console/console.hpp"

namespace odocal::console {

void Console::cmd_param(Handler handler, const Token* words) {
  params::ParamId id{};
  if (!params::find_param(words[1].text, words[1].length, id)) {
    send_error(ErrorCode::unknown_parameter, "no such parameter (see params)");
    return;
  }
  const params::ParamInfo& info = params::param_info(id);
  if (handler == Handler::set) {
    // number_arg accepts the bounds as `params` prints them and keeps the value inside the
    // table's.
    float stored = 0.0f;
    if (!number_arg(words[2], info.min, info.max, stored,
                    info.integer ? "a whole number is required" : nullptr)) {
      return;
    }
    if (refuse_busy(Busy::path)) {
      return;
    }
    if (!config_accepted(settings_.set(id, stored))) {
      return;
    }
  }
  // The value in force: for `set`, the one stored, as it is.
  send_line("ok %s=%6", info.name, settings_.get(id));
}

void Console::cmd_save() {
  params::StoreInfo info;
  const params::StoreResult result = settings_.save(info);
  if (result != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(result));
    return;
  }
  send_line("ok sequence=%u sector=%u slot=%u", info.record.sequence, info.sector, info.slot);
}

void Console::cmd_load() {
  const Settings::Load load = settings_.load();
  if (load.store == params::StoreResult::empty) {
    send_error(ErrorCode::store_empty, params::to_string(load.store));
    return;
  }
  if (load.store == params::StoreResult::corrupt) {
    // Nothing loaded and nothing erased: the damaged image stays until the next `save`.
    send_error_line(ErrorCode::store_corrupt,
                    "%s (%u slots); nothing changed, save writes a new one",
                    params::to_string(load.store), load.info.damaged);
    return;
  }
  if (load.store == params::StoreResult::newer_version) {
    send_error_line(ErrorCode::store_version, "record format %u is newer than this firmware's %u",
                    load.info.record.version, params::record_format_version);
    return;
  }
  if (load.store != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(load.store));
    return;
  }
  if (!config_accepted(load.check)) {
    return;
  }
  send_line("ok sequence=%u version=%u migrated=%u", load.info.record.sequence,
            load.info.record.version, load.info.record.migrated ? 1u : 0u);
}

void Console::cmd_defaults() {
  if (!config_accepted(settings_.restore_defaults())) {
    return;
  }
  // The spec of `params`'s last line (one string in the image).
  send_line("ok params=%u unsaved=%u", params::param_count, settings_.unsaved() ? 1u : 0u);
}

void Console::cmd_provenance() {
  const params::ParamSet& values = settings_.values();
  send_line(
      "ok wheel_method=%s wheel_runs=%u wheel_date=%u wheel_e_max_syst_mm=%3 lateral_method=%s"
      " lateral_runs=%u lateral_date=%u",
      params::method_name(values.wheel.method), values.wheel.runs, values.wheel.date_unix_s,
      values.wheel.quality_mm, params::method_name(values.lateral.method), values.lateral.runs,
      values.lateral.date_unix_s);
}

}  // namespace odocal::console
