#pragma once
/// @file
/// The robot's serial console: byte I/O, line editing, and a command table that dispatches each
/// line to its handler (docs/console.md). The parameters in force live in `Settings`; the
/// on-robot calibrations in calib::UmbmarkSession and calib::LateralSession; trials in
/// KeptTrials. The handlers are grouped by area in console/commands_*.cpp.

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "odocal/calib/lateral_session.hpp"
#include "odocal/calib/umbmark_session.hpp"
#include "odocal/console/commands.hpp"
#include "odocal/console/kept_trials.hpp"
#include "odocal/console/line_editor.hpp"
#include "odocal/console/output_queue.hpp"
#include "odocal/console/reply.hpp"
#include "odocal/console/reply_spec.hpp"
#include "odocal/console/self_test.hpp"
#include "odocal/console/settings.hpp"
#include "odocal/console/text.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/drive/trial.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/hal/wall_sensor.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/params/param_table.hpp"

namespace odocal::console {

/// The console's baud rate on a serial line (8N1), what ROSArduinoBridge's `b` answers.
inline constexpr std::uint32_t console_baud = 115200u;

/// Echo of typed characters.
enum class EchoMode : std::uint8_t {
  off,  ///< scripted input (pipes, test harnesses)
  on,   ///< an interactive terminal
  /// off until the input looks like a terminal: a backspace, or an odocal command line ended by
  /// a bare CR (never a ROSArduinoBridge line, never an empty one: diffdrive_arduino sends those)
  automatic,
};

/// A command a target adds to the console (e.g. the simulator's `measure`). Its handler gets the
/// words of the line (words[0] is the name) and writes one reply line into `reply` (starting with
/// "ok" or "err <code>"); it runs in the main loop. Printable ASCII only.
struct TargetCommand {
  const char* name = nullptr;   ///< one word; nullptr = none
  const char* usage = nullptr;  ///< for `help`: "measure: true pose (simulator only)"
  void (*handler)(void* context, const Token* words, std::size_t count, Reply& reply) = nullptr;
  void* context = nullptr;
};

/// How many wall sensors `walls` reports (ConsoleOptions::wall_sensors): a maze robot's usual
/// four.
inline constexpr std::size_t wall_sensor_slots = 4u;

/// What the target chooses. `extra`, `status_pairs`, `defaults` and `wall_sensors` are the target
/// options: the images that use none (the STM32F4 ones) link the console without the code for
/// them (core/src/console/target/, core/CMakeLists.txt), where they must stay unset.
struct ConsoleOptions {
  EchoMode echo = EchoMode::off;
  bool crlf = true;  ///< end output lines with CR LF (UART, pty) rather than LF (stdio pipes)
  /// A `# odocal ... console ...` start-up line, sent before the reply to the first odocal
  /// command line; never once a ROSArduinoBridge line came first (docs/console.md, "Connecting"):
  /// nothing unsolicited reaches a client that reads one line per command.
  bool banner = true;
  /// Appended to that line: the target's own ` key=value` pairs, each with a leading space.
  const char* banner_note = "";
  /// Optional: the target appends its own ` key=value` pairs (each with a leading space) to the
  /// `status` reply: writes at most `capacity` bytes into `out` and returns how many. Called from
  /// the main loop inside `poll`. Printable ASCII only; anything else is cut off there.
  std::size_t (*status_pairs)(void* context, char* out, std::size_t capacity) = nullptr;
  void* status_context = nullptr;  ///< passed to `status_pairs`
  /// Optional: the parameter set of this robot build, used when the store holds no usable set
  /// and restored by `defaults` (e.g. the simulator's robot file). nullptr, out of range or
  /// refused by the loop: the built-in defaults. Must outlive the console.
  const params::ParamSet* defaults = nullptr;
  /// Optional: one command of the target's own.
  TargetCommand extra{};
  /// Optional: the robot's wall sensors, which `walls` reads, in the order left front, left
  /// diagonal, right diagonal, right front; nullptr: that one is absent. The console only reads
  /// them, from the main loop (never while the tick does). Each must outlive the console.
  std::array<hal::WallSensor*, wall_sensor_slots> wall_sensors{};
};

/// Counters reported by `status`.
struct ConsoleCounters {
  std::uint32_t commands = 0u;        ///< lines answered
  std::uint32_t errors = 0u;          ///< of which `err`
  std::uint32_t stream_dropped = 0u;  ///< stream lines dropped because the output queue was full
  std::uint32_t rx_dropped = 0u;      ///< received bytes the stream lost (ByteStream::rx_dropped)
  /// Of `commands`, the questions: lines of a form that changes nothing the robot holds or does
  /// (`get`, `status`, `trial`, ...; marked so in the command table). Not in the `status` reply:
  /// a simulator in lockstep gives such a line no robot time (docs/simulation.md).
  std::uint32_t questions = 0u;
};

/// The console.
///
/// Wiring: construct it with the console byte stream, the control loop and the parameter store;
/// call `start()` once (loads the saved parameters into the loop); then call `poll(now_us)` from
/// the main loop as often as convenient (every iteration). The console reads its input from the
/// stream a byte at a time, only when a whole reply is sure to fit in its output queue; meanwhile
/// input waits in the stream's own receive buffer (the USART's ring, the kernel's tty buffer):
/// the console keeps no receive ring of its own (docs/architecture.md, "The console").
/// `poll` never blocks: output waits in a queue and stream lines are dropped (counted) when it is
/// full.
/// Memory: a few KiB, all inside the object. No heap, no exceptions.
class Console {
 public:
  static constexpr std::size_t max_reply = console::max_reply;  ///< longest reply line, bytes
  static constexpr std::size_t umbmark_capacity = calib::UmbmarkSession::capacity;

