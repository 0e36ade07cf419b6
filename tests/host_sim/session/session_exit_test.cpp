// Every way out of every procedure (DESIGN "Sessions on a real robot"): SIGINT, SIGTERM and the
// end of the input, at the moment before a run (Enter), at a measurement and while the robot
// drives, for umbmark, lateral, fit, verify, extended, selftest and auto, on odocal-sim behind a
// pty as a robot on a serial port. Each way out must leave the robot stopped, its stream off and
// every setting the session changed and did not save put back (read back on its console), keep
// every run in session.json with "complete": false, write report.html, exit 130 after a signal
// and 2 otherwise, and say how to resume; --resume then goes on, and finishes the session.
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "session_harness.hpp"
#include "session_person.hpp"

namespace {

using namespace odocal_session_test;

enum class Moment { enter, measurement, driving };
enum class WayOut { sigint, sigterm, end_of_input };

/// Where a session is ended: the `at`-th such moment of that session (1-based), and how.
struct Stop {
  Moment moment;
  std::size_t at;
  WayOut how;
};

const char* name_of(WayOut how) {
  return how == WayOut::sigint ? "SIGINT" : how == WayOut::sigterm ? "SIGTERM" : "end of input";
}

/// The same robot with its left encoder wired backwards: the self-test fixes it (wiring_fix 4).
constexpr const char* miswired_robot =
    R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
        "true_left_diameter_mm": 59.9, "true_right_diameter_mm": 60.1, "true_wheelbase_mm": 152,
        "slip_sigma": 0, "bump_height_mm": 0, "measure_sigma_mm": 0,
        "wiring": "left_encoder_reversed"})";

std::size_t count_of(const std::string& text, const std::regex& pattern) {
  return static_cast<std::size_t>(std::distance(
      std::sregex_iterator(text.begin(), text.end(), pattern), std::sregex_iterator()));
}

/// Moments the robot starts to move: a run's `Run N/M: label (command)` line, or the self-test.
std::size_t drives(const std::string& err) {
  static const std::regex run_line(R"(\nRun \d+/\d+: [^\n]*\)\n)");
  static const std::regex selftest_line("Self-test: each wheel turns alone");
  return count_of(err, run_line) + count_of(err, selftest_line);
}

/// What a careful person with a tape reads for the latest run: the odometry's pose (the robot
/// drives as its odometry says, up to the small wheel errors these short runs barely show) with a
/// scatter of 1 mm and 0.1 degree either way; for the self-test's one-wheel run of the
/// left-encoder-reversed robot, the heading it really turned: the opposite of what its reversed
/// encoder counted.
std::string reading(const Person& p, std::size_t typed) {
  const std::string& e = p.err;
  const auto at = e.rfind("odometry says x=");
  const double x = std::atof(e.c_str() + at + 16);
  const double y = std::atof(e.c_str() + e.find("y=", at) + 2);
  double theta = std::atof(e.c_str() + e.find("heading ", at) + 8);
  const auto prompt = e.rfind("\nRun ", at);
  if (e.compare(e.find('(', prompt) + 1, 13, "selftest left") == 0) {
    theta = -theta;
  }
  const double scatter = typed % 2 == 0 ? 1.0 : -1.0;
  char text[96];
  std::snprintf(text, sizeof text, "%.2f %.2f %.3f", x + scatter, y - scatter,
                theta + 0.1 * scatter);
  return text;
}

/// Answers the session as a person would (Enter before each run, the reading after it) until
/// `stop`, where it ends the session as `stop.how` says; without a stop, until the session ends.
/// Returns how many readings it typed.
std::size_t answer(Person& p, const Stop* stop, double timeout_s = 240.0) {
  std::size_t enters = 0, readings = 0;
  const auto deadline = PersonClock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    if (stop != nullptr && stop->moment == Moment::driving && drives(p.err) >= stop->at) {
      break;
    }
    if (p.count("press Enter to start") > enters) {
      if (stop != nullptr && stop->moment == Moment::enter && enters + 1 == stop->at) {
        break;
      }
      p.type("");
      ++enters;
      continue;
    }
    if (p.count("Measured stop point") > readings) {
      if (stop != nullptr && stop->moment == Moment::measurement && readings + 1 == stop->at) {
        break;
      }
      p.type(reading(p, readings));
      ++readings;
      continue;
    }
    if (p.closed() || PersonClock::now() > deadline) {
      break;
    }
    static_cast<void>(p.wait_for("\x01", 1, 0.05));  // reads what came
  }
  if (stop != nullptr) {
    if (stop->how == WayOut::end_of_input) {
      p.close_input();
    } else {
      p.signal(stop->how == WayOut::sigint ? SIGINT : SIGTERM);
    }
  }
  return readings;
}

