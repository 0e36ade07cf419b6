// The console's core: start-up, input, line events and the dispatch of a line to its command
// form. Replies are written in console_replies.cpp, the asynchronous lines (listings, trials,
// streams) in console_async.cpp, the handlers' shared argument checks in commands_args.cpp, the
// handlers in commands_*.cpp.

#include "odocal/console/console.hpp"

#include <cstring>

#include "odocal/console/version.hpp"

namespace odocal::console {
namespace {

// `fit apply <c_l> <c_r> <wheelbase_mm> <unix_s> <runs> arc <wheelbase_arc_mm>`
constexpr std::size_t kMaxWords = 9u;

}  // namespace

Console::Console(hal::ByteStream& stream, drive::ControlLoop& loop, params::ParamStore& store,
                 const ConsoleOptions& options)
    : stream_(stream),
      loop_(loop),
      options_(options),
      echo_(options.echo == EchoMode::on),
      selftest_(loop, settings_),
      settings_(loop, store, options.defaults) {}

params::StoreResult Console::start(std::uint32_t now_us) {
  last_now_us_ = now_us;
  clock_started_ = true;
  const Settings::Start start = settings_.start();
  trial_seen_ = loop_.last_trial().number;
  banner_due_ = options_.banner;
  banner_sequence_ = start.info.record.sequence;
  if (!start.used) {
    banner_store_ = start.store == params::StoreResult::ok ? "rejected" : store_word(start.store);
  }
  return start.store;
}

void Console::send_banner() {
  // Held until now: a client that reads one line per command (diffdrive_arduino) never sees it,
  // and a host that watches for it still learns of a restart at its next command.
  if (!banner_due_) {
    return;
  }
  banner_due_ = false;
  if (banner_store_ == nullptr) {
    send_line("# odocal %s console params=loaded sequence=%u%s", project_version, banner_sequence_,
              options_.banner_note);
  } else {
    send_line("# odocal %s console params=defaults store=%s%s", project_version, banner_store_,
              options_.banner_note);
  }
}

ConsoleCounters Console::counters() const {
  ConsoleCounters c;
  c.commands = commands_;
  c.errors = errors_;
  c.stream_dropped = stream_dropped_;
  c.rx_dropped = stream_.rx_dropped();
  c.questions = questions_;
  return c;
}

bool Console::idle() {
  return listing_ == Listing::none && out_.size() == 0u && peek_byte() < 0;
}

bool Console::next_byte(std::uint8_t& byte) {
  const int next = peek_byte();
  held_ = false;
  byte = static_cast<std::uint8_t>(next);
  return next >= 0;
}

int Console::peek_byte() {
  if (!held_) {
    held_ = stream_.read(&held_byte_, 1u) != 0u;
  }
  return held_ ? held_byte_ : -1;
}

void Console::poll(std::uint32_t now_us) {
  if (!clock_started_) {
    last_now_us_ = now_us;
    clock_started_ = true;
  }
  clock_us_ += static_cast<std::uint32_t>(now_us - last_now_us_);
  last_now_us_ = now_us;

  // A finished trial is announced before the reply to any later line.
  note_trials();
  if (selftest_.running()) {
    continue_selftest();
  }
  if (listing_ != Listing::none) {
    continue_listing();
  } else {
    take_input();
  }
  emit_streams(now_us);
  out_.flush(stream_);
}

void Console::take_input() {
  // One line per poll, and only while a whole reply (plus its echo) is sure to fit: until then
  // the input waits in the stream (the console has no receive ring of its own).
  std::uint8_t byte = 0u;
  while (out_.free_space() >= max_reply + 8u && next_byte(byte)) {
    Echo echo;
    const LineEvent event = editor_.feed(byte, echo);
    bool echo_this = echo_;
    if (options_.echo == EchoMode::automatic && !echo_ && editor_.saw_terminal()) {
      echo_ = true;
      echo_this = false;  // a backspace edits text never shown
    }
    if (echo_this && echo.count > 0u) {
      (void)out_.push(echo.bytes.data(), echo.count);
    }
    if (event != LineEvent::none) {
      // Terminals send Enter as a bare CR, one key at a time; programs send CR LF in one write.
      if (byte == '\r' && peek_byte() != '\n') {
        if (event == LineEvent::empty) {
          // No command, but ROSArduinoBridge answers its bare CR `Invalid Command` and
          // diffdrive_arduino sends one: so does the console, to a program (echo off).
          if (!echo_) {
            ++commands_;
            cmd_bridge(nullptr, 0u);
            return;
          }
        } else if (!bridge_line()) {
          // ROSArduinoBridge's lines, which diffdrive_arduino ends so, never turn the echo on.
          detect_terminal();
        }
      }
      handle_event(event);
      return;
    }
  }
}

bool Console::bridge_line() const {
  const char* text = editor_.line();  // NUL-ended; "" unless a line was completed
  while (*text == ' ') {
    ++text;
  }
  return text[0] != '\0' && (text[1] == ' ' || text[1] == '\0');
}

void Console::detect_terminal() {
  // A line ended by a CR with nothing behind it yet is a person typing: show the line they could
  // not see, echo on.
  if (options_.echo != EchoMode::automatic || echo_) {
    return;
  }
  echo_ = true;
  (void)out_.push(editor_.line(), editor_.length());
}

void Console::handle_event(LineEvent event) {
  if (echo_) {
    if (event == LineEvent::cancelled) {
      (void)out_.push("^C", 2u);
    }
    send_newline();
  }
  switch (event) {
    case LineEvent::line: {
      ++commands_;
      std::array<Token, kMaxWords> words{};
      const std::size_t count = split(editor_.line(), editor_.length(), words.data(), words.size());
      execute(words.data(), count);
      return;
    }
    case LineEvent::too_long:
      ++commands_;
      send_error(ErrorCode::line_too_long, "line over 127 bytes");
      return;
    case LineEvent::bad_byte:
      ++commands_;
      send_error(ErrorCode::non_ascii, "non-ASCII or control byte");
      return;
    case LineEvent::none:
    case LineEvent::empty:
    case LineEvent::cancelled:
      return;
  }
}

namespace {

// Length of the word at `text` (up to a space or the end).
std::size_t word_length(const char* text) {
  std::size_t n = 0u;
  while (text[n] != ' ' && text[n] != '\0') {
    ++n;
  }
  return n;
}

// True when `token` is the word at `text`.
bool is_word(const Token& token, const char* text) {
  const std::size_t n = word_length(text);
  return token.length == n && std::memcmp(token.text, text, n) == 0;
}

}  // namespace

FormLookup find_form(const Token* words, std::size_t count) {
  FormLookup lookup;
  const CommandForm* const table_end = command_forms + command_form_count;
  const CommandForm* first = command_forms;
  while (first != table_end && (count == 0u || !is_word(words[0], first->synopsis))) {
    ++first;
  }
  // The command's forms are adjacent rows: [first, last).
  const CommandForm* last = first;
  std::size_t min_words = 255u;
  std::size_t max_words = 0u;
  for (; last != table_end && is_word(words[0], last->synopsis); ++last) {
    min_words = last->min_words < min_words ? last->min_words : min_words;
    max_words = last->max_words > max_words ? last->max_words : max_words;
  }
  lookup.first = first;
  lookup.last = last;
  if (first == table_end) {
    return lookup;  // unknown
  }
  // Too few or too many words for any form (also a line with more words than any command takes).
  if (count < min_words || count > max_words) {
    lookup.result = FormLookup::Result::wrong_arity;
    return lookup;
  }
  // A form selected by its keyword, else the keyword-less form that takes this many words.
  const CommandForm* form = nullptr;
  for (const CommandForm* f = first; f != last && form == nullptr; ++f) {
    if (f->has(form_sub) && count >= 2u &&
        is_word(words[1], f->synopsis + word_length(f->synopsis) + 1u)) {
      form = f;
    }
  }
  for (const CommandForm* f = first; f != last && form == nullptr; ++f) {
    if (!f->has(form_sub) && count >= f->min_words && count <= f->max_words) {
      form = f;
    }
  }
  if (form == nullptr) {
    lookup.result = FormLookup::Result::bad_argument;
  } else if (count < form->min_words || count > form->max_words) {
    // Selected by its keyword, with too few or too many words: its own usage is quoted.
    lookup.result = FormLookup::Result::wrong_arity;
    lookup.first = form;
    lookup.last = form + 1;
  } else {
    lookup.result = FormLookup::Result::found;
    lookup.form = form;
  }
  return lookup;
}

void Console::execute(const Token* words, std::size_t count) {
  // A one-character first word is ROSArduinoBridge's (no odocal command is that short).
  if (words[0].length == 1u) {
    cmd_bridge(words, count);
    return;
  }
  send_banner();
  const FormLookup lookup = find_form(words, count);
  if (lookup.result == FormLookup::Result::unknown) {
    if (count <= kMaxWords && run_target_command(words, count)) {
      return;
    }
    send_error(ErrorCode::unknown_command, "unknown command (try help)");
    return;
  }
  if (lookup.result != FormLookup::Result::found) {
    send_usage(lookup.result == FormLookup::Result::wrong_arity ? ErrorCode::wrong_arity
                                                                : ErrorCode::bad_argument,
               lookup.first, lookup.last);
    return;
  }
  const Form* const form = lookup.form;
  form_ = form;
  if (form->has(form_moving) && refuse_busy(Busy::motion)) {
    return;
  }
  if (form->has(form_question)) {
    ++questions_;
  }
  dispatch(form->handler, words, count);
}

}  // namespace odocal::console
