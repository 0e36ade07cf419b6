#include "odocal/console/console.hpp"

#include <cmath>
#include <cstring>

#include "odocal/console/version.hpp"
#include "odocal/drive/motion_executor.hpp"

namespace odocal::console {
namespace {

constexpr std::size_t kMaxWords = 6u;
constexpr double kPi = 3.14159265358979323846;
constexpr int kParamDecimals = 6;
constexpr int kPoseDecimals = 3;

// Usage lines of `help`: command and arguments, then what it does.
constexpr const char* kHelp[] = {
    "help: this list",
    "version: firmware and protocol versions",
    "status: mode path segment faults tick timing counters",
    "params: every parameter with value unit range default",
    "get <name>: one parameter",
    "set <name> <value>: change a parameter (refused while a path runs)",
    "save: persist the parameters (refused while the robot moves)",
    "load: reload the saved parameters",
    "defaults: restore every default (not saved until save)",
    "provenance: how the calibration factors were obtained",
    "odom: pose x_mm y_mm theta_deg",
    "odom reset: set the pose to zero",
    "drive <v_mps> <w_radps> [ms]: drive at a twist (no ms: until cmd_timeout_ms)",
    "stop: stop at once, abandon the path, acknowledge faults",
    "run umbmark-cw <side_m>: UMBmark square, clockwise",
    "run umbmark-ccw <side_m>: UMBmark square, counter-clockwise",
    "run line <m>: straight calibration line",
    "run unseen: Maddahi unseen path",
    "umbmark clear: forget the entered runs and the solution",
    "umbmark add cw|ccw <x_mm> <y_mm>: one return error, measured minus odometry",
    "umbmark side <side_m>: side of the square to solve with",
    "umbmark solve [exact]: solve UMBmark from the entered runs",
    "umbmark apply [unix_s]: apply the solved factors (not saved until save)",
    "stream odom <hz>: print # odom lines at hz",
    "stream off: stop streaming",
    "echo on|off: echo typed characters",
};
constexpr std::size_t kHelpCount = sizeof(kHelp) / sizeof(kHelp[0]);

// One word for the banner (key=value pairs hold no spaces).
const char* store_word(params::StoreResult result) {
  switch (result) {
    case params::StoreResult::ok:
      return "ok";
    case params::StoreResult::empty:
      return "empty";
    case params::StoreResult::newer_version:
      return "newer_version";
    case params::StoreResult::device_error:
      return "device_error";
    case params::StoreResult::bad_geometry:
      return "bad_geometry";
  }
  return "unknown";
}

constexpr const char* kCommands[] = {"help", "version", "status",   "params",     "get",  "set",
                                     "save", "load",    "defaults", "provenance", "odom", "drive",
                                     "stop", "run",     "umbmark",  "stream",     "echo"};

bool is_command(const Token& word) {
  for (const char* name : kCommands) {
    if (word.is(name)) {
      return true;
    }
  }
  return false;
}

bool is_wheel_factor(params::ParamId id) {
  return id == params::ParamId::c_l || id == params::ParamId::c_r ||
         id == params::ParamId::wheelbase_mm;
}
bool is_lateral_factor(params::ParamId id) {
  return id == params::ParamId::f_lat || id == params::ParamId::f_lon;
}

}  // namespace

/// One output line under construction, in fixed storage.
class Console::Reply {
 public:
  Reply& text(const char* s) { return bytes(s, std::strlen(s)); }
  Reply& bytes(const char* s, std::size_t n) {
    if (n > max_reply - length_) {
      n = max_reply - length_;
    }
    std::memcpy(buffer_.data() + length_, s, n);
    length_ += n;
    return *this;
  }
  Reply& key(const char* k) { return text(" ").text(k).text("="); }
  Reply& number(double value, int decimals) {
    length_ += format_fixed(value, decimals, buffer_.data() + length_, max_reply - length_);
    return *this;
  }
  Reply& number(float value, int decimals) { return number(static_cast<double>(value), decimals); }
  Reply& pair(const char* k, double value, int decimals) { return key(k).number(value, decimals); }
  Reply& pair(const char* k, float value, int decimals) {
    return pair(k, static_cast<double>(value), decimals);
  }
  Reply& pair_u(const char* k, std::uint64_t value) {
    key(k);
    length_ += format_unsigned(value, buffer_.data() + length_, max_reply - length_);
    return *this;
  }
  Reply& pair_s(const char* k, const char* value) { return key(k).text(value); }
  /// Lets `fill(out, capacity)` write into the free space; keeps the printable ASCII prefix.
  template <typename Fill>
  Reply& append_with(Fill fill) {
    char* out = buffer_.data() + length_;
    std::size_t n = fill(out, max_reply - length_);
    if (n > max_reply - length_) {
      n = max_reply - length_;
    }
    std::size_t printable = 0u;
    while (printable < n && out[printable] >= 0x20 && out[printable] < 0x7f) {
      ++printable;
    }
    length_ += printable;
    return *this;
  }
  [[nodiscard]] const char* data() const { return buffer_.data(); }
  [[nodiscard]] std::size_t size() const { return length_; }