/// The robot's settings a session may change, and whether it is idle with nothing unsaved.

struct Procedure {
  const char* name;
  const char* robot;
  std::vector<std::string> options;
  std::vector<Stop> stops;  ///< one session each, each resumed by the next; then one to the end
};

/// The way outs of one procedure's chain of sessions, each checked; the last session completes.
void interrupt_and_resume(const Procedure& procedure) {
  SCOPED_TRACE(procedure.name);
  ::signal(SIGPIPE, SIG_IGN);  // a session that ends early fails a typed line, not the test
  const std::string robot = write(std::string("exit_") + procedure.name + ".json", procedure.robot);
  const std::string store = temp(std::string("exit_") + procedure.name + ".store");
  std::remove(store.c_str());
  const std::string out = temp(std::string("exit_") + procedure.name + "_out");
  std::system(("rm -rf " + out).c_str());
  prepare_store(robot, store);
  SimOnPty lockstep(robot, store);
  ASSERT_FALSE(lockstep.path().empty());
  const RobotState initial = robot_state(lockstep.path());
  json kept = json::array();
  bool selftest_done = false;
  for (std::size_t stage = 0; stage <= procedure.stops.size(); ++stage) {
    const bool last = stage == procedure.stops.size();
    const Stop* stop = last ? nullptr : &procedure.stops[stage];
    SCOPED_TRACE(last ? std::string("to the end")
                      : std::string("stage ") + std::to_string(stage + 1) + ": " +
                            name_of(stop->how));
    // While the robot drives, a real-time robot (the same store: a restarted robot): a run lasts
    // seconds, so the signal comes while it moves.
    std::optional<SimOnPty> real_time;
    if (stop != nullptr && stop->moment == Moment::driving) {
      real_time.emplace(robot, store, "1");
    }
    const std::string pty = real_time ? real_time->path() : lockstep.path();
    std::vector<std::string> args = {"--port", pty, "--yes", "--json"};
    if (stage == 0) {
      args.insert(args.end(), {"--procedure", procedure.name, "--out", out});
      args.insert(args.end(), procedure.options.begin(), procedure.options.end());
    } else {
      args.insert(args.end(), {"--resume", out});
    }
    // Once finished, the self-test stays finished in every session.json after (a session that
    // took it over and is interrupted again hands it on).
    const bool done_before = selftest_done;
    selftest_done =
        stage > 0 && read_json(out + "/session.json")["result"].contains("selftest_runs");
    EXPECT_TRUE(selftest_done || !done_before) << "the finished self-test was lost";
    Person p(args);
    const std::size_t typed = answer(p, stop);
    const int status = p.finish();
    if (selftest_done) {  // a finished self-test is taken over: the wheels do not turn again
      EXPECT_EQ(p.err.find("each wheel turns alone"), std::string::npos) << p.err;
    }
    if (last) {
      ASSERT_EQ(status, 0) << p.err;
      const json done = json::parse(p.out, nullptr, false);
      ASSERT_TRUE(done.is_object()) << p.out << p.err;
      EXPECT_TRUE(done["complete"].get<bool>());
      ASSERT_EQ(done["runs"].size(), kept.size() + typed) << p.err;
      for (std::size_t i = 0; i < kept.size(); ++i) {
        EXPECT_EQ(done["runs"][i], kept[i]) << "run " << i + 1;
      }
      break;
    }
    ASSERT_NE(status, -1) << "crashed:\n" << p.err;
    EXPECT_EQ(status, stop->how == WayOut::end_of_input ? 2 : 130) << p.err;
    EXPECT_NE(p.err.find(stop->how == WayOut::end_of_input
                             ? std::string("end of input")
                             : std::string("interrupted by ") + name_of(stop->how)),
              std::string::npos)
        << p.err;
    EXPECT_NE(p.err.find("The robot is stopped"), std::string::npos) << p.err;
    EXPECT_EQ(p.err.find("did not answer"), std::string::npos) << p.err;
    EXPECT_NE(p.err.find("--resume " + out), std::string::npos) << p.err;
    // The robot: idle, its stream off, every setting as before the first session, nothing unsaved.
    const RobotState now = robot_state(pty);
    EXPECT_EQ(now.factors, initial.factors);
    EXPECT_NE(now.status.find("mode=idle"), std::string::npos) << now.status;
    EXPECT_NE(now.status.find("unsaved=0"), std::string::npos) << now.status << p.err;
    EXPECT_EQ(now.status.find("# ticks"), std::string::npos) << now.status;
    // The files: every run so far kept (none lost, those before unchanged), not complete, a report.
    const json doc = read_json(out + "/session.json");
    ASSERT_TRUE(doc.is_object());
    EXPECT_FALSE(doc["complete"].get<bool>());
    ASSERT_EQ(doc["runs"].size(), kept.size() + typed);
    for (std::size_t i = 0; i < kept.size(); ++i) {
      EXPECT_EQ(doc["runs"][i], kept[i]) << "run " << i + 1;
    }
    const std::string journal = out + "/measurements.csv";
    EXPECT_EQ(exists(journal) ? rows_of(journal) : 0u,
              kept.size() + typed);  // none before a reading
    std::ifstream report(out + "/report.html");
    std::stringstream page;
    page << report.rdbuf();
    EXPECT_NE(page.str().find("interrupted"), std::string::npos);
    kept = doc["runs"];
  }
  // What the complete session saved is there for a restarted robot.
  EXPECT_EQ(
      stored(robot, store, "wiring_fix"),
      std::string(procedure.robot).find("left_encoder_reversed") != std::string::npos &&
              (std::string(procedure.name) == "selftest" || std::string(procedure.name) == "auto")
          ? 4.0
          : 0.0);
}

