#pragma once
/// @file
/// The console's commands, declared once. ODOCAL_CONSOLE_FORMS lists every form of every command
/// in the order `help` prints them; from it come the `Handler` of each form, the robot's form
/// table (`command_forms`) and what a host that keeps a copy of the parameters must forget after
/// sending a line (`Changes`). `find_form` is the one reading of a line's words into its form: the
/// robot's console and the host's client (host/robot_client.hpp) call it.

#include <cstddef>
#include <cstdint>

#include "odocal/console/text.hpp"
#include "odocal/drive/drive_config.hpp"

namespace odocal::console {

/// Flags of a form (CommandForm::flags, bits 0-2).
inline constexpr std::uint8_t form_sub = 1u;     ///< the synopsis' second word selects the form
inline constexpr std::uint8_t form_moving = 2u;  ///< refused while the robot moves
/// A question: answers without changing anything the robot holds or does (the lockstep simulator
/// gives it no robot time; it must change `nothing`).
inline constexpr std::uint8_t form_question = 4u;

/// Which parameters a form may change (CommandForm::flags, bits 3-5). A refused line changes
/// nothing whatever its form.
enum class Changes : std::uint8_t {
  nothing,  ///< no parameter (it may move the robot, or change a session or a stream)
  named,    ///< the one parameter its second word names (`set`)
  wheel,    ///< the wheel group's factors (drive::FactorGroup::wheel)
  lateral,  ///< the lateral group's factors (drive::FactorGroup::lateral)
  any,      ///< any parameter (`load`, `defaults`)
};

/// Every form: X(handler, synopsis, min words, max words, flags, changes). The synopsis is what
/// `help` prints and what a usage refusal quotes; its first word is the command, and its second,
/// for a `form_sub` row, the keyword that selects the form. A command's rows are adjacent (checked
/// when compiled). Full explanations are in docs/console.md (the robot keeps only the synopses).
/// A new command is a row here, its case in Console::dispatch and its handler
/// (docs/architecture.md, "How to add").
// clang-format off
#define ODOCAL_CONSOLE_FORMS(X)                                                                    \
  X(help, "help", 1, 1, form_question, nothing)                                                    \
  X(version, "version", 1, 1, form_question, nothing)                                              \
  X(status, "status", 1, 1, form_question, nothing)                                                \
  X(params, "params", 1, 1, form_question, nothing)                                                \
  X(get, "get <name>", 2, 2, form_question, nothing)                                               \
  X(set, "set <name> <value>", 3, 3, 0, named)                                                     \
  X(save, "save", 1, 1, form_moving, nothing)                                                      \
  X(load, "load", 1, 1, form_moving, any)                                                          \
  X(defaults, "defaults", 1, 1, form_moving, any)                                                  \
  X(provenance, "provenance", 1, 1, form_question, nothing)                                        \
  X(odom, "odom", 1, 1, form_question, nothing)                                                    \
  X(odom_reset, "odom reset", 2, 2, form_sub, nothing)                                             \
  X(walls, "walls", 1, 1, form_question, nothing)                                                  \
  X(drive, "drive <v_mps> <w_radps> [ms]", 3, 4, 0, nothing)                                       \
  X(stop, "stop", 1, 1, 0, nothing)                                                                \
  X(selftest, "selftest [left|right]", 1, 2, form_moving, nothing)                                 \
  X(run_umbmark_cw, "run umbmark-cw <side_m>", 3, 3, form_sub, nothing)                            \
  X(run_umbmark_ccw, "run umbmark-ccw <side_m>", 3, 3, form_sub, nothing)                          \
  X(run_line, "run line <m>", 3, 3, form_sub, nothing)                                             \
  X(run_unseen, "run unseen", 2, 2, form_sub, nothing)                                             \
  X(trial, "trial [N]", 1, 2, form_question, nothing)                                              \
  X(trials, "trials", 1, 1, form_question, nothing)                                                \
  X(trials_clear, "trials clear", 2, 2, form_sub, nothing)                                         \
  X(umbmark_clear, "umbmark clear", 2, 2, form_sub, nothing)                                       \
  X(umbmark_add, "umbmark add cw|ccw <x_mm> <y_mm>", 5, 5, form_sub, nothing)                      \
  X(umbmark_side, "umbmark side <side_m>", 3, 3, form_sub, nothing)                                \
  X(umbmark_solve, "umbmark solve [exact]", 2, 3, form_sub, nothing)                              \
  X(umbmark_apply, "umbmark apply [unix_s [runs]]", 2, 4, form_sub, wheel)                         \
  X(lateral_clear, "lateral clear", 2, 2, form_sub, nothing)                                       \
  X(lateral_add, "lateral add <x_mm> <y_mm>", 4, 4, form_sub, nothing)                             \
  X(lateral_solve, "lateral solve", 2, 2, form_sub, nothing)                                       \
  X(lateral_apply, "lateral apply [unix_s]", 2, 3, form_sub, lateral)                              \
  X(lateral_set, "lateral set <f_lat> <f_lon> [unix_s [runs]]", 4, 6, form_sub, lateral)           \
  X(fit_apply, "fit apply <c_l> <c_r> <wheelbase_mm> [unix_s [runs]] [arc <mm>]", 5, 9, form_sub,  \
    wheel)                                                                                         \
  X(stream_odom, "stream odom <hz>", 3, 3, form_sub, nothing)                                      \
  X(stream_ticks, "stream ticks <hz> [crc]", 3, 4, form_sub, nothing)                              \
  X(stream_off, "stream off", 2, 2, form_sub, nothing)                                             \
  X(echo, "echo on|off", 2, 2, 0, nothing)
// clang-format on

/// What handles a form: one value per row of ODOCAL_CONSOLE_FORMS (Console::dispatch switches on
/// it; the compiler warns on a value it misses).
enum class Handler : std::uint8_t {
#define ODOCAL_CONSOLE_HANDLER(handler, synopsis, min, max, flags, changes) handler,
  ODOCAL_CONSOLE_FORMS(ODOCAL_CONSOLE_HANDLER)
#undef ODOCAL_CONSOLE_HANDLER
};

/// One row of the command table: one form of a command, as `help` lists it. 8 bytes on the robot.
struct CommandForm {
  const char* synopsis;  ///< "umbmark add cw|ccw <x_mm> <y_mm>": help line and usage
  std::uint8_t min_words;
  std::uint8_t max_words;
  std::uint8_t flags;  ///< form_sub, form_moving, form_question; Changes in bits 3-5
  Handler handler;

