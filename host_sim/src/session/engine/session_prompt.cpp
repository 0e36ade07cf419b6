// What the session asks the person at the robot: one reading of a typed line for every prompt, so
// that a signal during any prompt is the signal's way out, never taken for the end of the input.

#include <istream>
#include <string>

#include <fmt/format.h>

#include "odocal/host/csv.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

bool read_typed_line(std::istream& in, std::string& line) {
  // Without SA_RESTART a signal ends the blocking read: getline fails as at the end of the input.
  const bool got = static_cast<bool>(std::getline(in, line));
  check_interrupt();
  return got;
}

bool ask_yes_no(Context& c, const std::string& question) {
  if (c.options.yes) {
    return true;
  }
  if (c.options.confirm_in == nullptr) {
    return false;
  }
  for (;;) {
    c.log << question << " [y/n]: " << std::flush;
    std::string answer;
    if (!read_typed_line(*c.options.confirm_in, answer)) {
      // No answer is not a yes, and not a no that keeps what was applied: the session ends as if
      // interrupted, and what it applied is taken back.
      throw InputError("standard input", 0, "", "end of input at the question '" + question + "'");
    }
    while (!answer.empty() && (answer.back() == '\r' || answer.back() == ' ')) {
      answer.pop_back();
    }
    if (answer == "y" || answer == "yes" || answer == "Y") {
      return true;
    }
    if (answer == "n" || answer == "no" || answer == "N") {
      return false;
    }
    c.log << "Please answer y or n (got '" << answer << "').\n";
  }
}

bool confirmed(Context& c) {
  if (!c.options.yes && c.options.confirm_in == nullptr) {
    c.log << "Not saved: no --yes and no terminal to confirm. The factors are in force until the "
             "robot restarts; type 'save' on its console to keep them.\n";
    return false;
  }
  if (ask_yes_no(c, "Save these factors on the robot?")) {
    return true;
  }
  c.log << "Not saved. The factors are in force until the robot restarts.\n";
  return false;
}

void Context::wait_for_enter(const std::string& prompt, const std::string& before) {
  if (options.start_in == nullptr) {
    return;
  }
  log << "\n" << prompt << " press Enter to start (Ctrl-C ends the session): " << std::flush;
  std::string line;
  const bool got = read_typed_line(*options.start_in, line);
  if (got && options.confirm_in == nullptr) {
    log << "\n";  // input from a pipe: the Enter did not show
  }
  if (!got) {
    throw InputError("standard input", 0, "",
                     "end of input while waiting for Enter before " + before);
  }
}

void Context::ask_to_place(std::size_t index, const std::string& label) {
  // A tape measures from the start mark; the walls measure the robot wherever it stopped.
  if (source.is_tape()) {
    wait_for_enter(fmt::format("Run {}/{} ({}): put the robot on the start mark, aligned with the "
                               "start line, hands off;",
                               index + 1, planned, label),
                   fmt::format("run {}", index + 1));
  }
}

}  // namespace odocal::host::session
