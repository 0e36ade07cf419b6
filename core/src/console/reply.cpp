#include "odocal/console/reply.hpp"

namespace odocal::console {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::line_too_long:
      return "line_too_long";
    case ErrorCode::non_ascii:
      return "non_ascii";
    case ErrorCode::unknown_command:
      return "unknown_command";
    case ErrorCode::unknown_parameter:
      return "unknown_parameter";
    case ErrorCode::wrong_arity:
      return "wrong_arity";
    case ErrorCode::bad_argument:
      return "bad_argument";
    case ErrorCode::bad_number:
      return "bad_number";
    case ErrorCode::out_of_range:
      return "out_of_range";
    case ErrorCode::busy:
      return "busy";
    case ErrorCode::fault:
      return "fault";
    case ErrorCode::rejected:
      return "rejected";
    case ErrorCode::store_error:
      return "store_error";
    case ErrorCode::store_empty:
      return "store_empty";
    case ErrorCode::store_version:
      return "store_version";
    case ErrorCode::store_corrupt:
      return "store_corrupt";
    case ErrorCode::umbmark_full:
      return "umbmark_full";
    case ErrorCode::umbmark_failed:
      return "umbmark_failed";
    case ErrorCode::not_solved:
      return "not_solved";
    case ErrorCode::no_trial:
      return "no_trial";
    case ErrorCode::lateral_full:
      return "lateral_full";
    case ErrorCode::lateral_failed:
      return "lateral_failed";
  }
  return "unknown";
}

ErrLine::ErrLine(OutputQueue& queue, ErrorCode code) : ReplyLine(queue) {
  text("err ").text(error_code_name(code)).text(" ");
}

OkLine::OkLine(OutputQueue& queue) : ReplyLine(queue) {
  text("ok");
}

Reply& Reply::bytes(const char* s, std::size_t n) {
  if (n > capacity_ - length_) {
    n = capacity_ - length_;
  }
  std::memcpy(buffer_ + length_, s, n);
  length_ += n;
  return *this;
}

Reply& Reply::number(float value, int decimals) {
  length_ += format_fixed(value, decimals, buffer_ + length_, capacity_ - length_);
  return *this;
}

Reply& Reply::unsigned_number(std::uint64_t value) {
  length_ += format_unsigned(value, buffer_ + length_, capacity_ - length_);
  return *this;
}

Reply& Reply::pair_i(const char* k, std::int64_t value) {
  key(k);
  auto magnitude = static_cast<std::uint64_t>(value);
  if (value < 0) {
    text("-");
    magnitude = 0u - magnitude;  // in unsigned arithmetic: correct for INT64_MIN too
  }
  return unsigned_number(magnitude);
}

}  // namespace odocal::console