  Console(hal::ByteStream& stream, drive::ControlLoop& loop, params::ParamStore& store,
          const ConsoleOptions& options = ConsoleOptions{});

  /// Loads the saved parameters (keeping the defaults when there are none, or they cannot be
  /// used) and configures the loop with them; holds the banner for the first odocal command line
  /// (ConsoleOptions::banner). Main loop, once, before `poll`.
  /// @return what the store said.
  /// Out of line: its parameter set stays off the main loop's frame.
  [[gnu::noinline]] params::StoreResult start(std::uint32_t now_us);

  /// Main-loop work: reads the stream, announces a finished trial (`# done`), handles at most one
  /// complete line (writing its reply), emits due stream lines, and writes queued output to the
  /// stream. Never blocks. @param now_us monotonic microseconds (wraps modulo 2^32).
  void poll(std::uint32_t now_us);

  /// True when no received byte waits, no multi-line reply is in progress and the output queue is
  /// empty: the console has answered everything it was given (but a `selftest` still running,
  /// see `selftest_running`). To know whether a byte waits it reads one ahead from the stream
  /// (kept for the next `poll`), so a stream's end (Ctrl-D, end of file) is seen only once every
  /// byte before it was taken. Main loop.
  [[nodiscard]] bool idle();
  /// True while a `selftest` drives the wheels (its reply is still to come): a host that runs
  /// the robot's time keeps it running until then.
  [[nodiscard]] bool selftest_running() const { return selftest_.running(); }

  /// The parameter values in force.
  [[nodiscard]] const params::ParamSet& params() const { return settings_.values(); }
  /// True when the parameters differ from what was last saved or loaded.
  [[nodiscard]] bool unsaved() const { return settings_.unsaved(); }
  [[nodiscard]] ConsoleCounters counters() const;
  /// True while typed characters are echoed (option, `echo on`, or automatic detection).
  [[nodiscard]] bool echo_enabled() const { return echo_; }

 private:
  /// One row of the command table (commands.hpp).
  using Form = CommandForm;
  /// The list's dispatch calls the handlers below.
  template <class C>
  friend void dispatch_form(C& c, Handler handler, const Token* words, std::size_t count);

  enum class Listing : std::uint8_t { none, help, params, trials };

