#pragma once
/// @file
/// The robot's serial console: line editing, parsing, and dispatch into the drive loop, the
/// parameter table and store, and the on-robot UMBmark. Protocol: docs/console.md.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "odocal/calib/umbmark.hpp"
#include "odocal/console/line_editor.hpp"
#include "odocal/console/output_queue.hpp"
#include "odocal/console/spsc_ring.hpp"
#include "odocal/console/text.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/params/param_store.hpp"
#include "odocal/params/param_table.hpp"

namespace odocal::console {

/// Error codes of `err <code> <message>` (docs/console.md). Each has one meaning.
enum class ErrorCode : std::uint8_t {
  line_too_long,      ///< more than 127 bytes before the line end
  non_ascii,          ///< a byte >= 0x80 or a control byte in the line
  unknown_command,    ///< first word is no command
  unknown_parameter,  ///< get/set of a name not in the table
  wrong_arity,        ///< too few or too many words for the command
  bad_argument,       ///< a keyword argument not among the allowed ones
  bad_number,         ///< not a strict finite decimal number (or not whole where required)
  out_of_range,       ///< a number outside the closed range of its parameter or argument
  busy,               ///< refused while a path runs / while the robot moves (docs)
  fault,              ///< the drive refuses motion until `stop` acknowledges its faults
  rejected,           ///< the drive refused the combination of values (cross-field rule)
  store_error,        ///< the block store failed
  store_empty,        ///< `load` found no saved parameters
  store_version,      ///< `load` found a record newer than this firmware
  umbmark_full,       ///< no room for another UMBmark run in that direction
  umbmark_failed,     ///< the UMBmark solver refused the runs (message says why)
  not_solved,         ///< `umbmark apply` without a successful `umbmark solve`
};

/// The code as printed ("line_too_long", ...).
[[nodiscard]] const char* error_code_name(ErrorCode code);

/// Echo of typed characters.
enum class EchoMode : std::uint8_t {
  off,        ///< scripted input (pipes, test harnesses)
  on,         ///< an interactive terminal
  automatic,  ///< off until the input looks like a terminal (backspace, or Enter sent as bare CR)
};

/// What the target chooses.
struct ConsoleOptions {
  EchoMode echo = EchoMode::off;
  bool crlf = true;    ///< end output lines with CR LF (UART, pty) rather than LF (stdio pipes)
  bool banner = true;  ///< `start()` prints a `# odocal ...` line
  /// Optional: the target appends its own ` key=value` pairs (each with a leading space) to the
  /// `status` reply: writes at most `capacity` bytes into `out` and returns how many. Called from
  /// the main loop inside `poll`. Printable ASCII only; anything else is cut off there.
  std::size_t (*status_pairs)(void* context, char* out, std::size_t capacity) = nullptr;
  void* status_context = nullptr;  ///< passed to `status_pairs`
  /// Optional: the parameter set of this robot build, used when the store holds no usable set
  /// and restored by `defaults` (e.g. the simulator's robot file). nullptr, out of range or
  /// refused by the loop: the built-in defaults. Must outlive the console.
  const params::ParamSet* defaults = nullptr;
};

/// Counters reported by `status`.
struct ConsoleCounters {
  std::uint32_t commands = 0u;        ///< lines answered
  std::uint32_t errors = 0u;          ///< of which `err`
  std::uint32_t stream_dropped = 0u;  ///< stream lines dropped because the output queue was full
  std::uint32_t rx_dropped = 0u;      ///< received bytes dropped because the RX ring was full
};

/// The console. Owns the parameter table in RAM (what `get` shows and the loop runs with).
///
/// Wiring: construct it with the console byte stream, the control loop and the parameter store;
/// call `start()` once (loads the saved parameters into the loop); then call `poll(now_us)` from
/// the main loop as often as convenient (every iteration). Received bytes reach the RX ring by one
/// path only (the ring has a single producer): either the stream's `read`, which `poll` calls, or
/// a UART RX interrupt calling `receive_from_isr()` (its stream's `read` then returns 0).
/// `poll` never blocks: output waits in a queue and stream lines are dropped (counted) when it is
/// full; input waits in the RX ring while a reply cannot be queued.
/// Memory: about 2.5 KiB, all inside the object. No heap, no exceptions.
class Console {
 public:
  static constexpr std::size_t rx_capacity = 256u;  ///< RX ring (255 usable bytes)
  static constexpr std::size_t max_reply =
      560u;  ///< longest reply line, bytes (status + target pairs)
  static constexpr std::size_t umbmark_capacity = 16u;  ///< runs kept per direction

