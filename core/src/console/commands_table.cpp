// The console's command table: names, arity, the moving guard, handlers and `help` lines.

#include "odocal/console/console.hpp"

namespace odocal::console {
namespace {

// `help` lines of each command: usage, then what it does.
constexpr const char* kHelpHelp[] = {"help: this list", nullptr};
constexpr const char* kVersionHelp[] = {"version: firmware and protocol versions", nullptr};
constexpr const char* kStatusHelp[] = {"status: mode path segment faults tick timing counters",
                                       nullptr};
constexpr const char* kParamsHelp[] = {"params: every parameter with value unit range default",
                                       nullptr};
constexpr const char* kGetHelp[] = {"get <name>: one parameter", nullptr};
constexpr const char* kSetHelp[] = {
    "set <name> <value>: change a parameter (refused while a path runs)", nullptr};
constexpr const char* kSaveHelp[] = {"save: persist the parameters (refused while the robot moves)",
                                     nullptr};
constexpr const char* kLoadHelp[] = {"load: reload the saved parameters", nullptr};
constexpr const char* kDefaultsHelp[] = {"defaults: restore every default (not saved until save)",
                                         nullptr};
constexpr const char* kProvenanceHelp[] = {"provenance: how the calibration factors were obtained",
                                           nullptr};
constexpr const char* kOdomHelp[] = {"odom: pose x_mm y_mm theta_deg",
                                     "odom reset: set the pose to zero", nullptr};
constexpr const char* kDriveHelp[] = {
    "drive <v_mps> <w_radps> [ms]: drive at a twist (no ms: until cmd_timeout_ms; ms: a trial)",
    nullptr};
constexpr const char* kStopHelp[] = {
    "stop: stop at once, abandon the path or trial, acknowledge faults", nullptr};
constexpr const char* kRunHelp[] = {"run umbmark-cw <side_m>: UMBmark square, clockwise",
                                    "run umbmark-ccw <side_m>: UMBmark square, counter-clockwise",
                                    "run line <m>: straight calibration line",
                                    "run unseen: Maddahi unseen path (each run is a trial)",
                                    nullptr};
constexpr const char* kTrialHelp[] = {
    "trial [N]: the latest trial or trial N: duration, counts, end pose", nullptr};
constexpr const char* kTrialsHelp[] = {"trials: every kept trial (the last 32)",
                                       "trials clear: forget the kept trials", nullptr};
constexpr const char* kUmbmarkHelp[] = {
    "umbmark clear: forget the entered runs and the solution",
    "umbmark add cw|ccw <x_mm> <y_mm>: one return error, measured minus odometry",
    "umbmark side <side_m>: side of the square to solve with",
    "umbmark solve [exact]: solve UMBmark from the entered runs",
    "umbmark apply [unix_s]: apply the solved factors (not saved until save)",
    nullptr};
constexpr const char* kLateralHelp[] = {
    "lateral clear: forget the entered line trials and the solution",
    "lateral add <x_mm> <y_mm>: where the latest line trial stopped, start frame",
    "lateral solve: F_lat and F_lon from the entered trials (Maddahi eq. 4-5)",
    "lateral apply [unix_s]: apply the solved factors (not saved until save)", nullptr};
constexpr const char* kStreamHelp[] = {"stream odom <hz>: print # odom lines at hz",
                                       "stream ticks <hz>: print # ticks lines (cumulative counts)",
                                       "stream off: stop streaming", nullptr};
constexpr const char* kEchoHelp[] = {"echo on|off: echo typed characters", nullptr};

}  // namespace

// The command table: `help` lists it in this order; dispatch, arity and the moving guard come
// from it. Handlers check what depends on their sub-command.
const Console::Command Console::command_table_[] = {
    {"help", "", kHelpHelp, 1, 1, Guard::none, &Console::cmd_help},
    {"version", "", kVersionHelp, 1, 1, Guard::none, &Console::cmd_version},
    {"status", "", kStatusHelp, 1, 1, Guard::none, &Console::cmd_status},
    {"params", "", kParamsHelp, 1, 1, Guard::none, &Console::cmd_params},
    {"get", "<name>", kGetHelp, 2, 2, Guard::none, &Console::cmd_get},
    {"set", "<name> <value>", kSetHelp, 3, 3, Guard::none, &Console::cmd_set},
    {"save", "", kSaveHelp, 1, 1, Guard::moving, &Console::cmd_save},
    {"load", "", kLoadHelp, 1, 1, Guard::moving, &Console::cmd_load},
    {"defaults", "", kDefaultsHelp, 1, 1, Guard::moving, &Console::cmd_defaults},
    {"provenance", "", kProvenanceHelp, 1, 1, Guard::none, &Console::cmd_provenance},
    {"odom", "[reset]", kOdomHelp, 1, 2, Guard::none, &Console::cmd_odom},
    {"drive", "<v_mps> <w_radps> [ms]", kDriveHelp, 3, 4, Guard::none, &Console::cmd_drive},
    {"stop", "", kStopHelp, 1, 1, Guard::none, &Console::cmd_stop},
    {"run", "umbmark-cw|umbmark-ccw <side_m> | line <m> | unseen", kRunHelp, 2, 3, Guard::none,
     &Console::cmd_run},
    {"trial", "[N]", kTrialHelp, 1, 2, Guard::none, &Console::cmd_trial},
    {"trials", "[clear]", kTrialsHelp, 1, 2, Guard::none, &Console::cmd_trials},
    {"umbmark", "clear|add|side|solve|apply ...", kUmbmarkHelp, 2, 5, Guard::none,
     &Console::cmd_umbmark},
    {"lateral", "clear|add|solve|apply ...", kLateralHelp, 2, 4, Guard::none,
     &Console::cmd_lateral},
    {"stream", "odom <hz> | ticks <hz> | off", kStreamHelp, 2, 3, Guard::none,
     &Console::cmd_stream},
    {"echo", "on|off", kEchoHelp, 2, 2, Guard::none, &Console::cmd_echo},
};
const std::size_t Console::command_count_ = sizeof(Console::command_table_) / sizeof(Command);

}  // namespace odocal::console
