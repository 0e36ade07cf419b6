// The console's target options (ConsoleOptions): a target's own command, its status pairs and its
// defaults. Linked where a target may use them (the host programs, the Linux board); no_options.cpp
// stands in for this file where none is used (core/CMakeLists.txt). The wall sensors are chosen
// apart (walls_read.cpp, walls_none.cpp): the QEMU mouse twin reads them without the rest.

#include "odocal/console/console.hpp"
#include "odocal/console/settings.hpp"

namespace odocal::console {

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
