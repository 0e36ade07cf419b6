// Console commands about the console and the firmware: help, version, status, echo, and the
// target's own command.

#include "odocal/console/console.hpp"
#include "odocal/console/version.hpp"

namespace odocal::console {

void Console::cmd_version() {
  OkLine reply(out_);
  reply.pair_s("name", "odocal")
      .pair_s("version", project_version)
      .pair_u("protocol", protocol_version)
      .pair_u("record_format", params::record_format_version);
  send(reply);
}

void Console::cmd_status() {
  constexpr int decimals = 3;
  const drive::LoopStatus status = loop_.status();
  OkLine reply(out_);
  reply.pair_s("mode", drive::mode_name(status.mode));
  reply.pair_s("path", drive::path_name(status.path)).pair_u("segment", status.segment);
  reply.key("faults");
  if (status.faults == drive::fault_none) {
    reply.text("none");
  } else {
    const char* names[] = {"encoder_left", "encoder_right", "stall_left", "stall_right"};
    bool first = true;
    for (unsigned bit = 0; bit < 4u; ++bit) {
      if ((status.faults & (1u << bit)) != 0u) {
        reply.text(first ? "" : ",").text(names[bit]);
        first = false;
      }
    }
  }
  const ConsoleCounters c = counters();
  reply.pair_u("ticks", status.ticks)
      .pair("tick_us_avg", status.tick_us_avg, decimals)
      .pair("tick_us_max", status.tick_us_max, decimals)
      .pair_u("illegal_l", status.illegal_left)
      .pair_u("illegal_r", status.illegal_right)
      .pair("left_radps", status.left_radps, decimals)
      .pair("right_radps", status.right_radps, decimals)
      .pair_u("unsaved", settings_.unsaved() ? 1u : 0u)
      .pair_s("store", store_word(settings_.store_state()))
      .pair_u("umbmark_cw", umbmark_.cw_count())
      .pair_u("umbmark_ccw", umbmark_.ccw_count())
      .pair_u("lateral", lateral_.count())
      .pair_u("trials", trials_.size())
      .pair_u("stream_dropped", c.stream_dropped)
      .pair_u("rx_dropped", c.rx_dropped);
  if (options_.status_pairs != nullptr) {
    reply.append_with([this](char* out, std::size_t capacity) {
      return options_.status_pairs(options_.status_context, out, capacity);
    });
  }
  send(reply);
}

void Console::cmd_echo(const Token* words) {
  if (!words[1].is("on") && !words[1].is("off")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  echo_ = words[1].is("on");
  options_.echo = echo_ ? EchoMode::on : EchoMode::off;
  OkLine reply(out_);
  reply.pair_s("echo", echo_ ? "on" : "off");
  send(reply);
}

void Console::cmd_extra(const Token* words, std::size_t count) {
  ReplyLine reply(out_);
  options_.extra.handler(options_.extra.context, words, count, reply);
  const char* text = reply.data();
  if (reply.size() >= 3u && text[0] == 'e' && text[1] == 'r' && text[2] == 'r') {
    ++errors_;
  }
  send(reply);
}

}  // namespace odocal::console