  // console.cpp: I/O, dispatch, listings, streams. take_input and handle_event out of line:
  // inlined into the main loop, they made one function too long for its literal pools to be
  // shared (the robot's flash).
  [[gnu::noinline]] void take_input();
  /// The next received byte: the one looked ahead at, else one read from the stream.
  /// @return false when none has arrived.
  bool next_byte(std::uint8_t& byte);
  /// The next received byte without taking it; -1 when none has arrived.
  int peek_byte();
  /// True when the line just completed is ROSArduinoBridge's (a one-character first word).
  [[nodiscard]] bool bridge_line() const;
  /// Echo on (automatic mode), for the line just ended by a bare CR: a person typing.
  void detect_terminal();
  [[gnu::noinline]] void handle_event(LineEvent event);
  void execute(const Token* words, std::size_t count);
  /// Sends the start-up line if it is still due (before an odocal command's reply).
  void send_banner();
  void dispatch(Handler handler, const Token* words, std::size_t count);
  /// While a self-test runs: refuses every command but `stop` (err busy), which ends the test
  /// (its `err busy` line first, then stop's own reply). @return true when refused.
  bool refused_by_selftest(Handler handler);
  void continue_listing();
  void note_trials();
  void emit_streams(std::uint32_t now_us);
  void send(Reply& reply);
  /// Before an asynchronous line (`# ...`): clears the line being typed, if echoed.
  /// @return its length (to show again after).
  std::size_t clear_typing();
  /// Sends `line` (begun after clear_typing()), then shows the `typed` text again.
  [[gnu::noinline]] void send_over_typing(Reply& line, std::size_t typed);
  /// The same for a stream line, dropped (and counted, the queue cut back to `mark`) when a reply
  /// would no longer fit.
  void send_async(Reply& line, std::size_t mark, std::size_t typed);
  /// Sends an `err` line (counted in `errors`).
  void send_refusal(Reply& reply);
  void send_error(ErrorCode code, const char* message);
  /// `err <code> usage: <synopsis> | ...` quoting the forms [first, last).
  void send_usage(ErrorCode code, const Form* first, const Form* last);
  /// The same for the form being handled.
  void send_usage(ErrorCode code) { send_usage(code, form_, form_ + 1); }
  void send_newline();

  /// One value of a line written from a spec (`append`, `send_line`): a whole number (at most
  /// 32 bits on the robot), a float, a text, or the address of a 64-bit whole number. Untagged:
  /// the spec's directive says which member is set, and ReplySpec checks that when compiled.
  struct Arg {
    template <typename T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
    explicit Arg(T value) : u(static_cast<std::size_t>(value)) {
      static_assert(sizeof(T) <= sizeof(std::size_t), "a whole number wider than size_t");
    }
    explicit Arg(float value) : f(value) {}
    explicit Arg(const char* value) : s(value) {}
    explicit Arg(const std::uint64_t* value) : u64(value) {}
    explicit Arg(const std::int64_t* value) : i64(value) {}
    explicit Arg(double value) = delete;
    union {
      std::size_t u;
      float f;
      const char* s;
      const std::uint64_t* u64;
      const std::int64_t* i64;
    };
  };
  /// Appends `spec` to `reply`, each `%` directive in it replaced by the next of `args`
  /// (reply_spec.hpp lists the directives). One shared path instead of a call per key and value
  /// at every reply; callers go through append, send_line and send_error_line, whose spec is
  /// checked against its values when compiled.
  static void append_args(Reply& reply, const char* spec, const Arg* args);
  template <typename... Values>
  static void append(Reply& reply, ReplySpec<std::type_identity_t<Values>...> spec,
                     Values... values) {
    if constexpr (sizeof...(Values) == 0u) {
      append_args(reply, spec.text(), nullptr);
    } else {
      const Arg args[] = {Arg(values)...};
      append_args(reply, spec.text(), args);
    }
  }
  /// Which of a two-spec reply's specs to write (append_either, send_either).
  enum class Spec : std::uint8_t {
    full,     ///< every value
    shorter,  ///< the last values left out
  };
  /// Appends the spec `which` says, `full` or `shorter`.
  template <typename... Values>
  static void append_either(Reply& reply, Spec which,
                            ReplySpec<std::type_identity_t<Values>...> full,
                            LeadingReplySpec<std::type_identity_t<Values>...> shorter,
                            Values... values) {
    const Arg args[] = {Arg(values)...};
    append_args(reply, which == Spec::full ? full.text() : shorter.text(), args);
  }
  /// Sends one line written from `spec` (see append_args).
  void send_args(const char* spec, const Arg* args);
  template <typename... Values>
  void send_line(ReplySpec<std::type_identity_t<Values>...> spec, Values... values) {
    if constexpr (sizeof...(Values) == 0u) {
      send_args(spec.text(), nullptr);
    } else {
      const Arg args[] = {Arg(values)...};
      send_args(spec.text(), args);
    }
  }
  /// Sends the spec `which` says, `full` or `shorter`.
  template <typename... Values>
  void send_either(Spec which, ReplySpec<std::type_identity_t<Values>...> full,
                   LeadingReplySpec<std::type_identity_t<Values>...> shorter, Values... values) {
    const Arg args[] = {Arg(values)...};
    send_args(which == Spec::full ? full.text() : shorter.text(), args);
  }
  /// Sends an `err <code> ` line whose message is written from `spec` (counted in `errors`).
  void send_error_args(ErrorCode code, const char* spec, const Arg* args);
  template <typename... Values>
  void send_error_line(ErrorCode code, ReplySpec<std::type_identity_t<Values>...> spec,
                       Values... values) {
    const Arg args[] = {Arg(values)...};
    send_error_args(code, spec.text(), args);
  }
  /// Parses `token` into [lo, hi] (and, with `not_whole` set, requires a whole number as typed,
  /// sending `not_whole` otherwise); sends the error and returns false when refused.
  bool number_arg(const Token& token, float lo, float hi, float& value,
                  const char* not_whole = nullptr);
  /// Parses the `<x_mm> <y_mm>` of a measured point at words[0] and words[1] (as number_arg).
  bool point_args(const Token* words, float& x, float& y);
  /// Parses the optional `unix_s` at words[index] (0 when absent); sends the error when refused.
  bool date_arg(const Token* words, std::size_t count, std::size_t index, std::uint32_t& date,
                std::uint16_t& runs);
  /// Sends the reason a configuration was refused; @return check.ok().
  bool config_accepted(const drive::ConfigCheck& check);
  /// What a command must wait for (refuse_busy).
  enum class Busy : std::uint8_t {
    motion,  ///< any motion (`save`, `load`, the factors' `apply`)
    path,    ///< a path running (`run`, `odom reset`, `set`: a drive command may go on)
  };
  /// Refuses (err busy) and returns true while `busy` holds.
  bool refuse_busy(Busy busy);
  void start_listing(Listing listing);