  [[nodiscard]] constexpr bool has(std::uint8_t flag) const { return (flags & flag) != 0u; }
  [[nodiscard]] constexpr Changes changes() const { return static_cast<Changes>(flags >> 3u); }
};

/// The form table, in `help`'s order.
inline constexpr CommandForm command_forms[] = {
#define ODOCAL_CONSOLE_FORM(handler, synopsis, min, max, flags, changes)                 \
  {synopsis, min, max,                                                                   \
   static_cast<std::uint8_t>((flags) | (static_cast<unsigned>(Changes::changes) << 3u)), \
   Handler::handler},
    ODOCAL_CONSOLE_FORMS(ODOCAL_CONSOLE_FORM)
#undef ODOCAL_CONSOLE_FORM
};
inline constexpr std::size_t command_form_count = sizeof command_forms / sizeof command_forms[0];

/// The ranges of the motion commands' arguments (closed; the robot refuses a value outside with
/// `out_of_range`), for the robot and for a host that reads its command lines (host/motion.hpp).
inline constexpr float run_length_min_m = 0.01f;  ///< `run line|umbmark-cw|umbmark-ccw <m>`
inline constexpr float run_length_max_m = 20.0f;
inline constexpr float drive_v_limit_mps = 5.0f;     ///< `drive <v_mps>`: within +-
inline constexpr float drive_w_limit_radps = 50.0f;  ///< `drive <w_radps>`: within +-
inline constexpr float drive_ms_max = 600000.0f;     ///< `drive ... [ms]`: whole, 0 .. this

/// Where a line's words lead in the table.
struct FormLookup {
  enum class Result : std::uint8_t {
    found,         ///< `form` takes these words
    unknown,       ///< no command has this first word (`first` == `last`)
    wrong_arity,   ///< too few or too many words for the forms in [first, last): every form of
                   ///< the command, or the one its keyword selects
    bad_argument,  ///< no form of the command is selected by these words
  };
  Result result = Result::unknown;
  const CommandForm* first = nullptr;  ///< the forms a refusal quotes: [first, last)
  const CommandForm* last = nullptr;
  const CommandForm* form = nullptr;  ///< found: the form
};

/// The form `words` (`count` of them, the first the command) select: a form selected by its
/// keyword (second word), else the keyword-less form that takes this many words.
[[nodiscard]] FormLookup find_form(const Token* words, std::size_t count);

/// The factors a calibration form puts in force: the wheel group for `wheel_form`, the lateral
/// group for the command's other form (`umbmark apply` / `lateral apply`, `fit apply` / `lateral
/// set`).
constexpr drive::FactorGroup factor_group(Handler handler, Handler wheel_form) {
  return handler == wheel_form ? drive::FactorGroup::wheel : drive::FactorGroup::lateral;
}

/// Each form to its handler: the one switch from a Handler to the console's member that serves it
/// (Console::dispatch calls it with itself, after the self-test's refusal; the compiler warns on a
/// Handler it misses). Written beside the list, so that a new command is its row and its case
/// here, and its handler (declared in console.hpp, defined in the commands_*.cpp of its topic).
template <class C>
void dispatch_form(C& c, Handler handler, const Token* words, std::size_t count) {
  switch (handler) {
    case Handler::help:
      c.start_listing(C::Listing::help);
      return;
    case Handler::version:
      c.cmd_version();
      return;
    case Handler::status:
      c.cmd_status();
      return;
    case Handler::params:
      c.start_listing(C::Listing::params);
      return;
    case Handler::get:
    case Handler::set:
      c.cmd_param(handler, words);
      return;
    case Handler::save:
      c.cmd_save();
      return;
    case Handler::load:
      c.cmd_load();
      return;
    case Handler::defaults:
      c.cmd_defaults();
      return;
    case Handler::provenance:
      c.cmd_provenance();
      return;
    case Handler::odom:
    case Handler::odom_reset:
      c.cmd_odom(handler);
      return;
    case Handler::walls:
      c.cmd_walls();
      return;
    case Handler::drive:
      c.cmd_drive(words, count);
      return;
    case Handler::stop:
      c.cmd_stop();
      return;
    case Handler::selftest:
      c.cmd_selftest(words, count);
      return;
    case Handler::run_umbmark_cw:
    case Handler::run_umbmark_ccw:
    case Handler::run_line:
    case Handler::run_unseen:
      c.cmd_run(handler, words);
      return;
    case Handler::trial:
      c.cmd_trial(words, count);
      return;
    case Handler::trials:
    case Handler::trials_clear:
      c.cmd_trials(handler);
      return;
    case Handler::umbmark_clear:
      c.cmd_umbmark_clear();
      return;
    case Handler::umbmark_add:
      c.cmd_umbmark_add(words);
      return;
    case Handler::umbmark_side:
      c.cmd_umbmark_side(words);
      return;
    case Handler::umbmark_solve:
      c.cmd_umbmark_solve(words, count);
      return;
    case Handler::lateral_clear:
      c.cmd_lateral_clear();
      return;
    case Handler::lateral_add:
      c.cmd_lateral_add(words);
      return;
    case Handler::lateral_solve:
      c.cmd_lateral_solve();
      return;
    case Handler::umbmark_apply:
    case Handler::lateral_apply:
      c.cmd_calib_apply(factor_group(handler, Handler::umbmark_apply), words, count);
      return;
    case Handler::lateral_set:
    case Handler::fit_apply:
      c.cmd_host_factors(factor_group(handler, Handler::fit_apply), words, count);
      return;
    case Handler::stream_odom:
    case Handler::stream_ticks:
    case Handler::stream_off:
      c.cmd_stream(handler, words, count);
      return;
    case Handler::echo:
      c.cmd_echo(words);
      return;
  }
}

}  // namespace odocal::console
