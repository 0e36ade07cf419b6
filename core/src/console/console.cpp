#include "odocal/console/console.hpp"
#include "odocal/drive/numeric.hpp"
#include "odocal/numbers.hpp"

#include <cstring>

#include "odocal/console/version.hpp"

namespace odocal::console {
namespace {

// `fit apply <c_l> <c_r> <wheelbase_mm> <unix_s> <runs> arc <wheelbase_arc_mm>`
constexpr std::size_t kMaxWords = 9u;
constexpr float kRadToDeg = 180.0f / pi_v<float>;

}  // namespace

Console::Console(hal::ByteStream& stream, drive::ControlLoop& loop, params::ParamStore& store,
                 const ConsoleOptions& options)
    : stream_(stream),
      loop_(loop),
      options_(options),
      echo_(options.echo == EchoMode::on),
      settings_(loop, store, options.defaults) {}

params::StoreResult Console::start(std::uint32_t now_us) {
  last_now_us_ = now_us;
  clock_started_ = true;
  const Settings::Start start = settings_.start();
  trial_seen_ = loop_.last_trial().number;
  if (options_.banner) {
    if (start.used) {
      send_line("# odocal %s console params=loaded sequence=%u", project_version,
                start.info.record.sequence);
    } else {
      send_line("# odocal %s console params=defaults store=%s", project_version,
                start.store == params::StoreResult::ok ? "rejected" : store_word(start.store));
    }
  }
  return start.store;
}

bool Console::receive_from_isr(std::uint8_t byte) {
  if (!rx_.push(byte)) {
    rx_dropped_.fetch_add(1u, std::memory_order_relaxed);
    return false;
  }
  return true;
}

ConsoleCounters Console::counters() const {
  ConsoleCounters c;
  c.commands = commands_;
  c.errors = errors_;
  c.stream_dropped = stream_dropped_;
  c.rx_dropped = rx_dropped_.load(std::memory_order_relaxed);
  return c;
}

bool Console::idle() const {
  return rx_.size() == 0u && listing_ == Listing::none && out_.size() == 0u;
}

void Console::poll(std::uint32_t now_us) {
  if (!clock_started_) {
    last_now_us_ = now_us;
    clock_started_ = true;
  }
  clock_us_ += static_cast<std::uint32_t>(now_us - last_now_us_);
  last_now_us_ = now_us;

  // Pull what the stream has into the ring (as much as the ring takes).
  std::array<std::uint8_t, 16> chunk{};  // small: the main loop's stack
  for (;;) {
    const std::size_t room = rx_.free_space();
    if (room == 0u) {
      break;
    }
    const std::size_t got = stream_.read(chunk.data(), room < chunk.size() ? room : chunk.size());
    for (std::size_t i = 0; i < got; ++i) {
      (void)rx_.push(chunk[i]);
    }
    if (got == 0u) {
      break;
    }
  }

  // A finished trial is announced before the reply to any later line.
  note_trials();
  if (selftest_phase_ != 0u) {
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
  // One line per poll, and only while a whole reply (plus its echo) is sure to fit.
  std::uint8_t byte = 0u;
  while (out_.free_space() >= max_reply + 8u && rx_.pop(byte)) {
    Echo echo;
    const LineEvent event = editor_.feed(byte, echo);
    bool echo_this = echo_;
    if (options_.echo == EchoMode::automatic && !echo_ && editor_.saw_terminal()) {
      // The byte that revealed the terminal (the first after a bare CR) is shown too.
      echo_ = true;
      echo_this = byte != 0x08u && byte != 0x7Fu;  // a backspace edits text never shown
    }
    if (echo_this && echo.count > 0u) {
      (void)out_.push(echo.bytes.data(), echo.count);
    }
    if (event != LineEvent::none) {
      if (byte == '\r') {
        detect_terminal(byte);
      }
      handle_event(event);
      return;
    }
  }
}

void Console::detect_terminal(std::uint8_t line_end) {
  // Terminals send Enter as a bare CR, one key at a time; programs send CR LF in one write. A CR
  // with nothing behind it yet is a person typing: show the line they could not see, echo on.
  std::uint8_t next = 0u;
  if (options_.echo != EchoMode::automatic || echo_ || line_end != '\r' ||
      (rx_.peek(next) && next == '\n')) {
    return;
  }
  echo_ = true;
  (void)out_.push(editor_.line(), editor_.length());
}

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

void Console::execute(const Token* words, std::size_t count) {
  // The command's forms are adjacent rows: [first, last).
  const Form* const table_end = form_table_ + form_count_;
  const Form* first = form_table_;
  while (first != table_end && !is_word(words[0], first->synopsis)) {
    ++first;
  }
  if (first == table_end) {
    if (count <= kMaxWords && run_target_command(words, count)) {
      return;
    }
    send_error(ErrorCode::unknown_command, "unknown command (try help)");
    return;
  }
  const Form* last = first;
  std::size_t min_words = 255u;
  std::size_t max_words = 0u;
  for (; last != table_end && is_word(words[0], last->synopsis); ++last) {
    min_words = last->min_words < min_words ? last->min_words : min_words;
    max_words = last->max_words > max_words ? last->max_words : max_words;
  }
  // Too few or too many words for any form (also a line with more words than any command takes).
  if (count < min_words || count > max_words) {
    send_usage(ErrorCode::wrong_arity, first, last);
    return;
  }
  // A form selected by its keyword, else the keyword-less form that takes this many words.
  const Form* form = nullptr;
  for (const Form* f = first; f != last && form == nullptr; ++f) {
    if ((f->flags & form_sub) != 0u && count >= 2u &&
        is_word(words[1], f->synopsis + word_length(f->synopsis) + 1u)) {
      form = f;
    }
  }
  for (const Form* f = first; f != last && form == nullptr; ++f) {
    if ((f->flags & form_sub) == 0u && count >= f->min_words && count <= f->max_words) {
      form = f;
    }
  }
  if (form == nullptr) {
    send_usage(ErrorCode::bad_argument, first, last);
    return;
  }
  form_ = form;
  if (count < form->min_words || count > form->max_words) {
    send_usage(ErrorCode::wrong_arity);
    return;
  }
  if ((form->flags & form_moving) != 0u && refuse_busy(false)) {
    return;
  }
  dispatch(form->handler, words, count);
}

void Console::start_listing(Listing listing) {
  listing_ = listing;
  listing_index_ = 0u;
  continue_listing();
}

void Console::continue_listing() {
  while (listing_ != Listing::none && out_.free_space() >= max_reply + 2u) {
    ReplyLine line(out_);
    if (listing_ == Listing::help) {
      // One line per form, then the target's own command.
      const char* text = nullptr;
      if (listing_index_ < form_count_) {
        text = form_table_[listing_index_].synopsis;
      } else if (listing_index_ == form_count_) {
        text = target_usage();
      }
      if (text != nullptr) {
        ++listing_index_;
        append(line, "# %s", text);
        send(line);
        continue;
      }
      append(line, "ok commands=%u", listing_index_);  // the number of help lines
    } else if (listing_ == Listing::params) {
      if (listing_index_ < params::param_count) {
        const auto id = static_cast<params::ParamId>(listing_index_++);
        const params::ParamInfo& info = params::param_info(id);
        append(line, "# %s=%6 unit=%s min=%6 max=%6 default=%6", info.name, settings_.get(id),
               info.unit, info.min, info.max, settings_.default_value(id));
        send(line);
        continue;
      }
      append(line, "ok params=%u unsaved=%u", params::param_count, settings_.unsaved() ? 1u : 0u);
    } else {
      if (listing_index_ < trials_.size()) {
        const KeptTrial& trial = trials_.at(listing_index_++);
        append(line, "# trial %u", trial.number);
        trial_pairs(line, trial);
        send(line);
        continue;
      }
      append(line, "ok trials=%u", trials_.size());
    }
    send(line);
    listing_ = Listing::none;
  }
}

void Console::note_trials() {
  const drive::TrialRecord trial = loop_.last_trial();
  if (trial.number == 0u || trial.number == trial_seen_) {
    return;
  }
  trial_seen_ = trial.number;
  trials_.push(trial);
  const std::size_t typed = clear_typing();
  ReplyLine line(out_);
  append(line, "# done trial=%u path=%s", trial.number, drive::path_name(trial.path));
  // Announced like a reply (never dropped): a host waits for it.
  send_over_typing(line, typed);
}

namespace {

// Next due instant of a periodic stream; @return false when not due yet.
bool due(std::uint32_t now_us, std::uint32_t period_us, std::uint32_t& next_us) {
  if (static_cast<std::int32_t>(now_us - next_us) < 0) {
    return false;
  }
  next_us += period_us;
  if (static_cast<std::int32_t>(now_us - next_us) >= 0) {
    next_us = now_us + period_us;  // fell behind: skip, do not burst
  }
  return true;
}

}  // namespace

void Console::emit_streams(std::uint32_t now_us) {
  // One path for both streams (odom first): they differ only in their time and values.
  for (std::size_t i = 0u; i < streams_.size(); ++i) {
    StreamTimer& timer = streams_[i];
    if (timer.period_us == 0u || !due(now_us, timer.period_us, timer.next_us)) {
      continue;
    }
    const bool odom = i == 0u;
    drive::Pose pose;
    drive::WheelCounts counts;
    if (odom) {
      pose = loop_.pose();
      counts.t_us = clock_us_;
    } else {
      counts = loop_.wheel_counts();
    }
    const std::size_t mark = out_.size();
    const std::size_t typed = clear_typing();
    ReplyLine line(out_);
    const std::uint64_t t_ms = drive::divide_u64(counts.t_us, 1000u);
    if (odom) {
      append(line, "# odom t_ms=%U", &t_ms);
      pose_pairs(line, pose);
    } else {
      append(line, "# ticks t_ms=%U count_l=%I count_r=%I", &t_ms, &counts.left, &counts.right);
    }
    send_async(line, mark, typed);
  }
}

bool Console::number_arg(const Token& token, float lo, float hi, float& value,
                         const char* not_whole) {
  constexpr int decimals = 6;  // bounds as `params` and the refusal print them
  Decimal typed;
  if (!parse_decimal(token, typed)) {
    send_error(ErrorCode::bad_number, "not a finite decimal number");
    return false;
  }
  // The typed decimal against the printed bounds, exactly: `set v_max_mps 0.001` is the minimum
  // although the table's float is 0.0010000000475, and 2.0000001 is above 2 though not as a float.
  if (compare(typed, lo, decimals) < 0 || compare(typed, hi, decimals) > 0) {
    send_error_line(ErrorCode::out_of_range, "allowed min=%6 max=%6", lo, hi);
    return false;
  }
  // Whole as typed: 1440.0000001 is not, although its nearest float is 1440.
  if (not_whole != nullptr && !is_whole(typed)) {
    send_error(ErrorCode::bad_number, not_whole);
    return false;
  }
  const float parsed = to_float(typed);
  value = parsed < lo ? lo : (parsed > hi ? hi : parsed);
  return true;
}

bool Console::config_accepted(const drive::ConfigCheck& check) {
  if (check.ok()) {
    return true;
  }
  if (check.error == drive::ConfigError::out_of_range) {
    send_error_line(ErrorCode::rejected, "drive refused %s (outside its range)",
                    drive::config_fields[check.field].name);
  } else {
    send_error(ErrorCode::rejected,
               check.error == drive::ConfigError::wheelbase_arc
                   ? "drive refused (need wheelbase_arc_mm 0 or within 20% of wheelbase_mm)"
                   : "drive refused (need wheelbase_mm > wheel_diameter_mm/4)");
  }
  return false;
}

bool Console::refuse_busy(bool path_only) {
  // The loop's status shows a command not taken yet as taken: `run` then `save` on the next
  // line is refused even when no tick came between the two.
  const drive::Mode mode = loop_.status().mode;
  if (mode == drive::Mode::path || (!path_only && mode == drive::Mode::drive)) {
    send_error(ErrorCode::busy,
               path_only ? "a path is running; stop first" : "the robot is moving; stop first");
    return true;
  }
  return false;
}

bool Console::date_arg(const Token* words, std::size_t count, std::size_t index,
                       std::uint32_t& date, std::uint16_t& runs) {
  date = 0u;
  if (count > index && !parse_unsigned(words[index], date)) {
    send_error(ErrorCode::bad_number, "unix_s must be whole seconds");
    return false;
  }
  // The runs the result came from, when the host knows more than this console saw (every pass).
  std::uint32_t given = 0u;
  if (count > index + 1u) {
    if (!parse_unsigned(words[index + 1u], given) || given == 0u || given > 65535u) {
      send_error(ErrorCode::bad_number, "runs must be a whole number from 1 to 65535");
      return false;
    }
    runs = static_cast<std::uint16_t>(given);
  }
  return true;
}

}  // namespace odocal::console
