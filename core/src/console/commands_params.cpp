// Console commands on the parameters: params, get, set, save, load, defaults, provenance.

#include <cmath>

#include "odocal/console/console.hpp"

namespace odocal::console {
namespace {

constexpr int kParamDecimals = 6;

}  // namespace

void Console::cmd_get(const Token* words) {
  params::ParamId id{};
  if (!params::find_param(words[1].text, words[1].length, id)) {
    send_error(ErrorCode::unknown_parameter, "no such parameter (see params)");
    return;
  }
  OkLine reply(out_);
  reply.pair(params::param_info(id).name, settings_.get(id), kParamDecimals);
  send(reply);
}

void Console::cmd_set(const Token* words) {
  params::ParamId id{};
  if (!params::find_param(words[1].text, words[1].length, id)) {
    send_error(ErrorCode::unknown_parameter, "no such parameter (see params)");
    return;
  }
  const params::ParamInfo& info = params::param_info(id);
  // number_arg accepts the bounds as `params` prints them and keeps the value inside the table's.
  float stored = 0.0f;
  if (!number_arg(words[2], info.min, info.max, stored,
                  info.integer ? "a whole number is required" : nullptr)) {
    return;
  }
  if (refuse_busy(true)) {
    return;
  }
  if (!config_accepted(settings_.set(id, stored))) {
    return;
  }
  OkLine reply(out_);
  reply.pair(info.name, stored, kParamDecimals);
  send(reply);
}

void Console::cmd_save() {
  params::StoreInfo info;
  const params::StoreResult result = settings_.save(info);
  if (result != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(result));
    return;
  }
  OkLine reply(out_);
  reply.pair_u("sequence", info.record.sequence)
      .pair_u("sector", info.sector)
      .pair_u("slot", info.slot);
  send(reply);
}

void Console::cmd_load() {
  const Settings::Load load = settings_.load();
  if (load.store == params::StoreResult::empty) {
    send_error(ErrorCode::store_empty, params::to_string(load.store));
    return;
  }
  if (load.store == params::StoreResult::corrupt) {
    // Nothing loaded and nothing erased: the damaged image stays until the next `save`.
    ErrLine reply(out_, ErrorCode::store_corrupt);
    reply.text(params::to_string(load.store)).text(" (").unsigned_number(load.info.damaged);
    reply.text(" slots); nothing changed, save writes a new one");
    send_refusal(reply);
    return;
  }
  if (load.store == params::StoreResult::newer_version) {
    ErrLine reply(out_, ErrorCode::store_version);
    reply.text("record format ").unsigned_number(load.info.record.version);
    reply.text(" is newer than this firmware's ").unsigned_number(params::record_format_version);
    send_refusal(reply);
    return;
  }
  if (load.store != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(load.store));
    return;
  }
  if (!config_accepted(load.check)) {
    return;
  }
  OkLine reply(out_);
  reply.pair_u("sequence", load.info.record.sequence)
      .pair_u("version", load.info.record.version)
      .pair_u("migrated", load.info.record.migrated ? 1u : 0u);
  send(reply);
}

void Console::cmd_defaults() {
  if (!config_accepted(settings_.restore_defaults())) {
    return;
  }
  OkLine reply(out_);
  reply.pair_u("params", params::param_count).pair_u("unsaved", 1u);
  send(reply);
}

void Console::cmd_provenance() {
  const params::ParamSet& values = settings_.values();
  OkLine reply(out_);
  reply.pair_s("wheel_method", params::method_name(values.wheel.method))
      .pair_u("wheel_runs", values.wheel.runs)
      .pair_u("wheel_date", values.wheel.date_unix_s)
      .pair("wheel_e_max_syst_mm", values.wheel.quality_mm, 3)
      .pair_s("lateral_method", params::method_name(values.lateral.method))
      .pair_u("lateral_runs", values.lateral.runs)
      .pair_u("lateral_date", values.lateral.date_unix_s);
  send(reply);
}

}  // namespace odocal::console