 private:
  std::array<char, max_reply> buffer_{};
  std::size_t length_ = 0u;
};

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
    case ErrorCode::umbmark_full:
      return "umbmark_full";
    case ErrorCode::umbmark_failed:
      return "umbmark_failed";
    case ErrorCode::not_solved:
      return "not_solved";
  }
  return "unknown";
}

Console::Console(hal::ByteStream& stream, drive::ControlLoop& loop, params::ParamStore& store,
                 const ConsoleOptions& options)
    : stream_(stream),
      loop_(loop),
      store_(store),
      options_(options),
      echo_(options.echo == EchoMode::on),
      params_(default_set()) {}

params::ParamSet Console::default_set() const {
  if (options_.defaults != nullptr && params::all_in_range(*options_.defaults) &&
      drive::valid(params::to_drive_config(*options_.defaults))) {
    return *options_.defaults;
  }
  return params::default_params();
}

params::StoreResult Console::start(std::uint32_t now_us) {
  last_now_us_ = now_us;
  clock_started_ = true;
  params::ParamSet loaded;
  params::StoreInfo info;
  const params::StoreResult result = store_.load(loaded, info);
  bool used = false;
  if (result == params::StoreResult::ok && loop_.configure(params::to_drive_config(loaded))) {
    params_ = loaded;
    used = true;
  } else {
    params_ = default_set();
    (void)loop_.configure(params::to_drive_config(params_));
  }
  unsaved_ = false;
  if (options_.banner) {
    Reply banner;
    banner.text("# odocal ").text(project_version).text(" console");
    if (used) {
      banner.pair_s("params", "loaded").pair_u("sequence", info.record.sequence);
    } else if (result == params::StoreResult::ok) {
      banner.pair_s("params", "defaults").pair_s("store", "rejected");
    } else {
      banner.pair_s("params", "defaults").pair_s("store", store_word(result));
    }
    send(banner);
  }
  return result;
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
  std::array<std::uint8_t, 64> chunk{};
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

  if (listing_ != Listing::none) {
    continue_listing();
  } else {
    take_input();
  }
  if (streaming_) {
    emit_stream(now_us);
  }
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
      echo_ = true;  // from the next byte on: this one edits text the terminal never showed
    }
    if (echo_this && echo.count > 0u) {
      (void)out_.push(echo.bytes.data(), echo.count);
    }
    if (event != LineEvent::none) {
      handle_event(event);
      return;
    }
  }
}

void Console::send_newline() {
  if (options_.crlf) {
    (void)out_.push("\r\n", 2u);
  } else {
    (void)out_.push("\n", 1u);
  }
}

void Console::send(Reply& reply) {
  // take_input() guarantees room for max_reply + newline before a command runs.
  if (out_.push(reply.data(), reply.size())) {
    send_newline();
  }
}

void Console::send_error(ErrorCode code, const char* message) {
  Reply reply;
  reply.text("err ").text(error_code_name(code)).text(" ").text(message);
  ++errors_;
  send(reply);
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
      if (count > words.size()) {
        // No command takes this many words.
        if (is_command(words[0])) {
          send_error(ErrorCode::wrong_arity, "too many words");
        } else {
          send_error(ErrorCode::unknown_command, "unknown command (try help)");
        }
        return;
      }
      execute(words.data(), count);
      return;
    }
    case LineEvent::too_long:
      ++commands_;
      send_error(ErrorCode::line_too_long, "line longer than 127 bytes refused");
      return;
    case LineEvent::bad_byte:
      ++commands_;
      send_error(ErrorCode::non_ascii, "line holds a non-ASCII or control byte");
      return;
    case LineEvent::none:
    case LineEvent::empty:
    case LineEvent::cancelled:
      return;
  }
}