  // commands_bridge.cpp: ROSArduinoBridge's one-letter commands (docs/ros.md).
  /// Answers a line whose first word is one character, in ROSArduinoBridge's format; `count` 0:
  /// an empty line ended by a bare CR (`words` unused).
  [[gnu::noinline]] void cmd_bridge(const Token* words, std::size_t count);
  // commands_system.cpp
  void cmd_version();
  void cmd_status();
  void cmd_echo(const Token* words);
  // console/target/options.cpp, or console/target/no_options.cpp where the target options are
  // not linked (ConsoleOptions).
  /// Runs the target's command when words[0] names it (its one reply sent). @return false when
  /// it does not.
  bool run_target_command(const Token* words, std::size_t count);
  /// The target command's `help` line; nullptr when there is none.
  [[nodiscard]] const char* target_usage() const;
  /// Appends the target's own ` key=value` pairs to the `status` reply.
  void append_target_status(Reply& reply);
  /// `walls`: each present wall sensor's reflected light (ambient taken away), counts; `err
  /// no_sensors` when there is none. Runs while the robot moves (a mouse reads walls as it
  /// drives). Main loop.
  void cmd_walls();
  /// `walls`' refusal: one text for options.cpp and no_options.cpp.
  static constexpr char no_wall_sensors[] = "this robot has no wall sensors";
  // commands_params.cpp. [[gnu::noinline]]: handlers with a big frame (a parameter set, a drive
  // configuration, the UMBmark solver) stay out of the dispatch's frame, which every command's
  // path (`load` and the store's the deepest) shares (worst-case stack, docs/stm32f4.md).
  /// `get <name>` and `set <name> <value>` (handler: which form; the same reply).
  [[gnu::noinline]] void cmd_param(Handler handler, const Token* words);
  void cmd_save();
  void cmd_load();
  void cmd_defaults();
  void cmd_provenance();
  // commands_motion.cpp
  /// `odom` and `odom reset` (handler: which form).
  void cmd_odom(Handler handler);
  [[gnu::noinline]] void cmd_drive(const Token* words, std::size_t count);
  void cmd_stop();
  /// `run <path>` (handler: which path).
  void cmd_run(Handler handler, const Token* words);
  /// `stream odom|ticks <hz>`, `stream off` (handler: which form).
  void cmd_stream(Handler handler, const Token* words, std::size_t count);
  void cmd_trial(const Token* words, std::size_t count);
  /// `trials` and `trials clear` (handler: which form).
  void cmd_trials(Handler handler);
  // commands_selftest.cpp: `selftest`, moved on from `poll` until its one reply.
  void cmd_selftest(const Token* words, std::size_t count);
  /// Moves the running self-test on; sends its reply when it ends.
  void continue_selftest();
  /// ` path=.. duration_ms=.. count_l=.. count_r=.. x_mm=.. y_mm=.. theta_deg=..`
  static void trial_pairs(Reply& reply, const KeptTrial& trial);
  /// ` x_mm=.. y_mm=.. theta_deg=..` (`odom`, the odom stream, trials)
  static void pose_pairs(Reply& reply, const drive::Pose& pose);
  /// The names of the bits set in `bits`, comma-separated, or `none`. `names`: one name per bit
  /// from bit 0 on, each ended by a NUL, the list by an empty name (`status` faults, `selftest`).
  static void flag_names(Reply& reply, unsigned bits, const char* names);
  // commands_calib.cpp
  void cmd_umbmark_clear();
  void cmd_umbmark_add(const Token* words);
  void cmd_umbmark_side(const Token* words);
  [[gnu::noinline]] void cmd_umbmark_solve(const Token* words, std::size_t count);
  void cmd_lateral_clear();
  void cmd_lateral_add(const Token* words);
  void cmd_lateral_solve();
  /// The two groups of factors, each with its own provenance (params::ParamSet): the group
  /// column of the parameter list (drive_config.hpp).
  using FactorGroup = drive::FactorGroup;
  /// The group's factors in the order its commands take them (commands_calib.cpp).
  static const params::ParamId* factor_ids(FactorGroup group);
  /// `umbmark apply` (wheel) / `lateral apply` (lateral): puts the solved factors in force.
  void cmd_calib_apply(FactorGroup group, const Token* words, std::size_t count);
  /// `fit apply` (wheel) / `lateral set` (lateral): puts host-computed factors in force with
  /// their provenance. Main loop.
  void cmd_host_factors(FactorGroup group, const Token* words, std::size_t count);
  /// Puts the first `count` factors of `group` = `values` in force with their provenance when
  /// the robot is still, they are in range and the drive accepts them, and sends the `ok` line;
  /// sends the refusal otherwise. Out of line: the candidate parameter set is on its frame only.
  [[gnu::noinline]] bool apply_factors(FactorGroup group, const float* values, std::size_t count,
                                       params::FactorMethod method, std::uint16_t runs,
                                       std::uint32_t date, float quality_mm);

