// The way out of every procedure (DESIGN "Sessions on a real robot": an interruption leaves the
// robot as it was). SIGINT, SIGTERM, the end of the input at a prompt, a robot that stops
// answering and a refused result all end here: the robot stopped and its stream off, every setting
// the session changed and did not save put back, session.json and report.html written, the reason
// and the way to resume said, and the documented exit status.

#include <algorithm>
#include <cmath>
#include <exception>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

bool same_value(double a, double b) {
  return std::fabs(a - b) <= 1e-6 * std::max(1.0, std::fabs(b));
}

/// What a session may change on the robot: the factors (every procedure), the cruise speed
/// (lateral), the wiring fix (the self-test).
struct Settings {
  Factors factors;
  double cruise_mps = 0.0;
  std::optional<double> wiring_fix;
};

Settings settings_now(Context& c) {
  Settings s;
  s.factors = c.factors();
  s.cruise_mps = c.get(ParamId::v_max_mps);
  if (c.initial_wiring_fix) {
    s.wiring_fix = c.get(ParamId::wiring_fix);
  }
  return s;
}

bool same_factors(const Factors& f, const Factors& i) {
  std::vector<double> values;
  i.each([&values](ParamId, double value) { values.push_back(value); });
  std::size_t k = 0;
  bool same = true;
  f.each([&](ParamId, double value) { same = same && same_value(value, values[k++]); });
  return same;
}

bool as_started(const Context& c, const Settings& s) {
  return same_factors(s.factors, c.initial) && same_value(s.cruise_mps, c.initial_cruise_mps) &&
         (!c.initial_wiring_fix || (s.wiring_fix && *s.wiring_fix == *c.initial_wiring_fix));
}

/// Stops the robot and its stream. The replies still on their way (to the interrupted command, to
/// the signal handler's `stop`) are drained after, so that none is taken for a reply below; the
/// stream is off first, so that the drain ends. A command the robot was busy with (the self-test
/// turns its wheels for about 2 s) answers first: hence the robot's usual 5 s.
void stop_robot(Context& c) {
  c.robot.on_ticks(nullptr);
  static_cast<void>(c.robot.command("stop", 5000));
  static_cast<void>(c.robot.command("stream off", 5000));
  c.robot.drain(300);
}

/// Each setting `set` back to what was in force at the start.
void set_back(Context& c) {
  c.set_factors(c.initial);
  c.set(ParamId::v_max_mps, c.initial_cruise_mps);
  if (c.initial_wiring_fix) {
    c.set(ParamId::wiring_fix, *c.initial_wiring_fix);
  }
}

/// The robot stopped, and every setting the session changed put back to what was in force when it
/// started (the saved set reloaded when nothing was unsaved then, so that its provenance comes back
/// too). Says on the log what it did; never throws.
void put_back(Context& c) {
  try {
    stop_robot(c);
    // A value set and set back again leaves the robot unsaved: its saved set is reloaded then too.
    const Reply status = c.robot.status();
    const bool unsaved = status.text("unsaved") != "0";
    if (as_started(c, settings_now(c)) && (c.initial_unsaved || !unsaved)) {
      c.log << "The robot is stopped; its factors and settings are as they were when the session "
               "started.\n";
      return;
    }
    // A robot that has never saved and had nothing unsaved ran on its defaults: `defaults` brings
    // them back with their provenance (`set` would leave them "manual") and nothing unsaved (the
    // firmware's reply to `defaults` on a robot whose store is empty).
    const auto store = status.pairs.find("store");
    const bool never_saved = store != status.pairs.end() && store->second == "empty";
    const bool reloaded =
        !c.initial_unsaved && c.robot.command(never_saved ? "defaults" : "load", 5000).ok;
    if (!reloaded || !as_started(c, settings_now(c))) {
      set_back(c);
    }
    const Settings now = settings_now(c);
    if (!as_started(c, now)) {
      c.log << "WARNING: could not put the factors back exactly; in force now: "
            << factors_json(now.factors).dump() << "\n";
      return;
    }
    const Factors& f = now.factors;
    c.log << fmt::format(
        "The robot is stopped. The factors this session applied and did not save were put back "
        "to what was in force when it started{}: c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} "
        "f_lat={:.6f} f_lon={:.6f}{}{}\n",
        !reloaded     ? ""
        : never_saved ? " (its defaults: it has never saved)"
                      : " (its saved set, reloaded)",
        f.c_l, f.c_r, f.wheelbase_mm, f.f_lat, f.f_lon,
        f.wheelbase_arc_mm != 0.0 ? fmt::format(" wheelbase_arc_mm={:.3f}", f.wheelbase_arc_mm)
                                  : std::string(),
        now.wiring_fix ? fmt::format(" wiring_fix={:.0f}", *now.wiring_fix) : std::string());
  } catch (const std::exception& e) {
    c.log << "WARNING: the robot did not answer while stopping it and putting its factors back ("
          << e.what()
          << "). Nothing was saved: restarting the robot brings back its saved factors.\n";
  }
}

