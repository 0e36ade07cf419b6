// The way out at the save question puts back what the session applied: a robot with an earlier
// calibration saved gets it back as it was; one that has never saved gets its defaults back,
// with their provenance.
#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "session_harness.hpp"
#include "session_person.hpp"

namespace {

using namespace odocal_session_test;

/// umbmark's one pass applied, then the end of input where the save question wants its answer.
/// `saved_before`: the robot holds an earlier calibration; else it has never saved. Either way
/// the robot ends as the session found it: the same values, nothing unsaved but what the
/// firmware's `defaults` documents, and the provenance it had.
void end_of_input_at_the_save_question(bool saved_before, const std::string& tag) {
  // The question is asked at a terminal only: odocal's stdin is a pty's slave, the test types on
  // its master, every reading ahead, then Ctrl-D where the answer should come.
  const std::string robot = write(tag + ".json", plain_robot);
  const std::string store = temp(tag + ".store");
  std::remove(store.c_str());
  if (saved_before) {
    prepare_store(robot, store);
  }
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  const RobotState initial = robot_state(sim.path());
  const std::string provenance = ask_robot(sim.path(), "provenance", "wheel_method");
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  const std::string slave = ::ptsname(master);
  const std::string typed = "\n-40 -45\n\n41 44\n\n-5 8\n\n6 -9\n\x04";
  ASSERT_EQ(::write(master, typed.data(), typed.size()), static_cast<ssize_t>(typed.size()));
  const std::string out = temp(tag + "_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = session("--port " + sim.path() + " --procedure umbmark --side-m 1 --runs 2 " +
                               "--passes 1 --out " + out,
                           slave);
  ::close(master);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("Applied on the robot:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("end of input at the question 'Save these factors"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("put back"), std::string::npos) << r.err;
  const RobotState now = robot_state(sim.path());
  EXPECT_EQ(now.factors, initial.factors);
  EXPECT_EQ(ask_robot(sim.path(), "provenance", "wheel_method"), provenance);
  // Left as it was: nothing unsaved, whether it had saved (its set reloaded) or never had (its
  // defaults, which a restart would bring too).
  EXPECT_NE(now.status.find("unsaved=0"), std::string::npos) << now.status;
  if (!saved_before) {
    EXPECT_NE(provenance.find("wheel_method=defaults"), std::string::npos) << provenance;
    EXPECT_NE(r.err.find("it has never saved"), std::string::npos) << r.err;
  }
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_FALSE(doc["complete"].get<bool>());
  EXPECT_EQ(doc["runs"].size(), 4u);
}

TEST(SessionWayOut, TheEndOfInputAtTheSaveQuestionPutsBackWhatWasApplied) {
  end_of_input_at_the_save_question(true, "exit_save");
}

TEST(SessionWayOut, ARobotThatNeverSavedGetsItsDefaultsBackWithTheirProvenance) {
  end_of_input_at_the_save_question(false, "exit_never_saved");
}

}  // namespace