void Console::execute(const Token* words, std::size_t count) {
  const Token& command = words[0];
  if (command.is("help")) {
    if (count != 1u) {
      send_error(ErrorCode::wrong_arity, "usage: help");
      return;
    }
    listing_ = Listing::help;
    listing_index_ = 0u;
    continue_listing();
  } else if (command.is("params")) {
    if (count != 1u) {
      send_error(ErrorCode::wrong_arity, "usage: params");
      return;
    }
    listing_ = Listing::params;
    listing_index_ = 0u;
    continue_listing();
  } else if (command.is("version")) {
    cmd_version(count);
  } else if (command.is("status")) {
    cmd_status(count);
  } else if (command.is("get")) {
    cmd_get(words, count);
  } else if (command.is("set")) {
    cmd_set(words, count);
  } else if (command.is("save")) {
    cmd_save(count);
  } else if (command.is("load")) {
    cmd_load(count);
  } else if (command.is("defaults")) {
    cmd_defaults(count);
  } else if (command.is("provenance")) {
    cmd_provenance(count);
  } else if (command.is("odom")) {
    cmd_odom(words, count);
  } else if (command.is("drive")) {
    cmd_drive(words, count);
  } else if (command.is("stop")) {
    cmd_stop(count);
  } else if (command.is("run")) {
    cmd_run(words, count);
  } else if (command.is("umbmark")) {
    cmd_umbmark(words, count);
  } else if (command.is("stream")) {
    cmd_stream(words, count);
  } else if (command.is("echo")) {
    cmd_echo(words, count);
  } else {
    send_error(ErrorCode::unknown_command, "unknown command (try help)");
  }
}

void Console::continue_listing() {
  while (listing_ != Listing::none && out_.free_space() >= max_reply + 2u) {
    Reply line;
    if (listing_ == Listing::help) {
      if (listing_index_ < kHelpCount) {
        line.text("# ").text(kHelp[listing_index_++]);
        send(line);
        continue;
      }
      line.text("ok").pair_u("commands", kHelpCount);
    } else {
      if (listing_index_ < params::param_count) {
        const auto id = static_cast<params::ParamId>(listing_index_++);
        const params::ParamInfo& info = params::param_info(id);
        line.text("# ").text(info.name).text("=").number(params_.get(id), kParamDecimals);
        line.pair_s("unit", info.unit)
            .pair("min", info.min, kParamDecimals)
            .pair("max", info.max, kParamDecimals)
            .pair("default", params::default_value(id), kParamDecimals);
        send(line);
        continue;
      }
      line.text("ok").pair_u("params", params::param_count).pair_u("unsaved", unsaved_ ? 1u : 0u);
    }
    send(line);
    listing_ = Listing::none;
  }
}

void Console::emit_stream(std::uint32_t now_us) {
  if (static_cast<std::int32_t>(now_us - stream_next_us_) < 0) {
    return;
  }
  stream_next_us_ += stream_period_us_;
  if (static_cast<std::int32_t>(now_us - stream_next_us_) >= 0) {
    stream_next_us_ = now_us + stream_period_us_;  // fell behind: skip, do not burst
  }
  const drive::Pose pose = loop_.pose();
  Reply line;
  line.text("# odom")
      .pair_u("t_ms", clock_us_ / 1000u)
      .pair("x_mm", static_cast<double>(pose.x_m) * 1000.0, kPoseDecimals)
      .pair("y_mm", static_cast<double>(pose.y_m) * 1000.0, kPoseDecimals)
      .pair("theta_deg", static_cast<double>(pose.theta_rad) * 180.0 / kPi, kPoseDecimals);
  // Stream lines never take the room a reply needs: dropped (and counted) instead.
  const std::size_t newline = options_.crlf ? 2u : 1u;
  if (out_.free_space() < line.size() + newline + max_reply + 8u) {
    ++stream_dropped_;
    return;
  }
  send(line);
}

