// A run's end on a robot in real time, when something else drove trials between the runs (the
// walls' looks): the robot reports itself idle before the run's own trial is over (its wheels
// still coasting) and `trial` still names the last look step's. The run must wait for its own
// trial, not take the look's (found against the QEMU mouse twin; odocal-sim in lockstep never
// shows it). A scripted robot plays exactly that: no `# done` for a while, `status` idle, `trial`
// the older number, then the run's trial.

#include <gtest/gtest.h>

#include <deque>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>

#include "odocal/host/robot_client.hpp"
#include "odocal/host/session.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

constexpr long kLookTrial = 360;  // the look's last step, before the run
constexpr long kRunTrial = 361;   // the run's own

// The robot's console as a script: answers each command line; the run's `# done` comes only
// after `late_polls` reads that found nothing (the run still driving, then coasting).
class RaceRobot final : public LineChannel {
 public:
  void write_line(const std::string& line) override {
    const std::string word = line.substr(0, line.find(' '));
    if (word == "status") {
      reply("ok mode=idle path=none segment=0 faults=none ticks=" + std::to_string(ticks_ += 10) +
            " unsaved=0");
    } else if (word == "trial") {
      reply(trial_line(run_over_ ? kRunTrial : kLookTrial));
      trials_read_ += 1;
    } else if (word == "drive") {
      driving_ = true;
      reply("ok v_mps=0.000 w_radps=1.050 ms=35904");
    } else if (word == "odom") {
      reply("ok x_mm=0.000 y_mm=0.000 theta_deg=0.000");
    } else if (word == "get") {
      const std::string name = line.substr(4);
      reply("ok " + name + "=" + value_of(name));
    } else {
      reply("ok");
    }
  }
  bool read_line(std::string& line, int /*timeout_ms*/) override {
    if (lines_.empty() && driving_ && !run_over_ && ++quiet_reads_ > late_polls) {
      run_over_ = true;  // the wheels stand still: the run's trial is over
      lines_.push_back("# done trial=" + std::to_string(kRunTrial) + " path=drive");
    }
    if (lines_.empty()) {
      return false;  // nothing within the timeout
    }
    line = lines_.front();
    lines_.pop_front();
    return true;
  }
  [[nodiscard]] std::string name() const override { return "scripted robot"; }

  /// Reads that find nothing before the run's `# done`: enough for the session's check of a
  /// lost `# done` (every sixth quiet poll) to run twice while the robot is idle.
  int late_polls = 14;

 private:
  void reply(const std::string& line) { lines_.push_back(line); }
  static std::string trial_line(long number) {
    // The look's step turned a few counts; the run six turns' worth.
    const long counts = number == kRunTrial ? 20537 : 22;
    return "ok trial=" + std::to_string(number) +
           " path=drive duration_ms=" + (number == kRunTrial ? "36168" : "290") +
           " count_l=" + std::to_string(-counts) + " count_r=" + std::to_string(counts) +
           " x_mm=0.000 y_mm=0.000 theta_deg=0.000";
  }
  static std::string value_of(const std::string& name) {
    if (name == "wheel_diameter_mm")
      return "32.000000";
    if (name == "wheelbase_mm")
      return "76.000000";
    if (name == "counts_per_rev")
      return "1440.000000";
    if (name == "cruise_mps" || name == "spin_radps")
      return "0.200000";
    return "1.000000";
  }

  std::deque<std::string> lines_;
  long ticks_ = 1000;
  bool driving_ = false;
  bool run_over_ = false;
  int quiet_reads_ = 0;
  int trials_read_ = 0;
};

// A measurement source that is no tape (the walls drive trials of their own between runs).
class NotATape final : public MeasurementSource {
 public:
  [[nodiscard]] bool by_hand() const override { return false; }
  [[nodiscard]] bool is_tape() const override { return false; }
  SessionPose take(const RunRecord&, std::size_t, std::size_t) override {
    return SessionPose{0.0, 0.0, 0.0};
  }
  [[nodiscard]] std::size_t available(std::size_t) const override {
    return std::numeric_limits<std::size_t>::max();
  }
  [[nodiscard]] std::string describe() const override { return "the walls (scripted)"; }
};

TEST(SessionTrialRace, ARunWaitsForItsOwnTrialWhenTheRobotIdlesBeforeIt) {
  RaceRobot robot_line;
  RobotClient robot(robot_line);
  NotATape source;
  SessionOptions options;
  options.out_dir = (std::filesystem::temp_directory_path() / "odocal-trial-race").string();
  std::filesystem::remove_all(options.out_dir);
  std::filesystem::create_directories(options.out_dir);
  std::ostringstream log;
  Context c(robot, source, options, log);
  c.last_trial = 12;  // the session's last run, long before the looks' steps
  const RunRecord r = c.run("turns-ccw", Motion::timed(0.0, 1.05, 35904.0), 36.0);
  EXPECT_EQ(r.trial, kRunTrial) << log.str();
  EXPECT_EQ(r.count_r - r.count_l, 2 * 20537) << "the run's counts, not the look step's";
  EXPECT_EQ(c.last_trial, kRunTrial);
  std::filesystem::remove_all(options.out_dir);
}

}  // namespace
}  // namespace odocal::host::session