TEST(SessionWayOut, UmbmarkEveryWayOutPutsBackKeepsItsRunsAndResumes) {
  interrupt_and_resume({"umbmark",
                        plain_robot,
                        {"--side-m", "1", "--runs", "2", "--passes", "1"},
                        {{Moment::enter, 2, WayOut::end_of_input},
                         {Moment::measurement, 2, WayOut::sigterm},
                         {Moment::driving, 1, WayOut::sigint}}});
}

// A session.json edited or damaged into what no session writes (a run driven otherwise than this
// session would; and what fuzzing found: a crash, undefined conversions, an error naming nothing):
// each is refused on --resume with exit 2, a message naming the file and what is wrong, and the
// record kept as it was, runs this session would have taken over included.
TEST(SessionWayOut, AResumeRefusesADamagedSessionJsonNamingWhatIsWrong) {
  ::signal(SIGPIPE, SIG_IGN);
  const std::string robot = write("exit_damaged.json", plain_robot);
  const std::string out = temp("exit_damaged_out");
  std::system(("rm -rf " + out).c_str());
  SimOnPty sim(robot, temp("exit_damaged.store"));
  ASSERT_FALSE(sim.path().empty());
  {
    Person p({"--port", sim.path(), "--procedure", "fit", "--runs", "3", "--out", out});
    const Stop stop{Moment::enter, 3, WayOut::end_of_input};
    EXPECT_EQ(answer(p, &stop), 2u);
    EXPECT_EQ(p.finish(), 2) << p.err;
  }
  const json interrupted = read_json(out + "/session.json");
  ASSERT_EQ(interrupted["runs"].size(), 2u);
  ASSERT_GE(interrupted["runs"][0]["ticks"].size(), 2u);
  struct Damage {
    const char* what;
    std::function<void(json&)> edit;
    const char* said;
  };
  const std::vector<Damage> damages = {
      // (As session.json writes a motion: a refused resume writes back the runs it read, each
      // motion as its one console line.)
      {"run 2 driven otherwise", [](json& d) { d["runs"][1]["command"] = "run line 9.000"; },
       "other settings"},
      {"a logged run without ticks", [](json& d) { d["runs"][0]["ticks"] = nullptr; },
       "without a tick log"},
      {"a logged run with one tick row",
       [](json& d) { d["runs"][0]["ticks"] = json::array({d["runs"][0]["ticks"][0]}); },
       "without a tick log"},
      {"tick rows out of time order", [](json& d) { d["runs"][1]["ticks"][1][0] = -5.0; },
       "in time order"},
      {"a trial number with a fraction", [](json& d) { d["runs"][0]["trial"] = 1.5; },
       "trial is not a whole number"},
      {"a count beyond 64 bits", [](json& d) { d["runs"][1]["count_l"] = 1e300; },
       "count_l is not a whole number"},
      {"a tick count beyond 64 bits", [](json& d) { d["runs"][0]["ticks"][0][2] = -1e19; },
       "ticks is not a whole number"},
      {"complete as a number", [](json& d) { d["complete"] = 1; }, "not true or false"},
      {"a negative seed", [](json& d) { d["options"]["seed"] = -3; }, "options.seed"},
      {"a procedure no session has", [](json& d) { d["options"]["procedure"] = "umbmarks"; },
       "no procedure 'umbmarks'"},
      {"a baud rate beyond 64 bits", [](json& d) { d["options"]["baud"] = 1e300; }, "options.baud"},
  };
  for (const Damage& damage : damages) {
    json doc = interrupted;
    damage.edit(doc);
    std::ofstream(out + "/session.json") << doc.dump(2);
    Person p({"--port", sim.path(), "--resume", out});
    static_cast<void>(answer(p, nullptr));
    EXPECT_EQ(p.finish(), 2) << damage.what << ": " << p.err;
    EXPECT_NE(p.err.find("session.json"), std::string::npos) << damage.what << ": " << p.err;
    EXPECT_NE(p.err.find(damage.said), std::string::npos) << damage.what << ": " << p.err;
    const json after = read_json(out + "/session.json");
    EXPECT_FALSE(after["complete"].is_boolean() && after["complete"].get<bool>()) << damage.what;
    EXPECT_EQ(after["runs"], doc["runs"]) << damage.what;
    EXPECT_EQ(rows_of(out + "/measurements.csv"), 2u) << damage.what;
  }
  // Put back as it was, the record resumes to the end.
  std::ofstream(out + "/session.json") << interrupted.dump(2);
  Person p({"--port", sim.path(), "--resume", out});
  static_cast<void>(answer(p, nullptr));
  EXPECT_EQ(p.finish(), 0) << p.err;
}