bool Console::number_arg(const Token& token, double lo, double hi, double& value) {
  double parsed = 0.0;
  if (!parse_number(token, parsed)) {
    send_error(ErrorCode::bad_number, "not a finite decimal number");
    return false;
  }
  if (parsed < lo || parsed > hi) {
    Reply reply;
    reply.text("err ").text(error_code_name(ErrorCode::out_of_range)).text(" allowed");
    reply.pair("min", lo, kParamDecimals).pair("max", hi, kParamDecimals);
    ++errors_;
    send(reply);
    return false;
  }
  value = parsed;
  return true;
}

bool Console::apply(const params::ParamSet& candidate) {
  if (!loop_.configure(params::to_drive_config(candidate))) {
    send_error(ErrorCode::rejected,
               "drive refused the values (wheelbase_mm > wheel_diameter_mm/4)");
    return false;
  }
  params_ = candidate;
  return true;
}

bool Console::path_running(const drive::LoopStatus& status) const {
  if (pending_ != Pending::none && status.ticks == pending_ticks_) {
    return pending_ == Pending::run;
  }
  return status.mode == drive::Mode::path;
}

bool Console::moving(const drive::LoopStatus& status) const {
  if (pending_ != Pending::none && status.ticks == pending_ticks_) {
    return pending_ == Pending::run || pending_ == Pending::drive;
  }
  return status.mode == drive::Mode::path || status.mode == drive::Mode::drive;
}

void Console::note_pending(Pending pending) {
  pending_ = pending;
  pending_ticks_ = loop_.status().ticks;
}

void Console::cmd_version(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: version");
    return;
  }
  Reply reply;
  reply.text("ok")
      .pair_s("name", "odocal")
      .pair_s("version", project_version)
      .pair_u("protocol", protocol_version)
      .pair_u("record_format", params::record_format_version);
  send(reply);
}

void Console::cmd_status(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: status");
    return;
  }
  const drive::LoopStatus status = loop_.status();
  Reply reply;
  reply.text("ok").pair_s("mode", drive::mode_name(status.mode));
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
      .pair("tick_us_avg", status.tick_us_avg, kPoseDecimals)
      .pair("tick_us_max", status.tick_us_max, kPoseDecimals)
      .pair_u("illegal_l", status.illegal_left)
      .pair_u("illegal_r", status.illegal_right)
      .pair("left_radps", status.left_radps, kPoseDecimals)
      .pair("right_radps", status.right_radps, kPoseDecimals)
      .pair_u("unsaved", unsaved_ ? 1u : 0u)
      .pair_u("umbmark_cw", cw_count_)
      .pair_u("umbmark_ccw", ccw_count_)
      .pair_u("stream_dropped", c.stream_dropped)
      .pair_u("rx_dropped", c.rx_dropped);
  if (options_.status_pairs != nullptr) {
    reply.append_with([this](char* out, std::size_t capacity) {
      return options_.status_pairs(options_.status_context, out, capacity);
    });
  }
  send(reply);
}

void Console::cmd_get(const Token* words, std::size_t count) {
  if (count != 2u) {
    send_error(ErrorCode::wrong_arity, "usage: get <name>");
    return;
  }
  params::ParamId id{};
  if (!params::find_param(words[1].text, words[1].length, id)) {
    send_error(ErrorCode::unknown_parameter, "no such parameter (see params)");
    return;
  }
  Reply reply;
  reply.text("ok").pair(params::param_info(id).name, params_.get(id), kParamDecimals);
  send(reply);
}