/// After a reset: what the robot lost, and that the run under way does not count.
void say_what_a_reset_lost(Context& c) {
  std::string applied;
  // The factors last read before the reset (a read after it meets the start-up line first), when
  // they are not those the session started with: only the factors count here (the wiring fix
  // and the cruise speed are not factors, and the start values were never "applied").
  if (c.last_factors && !same_factors(*c.last_factors, c.initial)) {
    const Factors& f = *c.last_factors;
    applied = fmt::format(
        " This session had applied c_l={:.6f} c_r={:.6f} wheelbase_mm={:.3f} f_lat={:.6f} "
        "f_lon={:.6f}{}: --resume applies them again (its steps are replayed) before it goes on.",
        f.c_l, f.c_r, f.wheelbase_mm, f.f_lat, f.f_lon,
        f.wheelbase_arc_mm != 0.0 ? fmt::format(" wheelbase_arc_mm={:.3f}", f.wheelbase_arc_mm)
                                  : std::string());
  }
  c.log
      << "A reset (a brown-out, a loose battery lead, a watchdog) loses the robot's odometry, its "
         "trials and every factor not saved; it starts again with its saved ones. The run that "
         "was under way, if any, is not counted; every run measured before is kept."
      << applied << "\n";
}

}  // namespace

void end_early(Context& c, const std::exception& why) {
  std::string reason = why.what();
  bool by_signal = dynamic_cast<const Interrupted*>(&why) != nullptr;
  // A signal that came with another error (a read it cut short, a reply it garbled) is the
  // signal's way out. Taking it here also keeps it from cutting the put-back short.
  try {
    check_interrupt();
  } catch (const Interrupted&) {
  }
  if (!by_signal && interrupt_signal() != 0) {
    c.log << "\nodocal session: " << reason << "\n";
    reason = Interrupted(interrupt_signal()).what();
    by_signal = true;
  }
  c.log << "\nodocal session: " << reason << "\n";
  if (dynamic_cast<const RobotRestarted*>(&why) != nullptr) {
    say_what_a_reset_lost(c);
  }
  if (dynamic_cast<const LinkLost*>(&why) != nullptr) {
    // Nothing can reach the robot: no stop, no put-back to try.
    c.log << "The robot's port hung up (a USB adapter unplugged, a cable pulled): nothing could "
             "be sent to stop the robot or to put its factors back. If it still moves, switch it "
             "off; nothing was saved on it. The run under way, if any, is not counted; every "
             "reading typed is kept. Plug the adapter in again.\n";
  } else {
    put_back(c);
  }
  try {
    c.write_session_json(false, c.partial, false, false, reason);
    write_report(c, c.partial, "", false, false, reason);
    // One command to go on: after a hang-up the adapter may come back under another name.
    const bool hung_up = dynamic_cast<const LinkLost*>(&why) != nullptr;
    c.log << "What was measured is in " << c.options.out_dir
          << "/measurements.csv and session.json";
    if (c.source.resumable()) {
      c.log << "; continue with: odocal session --resume " << c.options.out_dir
            << (hung_up ? " --port DEV (DEV: the port it has now)" : "") << "\n";
    } else {
      // The walls' session is not resumed (session_command.cpp refuses it).
      c.log << "; a session measured by the walls is not resumed (where the robot stood in the "
               "maze went with it): start a new one to go on (nothing was saved).\n";
    }
  } catch (const std::exception& write_error) {
    c.log << "WARNING: " << write_error.what() << "\n";
  }
  throw SessionEnded(reason, by_signal ? 130 : 2);
}

}  // namespace odocal::host::session