  Console(hal::ByteStream& stream, drive::ControlLoop& loop, params::ParamStore& store,
          const ConsoleOptions& options = ConsoleOptions{});

  /// Loads the saved parameters (keeping the defaults when there are none, or they cannot be
  /// used) and configures the loop with them; queues the banner. Main loop, once, before `poll`.
  /// @return what the store said.
  params::StoreResult start(std::uint32_t now_us);

  /// Hands one received byte to the console. ISR-safe (single producer: one ISR or one reader
  /// thread). @return false when the RX ring is full (byte dropped and counted).
  bool receive_from_isr(std::uint8_t byte);

  /// Main-loop work: reads the stream, handles at most one complete line (writing its reply),
  /// emits a due stream line, and writes queued output to the stream. Never blocks.
  /// @param now_us monotonic microseconds (wraps modulo 2^32).
  void poll(std::uint32_t now_us);

  /// True when no received byte waits, no multi-line reply is in progress and the output queue is
  /// empty: the console has answered everything it was given.
  [[nodiscard]] bool idle() const;

  /// The parameter values in force.
  [[nodiscard]] const params::ParamSet& params() const { return params_; }
  /// True when the parameters differ from what was last saved or loaded.
  [[nodiscard]] bool unsaved() const { return unsaved_; }
  [[nodiscard]] ConsoleCounters counters() const;
  /// True while typed characters are echoed (option, `echo on`, or automatic detection).
  [[nodiscard]] bool echo_enabled() const { return echo_; }

 private:
  class Reply;
  enum class Listing : std::uint8_t { none, help, params };
  enum class Pending : std::uint8_t { none, run, drive, stop };

  void take_input();
  void handle_event(LineEvent event);
  void execute(const Token* words, std::size_t count);
  void continue_listing();
  [[nodiscard]] params::ParamSet default_set() const;
  void emit_stream(std::uint32_t now_us);

  void send(Reply& reply);
  void send_error(ErrorCode code, const char* message);
  void send_newline();

  void cmd_version(std::size_t count);
  void cmd_status(std::size_t count);
  void cmd_get(const Token* words, std::size_t count);
  void cmd_set(const Token* words, std::size_t count);
  void cmd_save(std::size_t count);
  void cmd_load(std::size_t count);
  void cmd_defaults(std::size_t count);
  void cmd_provenance(std::size_t count);
  void cmd_odom(const Token* words, std::size_t count);
  void cmd_drive(const Token* words, std::size_t count);
  void cmd_stop(std::size_t count);
  void cmd_run(const Token* words, std::size_t count);
  void cmd_umbmark(const Token* words, std::size_t count);
  void cmd_stream(const Token* words, std::size_t count);
  void cmd_echo(const Token* words, std::size_t count);

  /// Parses `token` into [lo, hi]; sends the error and returns false otherwise.
  bool number_arg(const Token& token, double lo, double hi, double& value);
  /// Applies `candidate` to the loop; sends `rejected` and returns false when the loop refuses.
  bool apply(const params::ParamSet& candidate);
  [[nodiscard]] bool path_running(const drive::LoopStatus& status) const;
  [[nodiscard]] bool moving(const drive::LoopStatus& status) const;
  void note_pending(Pending pending);

  hal::ByteStream& stream_;
  drive::ControlLoop& loop_;
  params::ParamStore& store_;
  ConsoleOptions options_;

  SpscRing<rx_capacity> rx_;
  LineEditor editor_;
  OutputQueue out_;
  bool echo_ = false;
  Listing listing_ = Listing::none;
  std::size_t listing_index_ = 0u;

  params::ParamSet params_{};
  bool unsaved_ = false;

  Pending pending_ = Pending::none;
  std::uint32_t pending_ticks_ = 0u;

  std::array<calib::ReturnError, umbmark_capacity> cw_{};
  std::array<calib::ReturnError, umbmark_capacity> ccw_{};
  std::size_t cw_count_ = 0u;
  std::size_t ccw_count_ = 0u;
  double umbmark_side_mm_ = 4000.0;
  calib::UmbmarkResult umbmark_result_{};
  bool umbmark_solved_ = false;

  bool streaming_ = false;
  std::uint32_t stream_period_us_ = 0u;
  std::uint32_t stream_next_us_ = 0u;
  std::uint64_t clock_us_ = 0u;  ///< unwrapped time since start, µs
  std::uint32_t last_now_us_ = 0u;
  bool clock_started_ = false;

  std::uint32_t commands_ = 0u;
  std::uint32_t errors_ = 0u;
  std::uint32_t stream_dropped_ = 0u;
  std::atomic<std::uint32_t> rx_dropped_{0u};
};

}  // namespace odocal::console