void Console::cmd_set(const Token* words, std::size_t count) {
  if (count != 3u) {
    send_error(ErrorCode::wrong_arity, "usage: set <name> <value>");
    return;
  }
  params::ParamId id{};
  if (!params::find_param(words[1].text, words[1].length, id)) {
    send_error(ErrorCode::unknown_parameter, "no such parameter (see params)");
    return;
  }
  const params::ParamInfo& info = params::param_info(id);
  double value = 0.0;
  if (!number_arg(words[2], static_cast<double>(info.min), static_cast<double>(info.max), value)) {
    return;
  }
  if (info.integer && std::floor(value) != value) {
    send_error(ErrorCode::bad_number, "a whole number is required");
    return;
  }
  const auto stored = static_cast<float>(value);
  if (!params::in_range(id, stored)) {  // rounding to float crossed a bound
    send_error(ErrorCode::out_of_range, "value rounds outside the range");
    return;
  }
  if (path_running(loop_.status())) {
    send_error(ErrorCode::busy, "a path is running; stop first");
    return;
  }
  params::ParamSet candidate = params_;
  candidate.set(id, stored);
  if (is_wheel_factor(id)) {
    candidate.wheel = params::Provenance{};
    candidate.wheel.method = params::FactorMethod::manual;
  } else if (is_lateral_factor(id)) {
    candidate.lateral = params::Provenance{};
    candidate.lateral.method = params::FactorMethod::manual;
  }
  if (!apply(candidate)) {
    return;
  }
  unsaved_ = true;
  Reply reply;
  reply.text("ok").pair(info.name, stored, kParamDecimals);
  send(reply);
}

void Console::cmd_save(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: save");
    return;
  }
  if (moving(loop_.status())) {
    send_error(ErrorCode::busy, "the robot is moving; stop first");
    return;
  }
  params::StoreInfo info;
  const params::StoreResult result = store_.save(params_, info);
  if (result != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(result));
    return;
  }
  unsaved_ = false;
  Reply reply;
  reply.text("ok")
      .pair_u("sequence", info.record.sequence)
      .pair_u("sector", info.sector)
      .pair_u("slot", info.slot);
  send(reply);
}

void Console::cmd_load(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: load");
    return;
  }
  if (moving(loop_.status())) {
    send_error(ErrorCode::busy, "the robot is moving; stop first");
    return;
  }
  params::ParamSet loaded;
  params::StoreInfo info;
  const params::StoreResult result = store_.load(loaded, info);
  if (result == params::StoreResult::empty) {
    send_error(ErrorCode::store_empty, params::to_string(result));
    return;
  }
  if (result == params::StoreResult::newer_version) {
    Reply reply;
    reply.text("err ").text(error_code_name(ErrorCode::store_version));
    reply.text(" record format ");
    char digits[8];
    reply.bytes(digits, format_unsigned(info.record.version, digits, sizeof digits));
    reply.text(" is newer than this firmware's ");
    reply.bytes(digits, format_unsigned(params::record_format_version, digits, sizeof digits));
    ++errors_;
    send(reply);
    return;
  }
  if (result != params::StoreResult::ok) {
    send_error(ErrorCode::store_error, params::to_string(result));
    return;
  }
  if (!apply(loaded)) {
    return;
  }
  unsaved_ = false;
  Reply reply;
  reply.text("ok")
      .pair_u("sequence", info.record.sequence)
      .pair_u("version", info.record.version)
      .pair_u("migrated", info.record.migrated ? 1u : 0u);
  send(reply);
}

void Console::cmd_defaults(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: defaults");
    return;
  }
  if (moving(loop_.status())) {
    send_error(ErrorCode::busy, "the robot is moving; stop first");
    return;
  }
  if (!apply(default_set())) {
    return;
  }
  unsaved_ = true;
  Reply reply;
  reply.text("ok").pair_u("params", params::param_count).pair_u("unsaved", 1u);
  send(reply);
}

void Console::cmd_provenance(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: provenance");
    return;
  }
  Reply reply;
  reply.text("ok")
      .pair_s("wheel_method", params::method_name(params_.wheel.method))
      .pair_u("wheel_runs", params_.wheel.runs)
      .pair_u("wheel_date", params_.wheel.date_unix_s)
      .pair("wheel_e_max_syst_mm", params_.wheel.quality_mm, kPoseDecimals)
      .pair_s("lateral_method", params::method_name(params_.lateral.method))
      .pair_u("lateral_runs", params_.lateral.runs)
      .pair_u("lateral_date", params_.lateral.date_unix_s);
  send(reply);
}

