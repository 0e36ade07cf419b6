// How the console writes a reply: a line from a spec and its values, errors, usage, and lines
// sent over what the user is typing.

#include "odocal/console/console.hpp"

#include <numbers>

namespace odocal::console {
namespace {

constexpr float kRadToDeg = 180.0f / std::numbers::pi_v<float>;

}  // namespace

void Console::send_newline() {
  if (options_.crlf) {
    (void)out_.push("\r\n", 2u);
  } else {
    (void)out_.push("\n", 1u);
  }
}

void Console::send(Reply& reply) {
  // The reply was written in place at the queue's tail, leaving room for the line end.
  out_.commit(reply.size());
  send_newline();
}

std::size_t Console::clear_typing() {
  // An asynchronous line never lands inside a line the user is typing: that line is cleared first
  // (carriage return, erase to end of line) and shown again after.
  const std::size_t typed = echo_ ? editor_.pending_length() : 0u;
  if (typed > 0u) {
    (void)out_.push("\r\x1b[K", 4u);
  }
  return typed;
}

void Console::send_over_typing(Reply& line, std::size_t typed) {
  send(line);
  if (typed > 0u) {
    (void)out_.push(editor_.pending(), typed);
  }
}

void Console::send_async(Reply& line, std::size_t mark, std::size_t typed) {
  // A line that is not a reply never takes the room a reply needs: dropped and counted instead.
  const std::size_t newline = options_.crlf ? 2u : 1u;
  if (out_.free_space() < line.size() + newline + typed + max_reply + 8u) {
    out_.truncate(mark);
    ++stream_dropped_;
    return;
  }
  send_over_typing(line, typed);
}

void Console::pose_pairs(Reply& reply, const drive::Pose& pose) {
  append(reply, " x_mm=%3 y_mm=%3 theta_deg=%3", pose.x_m * 1000.0f, pose.y_m * 1000.0f,
         pose.theta_rad * kRadToDeg);
}

void Console::flag_names(Reply& reply, unsigned bits, const char* names) {
  const char* separator = "";
  for (unsigned bit = 1u; *names != '\0'; bit <<= 1u) {
    if ((bits & bit) != 0u) {
      reply.text(separator).text(names);
      separator = ",";
    }
    while (*names++ != '\0') {
    }
  }
  if (bits == 0u) {
    reply.text("none");
  }
}

void Console::append_args(Reply& reply, const char* spec, const Arg* args) {
  for (;;) {
    const char* text = spec;
    while (*spec != '\0' && *spec != '%') {
      ++spec;
    }
    reply.bytes(text, static_cast<std::size_t>(spec - text));
    if (*spec == '\0') {
      return;
    }
    const char code = spec[1];
    spec += 2;
    const Arg& arg = *args++;
    if (code == 's') {
      reply.text(arg.s);
    } else if (code == 'u') {
      reply.unsigned_number(arg.u);
    } else if (code == 'U') {
      reply.unsigned_number(*arg.u64);
    } else if (code == 'i' || code == 'I') {
      // %i was stored modulo 2^N from a 32-bit value: its low 32 bits give it back.
      const std::int64_t value = code == 'i' ? static_cast<std::int32_t>(arg.u) : *arg.i64;
      std::uint64_t magnitude = static_cast<std::uint64_t>(value);
      if (value < 0) {
        reply.bytes("-", 1u);
        magnitude = 0u - magnitude;  // unsigned: right for INT64_MIN too
      }
      reply.unsigned_number(magnitude);
    } else {
      reply.number(arg.f, code - '0');
    }
  }
}

void Console::send_args(const char* spec, const Arg* args) {
  ReplyLine line(out_);
  append_args(line, spec, args);
  send(line);
}

void Console::send_error_args(ErrorCode code, const char* spec, const Arg* args) {
  ReplyLine line(out_);
  append(line, "err %s ", error_code_name(code));
  append_args(line, spec, args);
  send_refusal(line);
}

void Console::send_refusal(Reply& reply) {
  ++errors_;
  send(reply);
}

void Console::send_error(ErrorCode code, const char* message) {
  send_error_line(code, "%s", message);
}

void Console::send_usage(ErrorCode code, const Form* first, const Form* last) {
  ReplyLine reply(out_);
  append(reply, "err %s usage: ", error_code_name(code));
  for (const Form* form = first; form != last; ++form) {
    reply.text(form == first ? "" : " | ").text(form->synopsis);
  }
  send_refusal(reply);
}

}  // namespace odocal::console
