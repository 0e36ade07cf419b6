// What the command handlers share: number and date arguments, the drive's refusal of a
// configuration, and the busy check.

#include "odocal/console/console.hpp"

namespace odocal::console {

bool Console::number_arg(const Token& token, float lo, float hi, float& value,
                         const char* not_whole) {
  switch (read_number_arg(token, lo, hi, not_whole != nullptr, value)) {
    case NumberArg::ok:
      return true;
    case NumberArg::not_number:
      send_error(ErrorCode::bad_number, "not a finite decimal number");
      return false;
    case NumberArg::out_of_range:
      send_error_line(ErrorCode::out_of_range, "allowed min=%6 max=%6", lo, hi);
      return false;
    case NumberArg::not_whole:
      break;
  }
  send_error(ErrorCode::bad_number, not_whole);
  return false;
}

bool Console::config_accepted(const drive::ConfigCheck& check) {
  if (check.ok()) {
    return true;
  }
  if (check.error == drive::ConfigError::out_of_range) {
    send_error_line(ErrorCode::rejected, "drive refused %s (outside its range)",
                    drive::config_fields[check.field].name);
  } else {
    send_error_line(ErrorCode::rejected, "drive refused (need %s)",
                    check.error == drive::ConfigError::wheelbase_arc
                        ? "wheelbase_arc_mm 0 or within 20% of wheelbase_mm"
                        : "wheelbase_mm > wheel_diameter_mm/4");
  }
  return false;
}

bool Console::refuse_busy(Busy busy) {
  const bool path_only = busy == Busy::path;
  // The loop's status shows a command not taken yet as taken: `run` then `save` on the next
  // line is refused even when no tick came between the two.
  const drive::Mode mode = loop_.status().mode;
  if (mode == drive::Mode::path || (!path_only && mode == drive::Mode::drive)) {
    send_error_line(ErrorCode::busy, "%s; stop first",
                    path_only ? "a path is running" : "the robot is moving");
    return true;
  }
  return false;
}

bool Console::date_arg(const Token* words, std::size_t count, std::size_t index,
                       std::uint32_t& date, std::uint16_t& runs) {
  date = 0u;
  if (count > index && !parse_unsigned(words[index], date)) {
    send_error(ErrorCode::bad_number, "unix_s must be whole");
    return false;
  }
  // The runs the result came from, when the host knows more than this console saw (every pass).
  std::uint32_t given = 0u;
  if (count > index + 1u) {
    if (!parse_unsigned(words[index + 1u], given) || given == 0u || given > 65535u) {
      send_error(ErrorCode::bad_number, "runs must be 1 to 65535");
      return false;
    }
    runs = static_cast<std::uint16_t>(given);
  }
  return true;
}

}  // namespace odocal::console