void Console::cmd_odom(const Token* words, std::size_t count) {
  if (count == 2u && words[1].is("reset")) {
    if (path_running(loop_.status())) {
      // The path's segments end on odometry: zeroing it mid-path would stretch the segment.
      send_error(ErrorCode::busy, "a path is running; stop first");
      return;
    }
    loop_.reset_pose();
  } else if (count == 2u) {
    send_error(ErrorCode::bad_argument, "usage: odom [reset]");
    return;
  } else if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: odom [reset]");
    return;
  }
  const drive::Pose pose = loop_.pose();
  Reply reply;
  reply.text("ok")
      .pair("x_mm", static_cast<double>(pose.x_m) * 1000.0, kPoseDecimals)
      .pair("y_mm", static_cast<double>(pose.y_m) * 1000.0, kPoseDecimals)
      .pair("theta_deg", static_cast<double>(pose.theta_rad) * 180.0 / kPi, kPoseDecimals);
  send(reply);
}

void Console::cmd_drive(const Token* words, std::size_t count) {
  if (count != 3u && count != 4u) {
    send_error(ErrorCode::wrong_arity, "usage: drive <v_mps> <w_radps> [ms]");
    return;
  }
  double v = 0.0;
  double w = 0.0;
  if (!number_arg(words[1], -5.0, 5.0, v) || !number_arg(words[2], -50.0, 50.0, w)) {
    return;
  }
  std::uint32_t ms = 0u;
  if (count == 4u) {
    double parsed = 0.0;
    if (!number_arg(words[3], 0.0, 600000.0, parsed)) {
      return;
    }
    if (std::floor(parsed) != parsed) {
      send_error(ErrorCode::bad_number, "ms must be a whole number");
      return;
    }
    ms = static_cast<std::uint32_t>(parsed);
  }
  drive::Twist twist;
  twist.v_mps = static_cast<float>(v);
  twist.w_radps = static_cast<float>(w);
  if (!loop_.drive(twist, ms)) {
    send_error(ErrorCode::fault, "drive faulted; stop acknowledges");
    return;
  }
  note_pending(Pending::drive);
  Reply reply;
  reply.text("ok")
      .pair("v_mps", v, kPoseDecimals)
      .pair("w_radps", w, kPoseDecimals)
      .pair_u("ms", ms);
  send(reply);
}

void Console::cmd_stop(std::size_t count) {
  if (count != 1u) {
    send_error(ErrorCode::wrong_arity, "usage: stop");
    return;
  }
  loop_.stop();
  note_pending(Pending::stop);
  Reply reply;
  reply.text("ok").pair_s("mode", "idle");
  send(reply);
}

void Console::cmd_run(const Token* words, std::size_t count) {
  if (count < 2u) {
    send_error(ErrorCode::wrong_arity,
               "usage: run umbmark-cw|umbmark-ccw <side_m> | line <m> | unseen");
    return;
  }
  const Token& name = words[1];
  const bool square = name.is("umbmark-cw") || name.is("umbmark-ccw");
  const bool line = name.is("line");
  const bool unseen = name.is("unseen");
  if (!square && !line && !unseen) {
    send_error(ErrorCode::bad_argument, "unknown path (umbmark-cw umbmark-ccw line unseen)");
    return;
  }
  if (count != (unseen ? 2u : 3u)) {
    send_error(ErrorCode::wrong_arity, unseen ? "usage: run unseen" : "usage: run <path> <m>");
    return;
  }
  double length_m = 0.0;
  if (!unseen && !number_arg(words[2], 0.01, 20.0, length_m)) {
    return;
  }
  const drive::LoopStatus status = loop_.status();
  if (path_running(status)) {
    send_error(ErrorCode::busy, "a path is running; stop first");
    return;
  }
  drive::Path path;
  if (square) {
    path = drive::make_umbmark_square(name.is("umbmark-cw"), static_cast<float>(length_m));
  } else if (line) {
    path = drive::make_line(static_cast<float>(length_m));
  } else {
    path = drive::make_unseen_path();
  }
  if (!loop_.run(path)) {
    send_error(ErrorCode::fault, "drive faulted; stop acknowledges");
    return;
  }
  note_pending(Pending::run);
  if (square) {
    umbmark_side_mm_ = length_m * 1000.0;
  }
  Reply reply;
  reply.text("ok").pair_s("path", drive::path_name(path.id)).pair_u("segments", path.count);
  if (!unseen) {
    reply.pair("length_m", length_m, kPoseDecimals);
  }
  send(reply);
}