TEST(SessionWayOut, ALostRobotEndsTheSessionKeepingEveryRun) {
  ::signal(SIGPIPE, SIG_IGN);
  const std::string robot = write("exit_lost.json", plain_robot);
  const std::string out = temp("exit_lost_out");
  std::system(("rm -rf " + out).c_str());
  std::optional<SimOnPty> sim(std::in_place, robot, temp("exit_lost.store"));
  ASSERT_FALSE(sim->path().empty());
  Person p({"--port", sim->path(), "--procedure", "umbmark", "--side-m", "1", "--runs", "2",
            "--out", out});
  // The adapter pulled after the second reading: the robot is gone at the third run's Enter.
  ASSERT_TRUE(p.wait_for("press Enter to start", 1)) << p.err;
  p.type("");
  ASSERT_TRUE(p.wait_for("Measured stop point", 1)) << p.err;
  p.type(reading(p, 0));
  ASSERT_TRUE(p.wait_for("press Enter to start", 2)) << p.err;
  p.type("");
  ASSERT_TRUE(p.wait_for("Measured stop point", 2)) << p.err;
  p.type(reading(p, 1));
  ASSERT_TRUE(p.wait_for("press Enter to start", 3)) << p.err;
  sim.reset();
  p.type("");
  EXPECT_EQ(p.finish(), 2) << p.err;
  EXPECT_NE(p.err.find("--resume " + out), std::string::npos) << p.err;
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_FALSE(doc["complete"].get<bool>());
  EXPECT_EQ(doc["runs"].size(), 2u);
  EXPECT_EQ(rows_of(out + "/measurements.csv"), 2u);
}

