// Console commands about the console and the firmware: help, version, status, echo.

#include <bit>

#include "odocal/console/console.hpp"
#include "odocal/console/version.hpp"
#include "odocal/name_list.hpp"

namespace odocal::console {
namespace {

// drive::FaultBits' names in bit order, each ended by a NUL, the list by an empty name
// (Console::flag_names). One per bit of fault_all, which holds bits 0, 1, 2, ... only.
constexpr char kFaultNames[] = "encoder_left\0encoder_right\0stall_left\0stall_right\0";
static_assert(nul_count(kFaultNames) ==
                      std::popcount(static_cast<unsigned>(drive::fault_all)) + 1u &&
                  std::has_single_bit(static_cast<unsigned>(drive::fault_all) + 1u),
              "one name per drive::FaultBits bit, in bit order");
static_assert(drive::fault_encoder_left == 0x01 && drive::fault_encoder_right == 0x02 &&
                  drive::fault_stall_left == 0x04 && drive::fault_stall_right == 0x08,
              "kFaultNames' order");

}  // namespace

void Console::cmd_version() {
  send_line("ok name=odocal version=%s protocol=%u record_format=%u", project_version,
            protocol_version, params::record_format_version);
}

void Console::cmd_status() {
  const drive::LoopStatus status = loop_.status();
  ReplyLine reply(out_);
  append(reply, "ok mode=%s path=%s segment=%u faults=", drive::mode_name(status.mode),
         drive::path_name(status.path), status.segment);
  flag_names(reply, status.faults, kFaultNames);
  const ConsoleCounters c = counters();
  append(reply,
         " ticks=%u tick_us_avg=%3 tick_us_max=%3 illegal_l=%u illegal_r=%u left_radps=%3"
         " right_radps=%3 unsaved=%u store=%s umbmark_cw=%u umbmark_ccw=%u lateral=%u trials=%u"
         " stream_dropped=%u rx_dropped=%u",
         status.ticks, status.tick_us_avg, status.tick_us_max, status.illegal_left,
         status.illegal_right, status.left_radps, status.right_radps, settings_.unsaved() ? 1u : 0u,
         store_word(settings_.store_state()), umbmark_.cw_count(), umbmark_.ccw_count(),
         lateral_.count(), trials_.size(), c.stream_dropped, c.rx_dropped);
  append_target_status(reply);
  send(reply);
}

void Console::cmd_echo(const Token* words) {
  const bool on = words[1].is("on");
  if (!on && !words[1].is("off")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  echo_ = on;
  options_.echo = echo_ ? EchoMode::on : EchoMode::off;
  send_line("ok echo=%s", echo_ ? "on" : "off");
}

}  // namespace odocal::console
