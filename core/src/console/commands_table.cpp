// The console's dispatch: each form of the command list (commands.hpp) to its handler, and the
// checks of that list made when compiled.

#include "odocal/console/console.hpp"

namespace odocal::console {

namespace {

// The first word of a synopsis equals that of `other`'s.
constexpr bool same_command(const char* synopsis, const char* other) {
  for (; *synopsis != '\0' && *synopsis != ' '; ++synopsis, ++other) {
    if (*synopsis != *other) {
      return false;
    }
  }
  return *other == '\0' || *other == ' ';
}

// The table's rules: a command's rows are adjacent (find_form takes them as one run); a question
// changes no parameter; the Handler of row i is i (dispatch and the table come from one list).
constexpr bool table_follows_its_rules() {
  for (std::size_t i = 0; i < command_form_count; ++i) {
    const CommandForm& form = command_forms[i];
    if (static_cast<std::size_t>(form.handler) != i ||
        (form.has(form_question) && form.changes() != Changes::nothing) || form.min_words == 0u ||
        form.min_words > form.max_words) {
      return false;
    }
    for (std::size_t j = i + 2u; j < command_form_count; ++j) {
      if (same_command(form.synopsis, command_forms[j].synopsis) &&
          !same_command(form.synopsis, command_forms[j - 1u].synopsis)) {
        return false;
      }
    }
  }
  return true;
}
static_assert(table_follows_its_rules(), "ODOCAL_CONSOLE_FORMS breaks a rule of its table");

}  // namespace

bool Console::refused_by_selftest(Handler handler) {
  if (!selftest_.running()) {
    return false;
  }
  // The self-test's reply is still to come: only `stop` is taken, and ends it.
  if (handler != Handler::stop) {
    send_error(ErrorCode::busy, "selftest running; stop ends it");
    return true;
  }
  selftest_.cancel();
  send_error(ErrorCode::busy, "selftest ended by stop");
  return false;
}

void Console::dispatch(Handler handler, const Token* words, std::size_t count) {
  if (refused_by_selftest(handler)) {
    return;
  }
  dispatch_form(*this, handler, words, count);
}

}  // namespace odocal::console
