// The console's target options (ConsoleOptions): a target's own command, its status pairs, its
// defaults and its wall sensors. Linked where a target may use them (the host programs, the Linux
// board); no_options.cpp stands in for this file where none is used (core/CMakeLists.txt).

#include "odocal/console/console.hpp"
#include "odocal/console/settings.hpp"
#include "odocal/name_list.hpp"

namespace odocal::console {
namespace {

// The wall sensors' keys in ConsoleOptions::wall_sensors' order (Console::cmd_walls).
constexpr char kWallSensorKeys[] = "left_front\0left_diagonal\0right_diagonal\0right_front";
static_assert(nul_count(kWallSensorKeys) == wall_sensor_slots, "one key per wall sensor");

}  // namespace

bool Console::run_target_command(const Token* words, std::size_t count) {
  if (options_.extra.name == nullptr || !words[0].is(options_.extra.name)) {
    return false;
  }
  ReplyLine reply(out_);
  options_.extra.handler(options_.extra.context, words, count, reply);
  const char* text = reply.data();
  if (reply.size() >= 3u && text[0] == 'e' && text[1] == 'r' && text[2] == 'r') {
    ++errors_;
  }
  send(reply);
  return true;
}

const char* Console::target_usage() const {
  if (options_.extra.name == nullptr) {
    return nullptr;
  }
  return options_.extra.usage != nullptr ? options_.extra.usage : options_.extra.name;
}

void Console::append_target_status(Reply& reply) {
  if (options_.status_pairs != nullptr) {
    reply.append_with([this](char* out, std::size_t capacity) {
      return options_.status_pairs(options_.status_context, out, capacity);
    });
  }
}

void Console::cmd_walls() {
  const auto& sensors = options_.wall_sensors;
  bool any = false;
  for (const hal::WallSensor* sensor : sensors) {
    any = any || sensor != nullptr;
  }
  if (!any) {
    send_error(ErrorCode::no_sensors, no_wall_sensors);
    return;
  }
  ReplyLine reply(out_);
  append(reply, "ok");
  for (unsigned i = 0u; i < wall_sensor_slots; ++i) {
    if (sensors[i] != nullptr) {
      append(reply, " %s=%u", name_at(kWallSensorKeys, i), sensors[i]->read_lit_counts());
    }
  }
  send(reply);
}

const params::ParamSet* Settings::usable_defaults(const params::ParamSet* defaults) {
  return defaults != nullptr && params::all_in_range(*defaults) &&
                 drive::valid(params::to_drive_config(*defaults))
             ? defaults
             : nullptr;
}

params::ParamSet Settings::defaults() const {
  return target_defaults_ != nullptr ? *target_defaults_ : params::default_params();
}

float Settings::default_value(params::ParamId id) const {
  return target_defaults_ != nullptr ? target_defaults_->get(id) : params::default_params().get(id);
}

}  // namespace odocal::console