TEST(SessionWayOut, ASessionsJournalReplaysIt) {
  const std::string robot = write("exit_journal.json", R"({"measure_sigma_mm": 2})");
  const std::string first = temp("exit_journal_first");
  const std::string again = temp("exit_journal_again");
  std::system(("rm -rf " + first + " " + again).c_str());
  const std::string options = " --procedure umbmark --side-m 1 --runs 2 --passes 1 --json";
  const json a = parse(session("--sim " + robot + options + " --out " + first));
  const json b = parse(session("--sim " + robot + options + " --measurements " + first +
                               "/measurements.csv --out " + again));
  ASSERT_TRUE(a.is_object());
  ASSERT_TRUE(b.is_object());
  ASSERT_EQ(b["runs"].size(), a["runs"].size());
  for (std::size_t i = 0; i < a["runs"].size(); ++i) {
    for (const char* key : {"x_mm", "y_mm", "theta_deg"}) {
      // The journal keeps a micrometre (3 decimals).
      EXPECT_NEAR(b["runs"][i]["measured"][key].get<double>(),
                  a["runs"][i]["measured"][key].get<double>(), 0.0005)
          << "run " << i + 1 << " " << key;
    }
  }
  EXPECT_NEAR(b["result"]["e_d"].get<double>(), a["result"]["e_d"].get<double>(), 1e-6);
}

TEST(SessionWayOut, LateralPutsBackItsCruiseSpeedAtEveryWayOut) {
  interrupt_and_resume({"lateral",
                        plain_robot,
                        {"--runs", "2"},
                        {{Moment::enter, 2, WayOut::sigint},
                         {Moment::measurement, 2, WayOut::end_of_input},
                         {Moment::driving, 1, WayOut::sigterm}}});
}

TEST(SessionWayOut, FitInterruptedWhileALoggedRunDrivesDoesNotCrash) {
  // The first way out while `stream ticks` logs the run: the stream's lines still come while the
  // robot is stopped and put back, after the run's record is gone.
  interrupt_and_resume({"fit",
                        plain_robot,
                        {"--runs", "3"},
                        {{Moment::driving, 1, WayOut::sigint},
                         {Moment::measurement, 2, WayOut::sigterm},
                         {Moment::enter, 1, WayOut::end_of_input}}});
}

TEST(SessionWayOut, VerifyPutsBackTheFactorsItSetForItsBeforeRuns) {
  interrupt_and_resume({"verify",
                        plain_robot,
                        {"--runs", "1"},
                        {{Moment::measurement, 1, WayOut::sigint},
                         {Moment::driving, 1, WayOut::sigterm},
                         {Moment::enter, 2, WayOut::end_of_input}}});
}

TEST(SessionWayOut, ExtendedEveryWayOutKeepsItsRunsAndResumes) {
  interrupt_and_resume({"extended",
                        plain_robot,
                        {"--runs", "2", "--side-m", "1"},
                        {{Moment::enter, 1, WayOut::sigterm},
                         {Moment::measurement, 3, WayOut::end_of_input},
                         {Moment::driving, 2, WayOut::sigint}}});
}

TEST(SessionWayOut, SelftestWaitsForEnterAndPutsBackItsWiringFix) {
  // Moments: Enter 1 the self-test's wheels, Enter 2 the one-wheel run that tells the reversed
  // encoder from a reversed motor, Enter 3 the test again after the fix (wiring_fix 4, applied).
  interrupt_and_resume({"selftest",
                        miswired_robot,
                        {},
                        {{Moment::driving, 1, WayOut::sigint},
                         {Moment::enter, 2, WayOut::end_of_input},
                         {Moment::enter, 3, WayOut::sigterm}}});
}

TEST(SessionWayOut, AutoEveryWayOutPutsBackTheWiringFixAndResumesWithoutTheSelftestAgain) {
  // 1: after the self-test's fix, at its second test; 2: at the second calibration run's reading
  // (the self-test finished this time, with its fix); 3: while a logged run drives (the resumed
  // session applies the fix again and does not turn the wheels for the self-test).
  interrupt_and_resume({"auto",
                        miswired_robot,
                        {"--side-m", "1"},
                        {{Moment::enter, 3, WayOut::sigint},
                         {Moment::measurement, 2, WayOut::end_of_input},
                         {Moment::driving, 1, WayOut::sigterm}}});
}

}  // namespace
