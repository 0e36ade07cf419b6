#include "odocal/console/reply.hpp"

#include "odocal/name_list.hpp"

namespace odocal::console {

const char* error_code_name(ErrorCode code) {
  // The names in the enumeration's order, each ended by a NUL: the n-th follows n NULs. One
  // string instead of a table of 22 pointers.
  static constexpr char names[] =
      "line_too_long\0non_ascii\0unknown_command\0unknown_parameter\0wrong_arity\0"
      "bad_argument\0bad_number\0out_of_range\0busy\0fault\0rejected\0store_error\0"
      "store_empty\0store_version\0umbmark_full\0umbmark_failed\0not_solved\0no_trial\0"
      "lateral_full\0lateral_failed\0store_corrupt\0no_sensors";
  // As many names as codes: a code added without its name does not compile (their order is
  // checked name by name in tests/core/console).
  static_assert(nul_count(names) == static_cast<std::size_t>(ErrorCode::count),
                "one name per ErrorCode, in its order");
  const auto n = static_cast<unsigned>(code);
  return n < static_cast<unsigned>(ErrorCode::count) ? name_at(names, n) : "unknown";
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
