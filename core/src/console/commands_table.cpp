// The console's command table: one row per command form. A row's synopsis is what `help` prints
// and what a wrong_arity / bad_argument refusal quotes; its first word is the command, and its
// second word, for a row marked `sub`, the keyword that selects the form.

#include "odocal/console/console.hpp"

namespace odocal::console {

// `help` lists the rows in this order; a command's rows are adjacent. Full explanations are in
// docs/console.md (the robot keeps only the synopses).
const Console::Form Console::form_table_[] = {
    {"help", 1, 1, form_question, Handler::help},
    {"version", 1, 1, form_question, Handler::version},
    {"status", 1, 1, form_question, Handler::status},
    {"params", 1, 1, form_question, Handler::params},
    {"get <name>", 2, 2, form_question, Handler::get},
    {"set <name> <value>", 3, 3, 0, Handler::set},
    {"save", 1, 1, form_moving, Handler::save},
    {"load", 1, 1, form_moving, Handler::load},
    {"defaults", 1, 1, form_moving, Handler::defaults},
    {"provenance", 1, 1, form_question, Handler::provenance},
    {"odom", 1, 1, form_question, Handler::odom},
    {"odom reset", 2, 2, form_sub, Handler::odom_reset},
    {"drive <v_mps> <w_radps> [ms]", 3, 4, 0, Handler::drive},
    {"stop", 1, 1, 0, Handler::stop},
    {"selftest [left|right]", 1, 2, form_moving, Handler::selftest},
    {"run umbmark-cw <side_m>", 3, 3, form_sub, Handler::run_umbmark_cw},
    {"run umbmark-ccw <side_m>", 3, 3, form_sub, Handler::run_umbmark_ccw},
    {"run line <m>", 3, 3, form_sub, Handler::run_line},
    {"run unseen", 2, 2, form_sub, Handler::run_unseen},
    {"trial [N]", 1, 2, form_question, Handler::trial},
    {"trials", 1, 1, form_question, Handler::trials},
    {"trials clear", 2, 2, form_sub, Handler::trials_clear},
    {"umbmark clear", 2, 2, form_sub, Handler::umbmark_clear},
    {"umbmark add cw|ccw <x_mm> <y_mm>", 5, 5, form_sub, Handler::umbmark_add},
    {"umbmark side <side_m>", 3, 3, form_sub, Handler::umbmark_side},
    {"umbmark solve [exact]", 2, 3, form_sub, Handler::umbmark_solve},
    {"umbmark apply [unix_s [runs]]", 2, 4, form_sub, Handler::umbmark_apply},
    {"lateral clear", 2, 2, form_sub, Handler::lateral_clear},
    {"lateral add <x_mm> <y_mm>", 4, 4, form_sub, Handler::lateral_add},
    {"lateral solve", 2, 2, form_sub, Handler::lateral_solve},
    {"lateral apply [unix_s]", 2, 3, form_sub, Handler::lateral_apply},
    {"lateral set <f_lat> <f_lon> [unix_s [runs]]", 4, 6, form_sub, Handler::lateral_set},
    {"fit apply <c_l> <c_r> <wheelbase_mm> [unix_s [runs]] [arc <mm>]", 5, 9, form_sub,
     Handler::fit_apply},
    {"stream odom <hz>", 3, 3, form_sub, Handler::stream_odom},
    {"stream ticks <hz> [crc]", 3, 4, form_sub, Handler::stream_ticks},
    {"stream off", 2, 2, form_sub, Handler::stream_off},
    {"echo on|off", 2, 2, 0, Handler::echo},
};
const std::size_t Console::form_count_ = sizeof(Console::form_table_) / sizeof(Form);

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
  switch (handler) {
    case Handler::help:
      start_listing(Listing::help);
      return;
    case Handler::version:
      cmd_version();
      return;
    case Handler::status:
      cmd_status();
      return;
    case Handler::params:
      start_listing(Listing::params);
      return;
    case Handler::get:
    case Handler::set:
      cmd_param(handler, words);
      return;
    case Handler::save:
      cmd_save();
      return;
    case Handler::load:
      cmd_load();
      return;
    case Handler::defaults:
      cmd_defaults();
      return;
    case Handler::provenance:
      cmd_provenance();
      return;
    case Handler::odom:
    case Handler::odom_reset:
      cmd_odom(handler);
      return;
    case Handler::drive:
      cmd_drive(words, count);
      return;
    case Handler::stop:
      cmd_stop();
      return;
    case Handler::selftest:
      cmd_selftest(words, count);
      return;
    case Handler::run_umbmark_cw:
    case Handler::run_umbmark_ccw:
    case Handler::run_line:
    case Handler::run_unseen:
      cmd_run(handler, words);
      return;
    case Handler::trial:
      cmd_trial(words, count);
      return;
    case Handler::trials:
    case Handler::trials_clear:
      cmd_trials(handler);
      return;
    case Handler::umbmark_clear:
      cmd_umbmark_clear();
      return;
    case Handler::umbmark_add:
      cmd_umbmark_add(words);
      return;
    case Handler::umbmark_side:
      cmd_umbmark_side(words);
      return;
    case Handler::umbmark_solve:
      cmd_umbmark_solve(words, count);
      return;
    case Handler::lateral_clear:
      cmd_lateral_clear();
      return;
    case Handler::lateral_add:
      cmd_lateral_add(words);
      return;
    case Handler::lateral_solve:
      cmd_lateral_solve();
      return;
    case Handler::umbmark_apply:
    case Handler::lateral_apply:
      cmd_calib_apply(handler == Handler::lateral_apply ? FactorGroup::lateral : FactorGroup::wheel,
                      words, count);
      return;
    case Handler::lateral_set:
    case Handler::fit_apply:
      cmd_host_factors(handler == Handler::fit_apply ? FactorGroup::wheel : FactorGroup::lateral,
                       words, count);
      return;
    case Handler::stream_odom:
    case Handler::stream_ticks:
    case Handler::stream_off:
      cmd_stream(handler, words, count);
      return;
    case Handler::echo:
      cmd_echo(words);
      return;
  }
}

}  // namespace odocal::console
