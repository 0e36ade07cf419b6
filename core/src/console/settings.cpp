#include "odocal/console/settings.hpp"

#include "odocal/name_list.hpp"

namespace odocal::console {
namespace {

bool is_wheel_factor(params::ParamId id) {
  return params::param_info(id).group == drive::FactorGroup::wheel;
}

bool is_lateral_factor(params::ParamId id) {
  return params::param_info(id).group == drive::FactorGroup::lateral;
}

}  // namespace

const char* store_word(params::StoreResult result) {
  // In StoreResult's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char words[] = "ok\0empty\0newer_version\0device_error\0bad_geometry\0corrupt";
  static_assert(nul_count(words) == static_cast<std::size_t>(params::StoreResult::corrupt) + 1u,
                "one word per StoreResult, in its order");
  const auto n = static_cast<unsigned>(result);
  return n <= static_cast<unsigned>(params::StoreResult::corrupt) ? name_at(words, n) : "unknown";
}

Settings::Settings(drive::ControlLoop& loop, params::ParamStore& store,
                   const params::ParamSet* target_defaults)
    : loop_(loop),
      store_(store),
      target_defaults_(usable_defaults(target_defaults)),
      values_(defaults()) {}

Settings::Start Settings::start() {
  Start start;
  // Loaded straight into the values in force (no copy): the store writes them only on `ok`, and
  // each way out below leaves them right (the loaded set when the drive takes it, else defaults).
  start.store = store_.load(values_, start.info);
  store_state_ = start.store;
  if (start.store == params::StoreResult::ok &&
      loop_.configure(params::to_drive_config(values_)).ok()) {
    start.used = true;
  } else {
    values_ = defaults();
    (void)loop_.configure(params::to_drive_config(values_));
  }
  unsaved_ = false;
  return start;
}

drive::ConfigCheck Settings::apply(const params::ParamSet& candidate) {
  const drive::ConfigCheck check = loop_.configure(params::to_drive_config(candidate));
  if (check.ok()) {
    values_ = candidate;
    unsaved_ = true;
  }
  return check;
}

drive::ConfigCheck Settings::set(params::ParamId id, float value) {
  params::ParamSet candidate = values_;
  candidate.set(id, value);
  if (is_wheel_factor(id)) {
    candidate.wheel = params::Provenance{};
    candidate.wheel.method = params::FactorMethod::manual;
  } else if (is_lateral_factor(id)) {
    candidate.lateral = params::Provenance{};
    candidate.lateral.method = params::FactorMethod::manual;
  }
  return apply(candidate);
}

drive::ConfigCheck Settings::restore_defaults() {
  const drive::ConfigCheck check = apply(defaults());
  if (store_state_ == params::StoreResult::empty) {
    unsaved_ = false;
  }
  return check;
}

params::StoreResult Settings::save(params::StoreInfo& info) {
  const params::StoreResult result = store_.save(values_, info);
  store_state_ = result;
  if (result == params::StoreResult::ok) {
    unsaved_ = false;
  }
  return result;
}

Settings::Load Settings::load() {
  Load load;
  params::ParamSet loaded;
  load.store = store_.load(loaded, load.info);
  store_state_ = load.store;
  if (load.store != params::StoreResult::ok) {
    return load;
  }
  load.check = loop_.configure(params::to_drive_config(loaded));
  if (load.check.ok()) {
    values_ = loaded;
    unsaved_ = false;
  }
  return load;
}

}  // namespace odocal::console