  // The small state first, the buffers and the parameter set last: on the robot most accesses
  // then reach their field with a short offset from the object (smaller instructions).
  hal::ByteStream& stream_;
  drive::ControlLoop& loop_;
  ConsoleOptions options_;
  bool echo_ = false;
  bool clock_started_ = false;
  bool held_ = false;         ///< a byte was read ahead (peek_byte): held_byte_
  std::uint8_t held_byte_{};  ///< read from the stream, not yet taken
  Listing listing_ = Listing::none;
  const Form* form_ = command_forms;  ///< the form being handled
  std::size_t listing_index_ = 0u;
  std::uint32_t trial_seen_ = 0u;    ///< number of the last trial announced
  std::uint32_t lateral_used_ = 0u;  ///< number of the last trial `lateral add` took
  SelfTest selftest_;

  /// The timing of one periodic stream (`stream odom|ticks <hz>`).
  struct StreamTimer {
    std::uint32_t period_us = 0u;  ///< 0: off (on, it is at least 1,000 µs)
    std::uint32_t next_us = 0u;
  };
  std::array<StreamTimer, 2> streams_{};  ///< odom, ticks: emitted in this order
  bool ticks_crc_ = false;                ///< `# ticks` lines end with " crc=" (stream ticks crc)
  std::uint64_t clock_us_ = 0u;           ///< unwrapped time since start, µs
  std::uint32_t last_now_us_ = 0u;

  /// The start-up line, held until the first odocal command line (send_banner); dropped at the
  /// first ROSArduinoBridge line.
  bool banner_due_ = false;
  const char* banner_store_ = nullptr;  ///< `store=` word when on defaults; nullptr: loaded
  std::uint32_t banner_sequence_ = 0u;  ///< `sequence=` of the loaded set

  /// The loop's counts at the last `r` (what `e` counts from), modulo 2^32.
  std::uint32_t bridge_zero_left_ = 0u;
  std::uint32_t bridge_zero_right_ = 0u;

  std::uint32_t commands_ = 0u;
  std::uint32_t questions_ = 0u;
  std::uint32_t errors_ = 0u;
  std::uint32_t stream_dropped_ = 0u;

  LineEditor editor_;
  Settings settings_;
  OutputQueue out_;
  calib::UmbmarkSession umbmark_;
  calib::LateralSession lateral_;
  KeptTrials trials_;
};

}  // namespace odocal::console