void Console::cmd_umbmark(const Token* words, std::size_t count) {
  if (count < 2u) {
    send_error(ErrorCode::wrong_arity, "usage: umbmark clear|add|side|solve|apply");
    return;
  }
  const Token& sub = words[1];
  if (sub.is("clear")) {
    if (count != 2u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark clear");
      return;
    }
    cw_count_ = 0u;
    ccw_count_ = 0u;
    umbmark_solved_ = false;
    Reply reply;
    reply.text("ok").pair_u("cw", 0u).pair_u("ccw", 0u);
    send(reply);
  } else if (sub.is("add")) {
    if (count != 5u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark add cw|ccw <x_mm> <y_mm>");
      return;
    }
    const bool cw = words[2].is("cw");
    if (!cw && !words[2].is("ccw")) {
      send_error(ErrorCode::bad_argument, "direction is cw or ccw");
      return;
    }
    double x = 0.0;
    double y = 0.0;
    if (!number_arg(words[3], -1.0e6, 1.0e6, x) || !number_arg(words[4], -1.0e6, 1.0e6, y)) {
      return;
    }
    std::size_t& n = cw ? cw_count_ : ccw_count_;
    if (n >= umbmark_capacity) {
      send_error(ErrorCode::umbmark_full, "16 runs per direction at most");
      return;
    }
    (cw ? cw_ : ccw_)[n] = calib::ReturnError{x, y};
    ++n;
    umbmark_solved_ = false;
    Reply reply;
    reply.text("ok").pair_u("cw", cw_count_).pair_u("ccw", ccw_count_);
    send(reply);
  } else if (sub.is("side")) {
    if (count != 3u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark side <side_m>");
      return;
    }
    double side_m = 0.0;
    if (!number_arg(words[2], 0.01, 20.0, side_m)) {
      return;
    }
    umbmark_side_mm_ = side_m * 1000.0;
    umbmark_solved_ = false;
    Reply reply;
    reply.text("ok").pair("side_mm", umbmark_side_mm_, kPoseDecimals);
    send(reply);
  } else if (sub.is("solve")) {
    if (count > 3u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark solve [exact]");
      return;
    }
    if (count == 3u && !words[2].is("exact")) {
      send_error(ErrorCode::bad_argument, "usage: umbmark solve [exact]");
      return;
    }
    calib::UmbmarkInput input;
    input.cw = cw_.data();
    input.cw_count = cw_count_;
    input.ccw = ccw_.data();
    input.ccw_count = ccw_count_;
    input.side_mm = umbmark_side_mm_;
    input.wheelbase_mm = static_cast<double>(params_.get(params::ParamId::wheelbase_mm));
    input.exact = count == 3u;
    calib::UmbmarkResult result;
    const calib::UmbmarkStatus status = calib::solve_umbmark(input, result);
    if (status != calib::UmbmarkStatus::ok) {
      send_error(ErrorCode::umbmark_failed, calib::to_string(status));
      return;
    }
    umbmark_result_ = result;
    umbmark_solved_ = true;
    Reply reply;
    reply.text("ok")
        .pair("e_d", result.e_d, kParamDecimals)
        .pair("e_b", result.e_b, kParamDecimals)
        .pair("c_l", result.c_l, kParamDecimals)
        .pair("c_r", result.c_r, kParamDecimals)
        .pair("wheelbase_new_mm", result.wheelbase_new_mm, kPoseDecimals)
        .pair("alpha_deg", result.alpha_deg, kParamDecimals)
        .pair("beta_deg", result.beta_deg, kParamDecimals)
        .pair("e_max_syst_mm", result.e_max_syst_mm, kPoseDecimals)
        .pair("sem_mm", result.sem_mm, kPoseDecimals)
        .pair_u("second_pass_recommended", result.second_pass_recommended ? 1u : 0u)
        .pair("side_mm", umbmark_side_mm_, kPoseDecimals)
        .pair_u("runs", cw_count_ + ccw_count_)
        .pair_s("method", input.exact ? "umbmark-exact" : "umbmark");
    send(reply);
  } else if (sub.is("apply")) {
    if (count > 3u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark apply [unix_s]");
      return;
    }
    std::uint32_t date = 0u;
    if (count == 3u && !parse_unsigned(words[2], date)) {
      send_error(ErrorCode::bad_number, "unix_s is a whole number of seconds");
      return;
    }
    if (!umbmark_solved_) {
      send_error(ErrorCode::not_solved, "run umbmark solve first");
      return;
    }
    if (moving(loop_.status())) {
      send_error(ErrorCode::busy, "the robot is moving; stop first");
      return;
    }
    calib::WheelFactors current;
    current.c_l = static_cast<double>(params_.get(params::ParamId::c_l));
    current.c_r = static_cast<double>(params_.get(params::ParamId::c_r));
    current.wheelbase_mm = static_cast<double>(params_.get(params::ParamId::wheelbase_mm));
    const calib::WheelFactors next = calib::compose(current, umbmark_result_);
    params::ParamSet candidate = params_;
    candidate.set(params::ParamId::c_l, static_cast<float>(next.c_l));
    candidate.set(params::ParamId::c_r, static_cast<float>(next.c_r));
    candidate.set(params::ParamId::wheelbase_mm, static_cast<float>(next.wheelbase_mm));
    if (!params::in_range(params::ParamId::c_l, candidate.get(params::ParamId::c_l)) ||
        !params::in_range(params::ParamId::c_r, candidate.get(params::ParamId::c_r)) ||
        !params::in_range(params::ParamId::wheelbase_mm,
                          candidate.get(params::ParamId::wheelbase_mm))) {
      send_error(ErrorCode::out_of_range, "the factors fall outside their ranges; not applied");
      return;
    }
    candidate.wheel.method =
        umbmark_result_.exact ? params::FactorMethod::umbmark_exact : params::FactorMethod::umbmark;
    candidate.wheel.runs = static_cast<std::uint16_t>(cw_count_ + ccw_count_);
    candidate.wheel.date_unix_s = date;
    candidate.wheel.quality_mm = static_cast<float>(umbmark_result_.e_max_syst_mm);
    if (!apply(candidate)) {
      return;
    }
    unsaved_ = true;
    // The runs were measured with the old factors: a second pass starts from new runs.
    cw_count_ = 0u;
    ccw_count_ = 0u;
    umbmark_solved_ = false;
    Reply reply;
    reply.text("ok")
        .pair("c_l", params_.get(params::ParamId::c_l), kParamDecimals)
        .pair("c_r", params_.get(params::ParamId::c_r), kParamDecimals)
        .pair("wheelbase_mm", params_.get(params::ParamId::wheelbase_mm), kParamDecimals)
        .pair_s("method", params::method_name(params_.wheel.method))
        .pair_u("runs", params_.wheel.runs)
        .pair_u("unsaved", 1u);
    send(reply);
  } else {
    send_error(ErrorCode::bad_argument, "usage: umbmark clear|add|side|solve|apply");
  }
}

void Console::cmd_stream(const Token* words, std::size_t count) {
  if (count == 2u && words[1].is("off")) {
    streaming_ = false;
    Reply reply;
    reply.text("ok").pair_s("stream", "off");
    send(reply);
    return;
  }
  if (count == 3u && words[1].is("odom")) {
    double hz = 0.0;
    if (!number_arg(words[2], 0.1, 100.0, hz)) {
      return;
    }
    streaming_ = true;
    stream_period_us_ = static_cast<std::uint32_t>(1.0e6 / hz + 0.5);
    stream_next_us_ = last_now_us_ + stream_period_us_;
    Reply reply;
    reply.text("ok").pair_s("stream", "odom").pair("hz", hz, kPoseDecimals);
    send(reply);
    return;
  }
  if (count >= 2u && !words[1].is("odom") && !words[1].is("off")) {
    send_error(ErrorCode::bad_argument, "usage: stream odom <hz> | stream off");
    return;
  }
  send_error(ErrorCode::wrong_arity, "usage: stream odom <hz> | stream off");
}

void Console::cmd_echo(const Token* words, std::size_t count) {
  if (count != 2u) {
    send_error(ErrorCode::wrong_arity, "usage: echo on|off");
    return;
  }
  if (!words[1].is("on") && !words[1].is("off")) {
    send_error(ErrorCode::bad_argument, "usage: echo on|off");
    return;
  }
  echo_ = words[1].is("on");
  options_.echo = echo_ ? EchoMode::on : EchoMode::off;
  Reply reply;
  reply.text("ok").pair_s("echo", echo_ ? "on" : "off");
  send(reply);
}

}  // namespace odocal::console
