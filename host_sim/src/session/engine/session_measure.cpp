// Where a session's measurements come from: the simulator's tape measure, a CSV file, a person.

#include <cctype>
#include <cmath>
#include <cstdio>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "odocal/host/csv.hpp"
#include "odocal/host/session.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "reading_check.hpp"
#include "session_internal.hpp"

namespace odocal::host {
namespace {

/// Largest stop-point coordinate taken, mm (the robot's `umbmark add` limit): 1 km is no run.
constexpr double max_reading_mm = 1e6;
/// Largest heading taken, degrees (ten turns: an unwrapped heading is fine, more is a typo).
constexpr double max_theta_deg = 3600.0;

class RobotMeasure final : public MeasurementSource {
 public:
  explicit RobotMeasure(RobotClient& robot) : robot_(robot) {}
  SessionPose take(const RunRecord&, std::size_t, std::size_t) override {
    const Reply reply = robot_.query("measure");
    if (!reply.ok) {
      throw LinkError("the robot has no tape measure ('measure': err " + reply.code +
                      "): only odocal-sim has one; give --measurements FILE or type them");
    }
    SessionPose pose;
    pose.x_mm = reply.number("x_mm");
    pose.y_mm = reply.number("y_mm");
    pose.theta_deg = reply.number("theta_deg");
    return pose;
  }
  std::size_t available(std::size_t) const override {
    return std::numeric_limits<std::size_t>::max();
  }
  std::string describe() const override { return "the simulator's tape measure ('measure')"; }
  bool by_hand() const override { return false; }

 private:
  RobotClient& robot_;
};

class FileMeasure final : public MeasurementSource {
 public:
  explicit FileMeasure(const std::string& path) : path_(path) {
    const std::vector<std::string> columns = header_of(path);
    // A session's journal (measurements.csv) numbers its rows; its x, y, theta follow the number.
    const std::size_t first = columns.front() == "run" ? 1 : 0;
    const bool with_theta = columns.size() == first + 3;
    const CsvTable table = read_csv(path, columns);
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      if (first == 1 && table.text(r, 0) != std::to_string(r + 1)) {
        table.fail(r, 0,
                   "expected " + std::to_string(r + 1) + ", got '" + table.text(r, 0) +
                       "' (a journal's rows are numbered 1, 2, ... in the order of the runs)");
      }
      SessionPose pose;
      pose.x_mm = bounded(table, r, first, max_reading_mm);
      pose.y_mm = bounded(table, r, first + 1, max_reading_mm);
      if (with_theta && !table.text(r, first + 2).empty()) {
        pose.theta_deg = bounded(table, r, first + 2, max_theta_deg);
      }
      rows_.push_back(pose);
    }
    if (rows_.empty()) {
      throw InputError(path, 0, "", "no measurement rows after the header");
    }
  }
  SessionPose take(const RunRecord&, std::size_t index, std::size_t) override {
    if (index >= rows_.size()) {
      throw InputError(path_, 0, "",
                       "too few rows: run " + std::to_string(index + 1) + " has no measurement");
    }
    return rows_[index];
  }
  std::size_t available(std::size_t already_taken) const override {
    return already_taken >= rows_.size() ? 0u : rows_.size() - already_taken;
  }
  std::string describe() const override { return path_; }

 private:
  static double bounded(const CsvTable& table, std::size_t row, std::size_t column, double limit) {
    const double value = table.number(row, column);
    if (std::fabs(value) > limit) {
      table.fail(row, column,
                 "absurd magnitude " + table.text(row, column) + " (at most " +
                     fmt::format("{:.1f}", limit) + ")");
    }
    return value;
  }
  /// The columns of the header (the first line that is not blank or a '#' note): x_mm,y_mm;
  /// x_mm,y_mm,theta_deg; or a session's journal, run,x_mm,y_mm,theta_deg. Anything else is
  /// refused naming the line and the three forms.
  static std::vector<std::string> header_of(const std::string& path) {
    static const std::vector<std::vector<std::string>> forms = {
        {"x_mm", "y_mm"}, {"x_mm", "y_mm", "theta_deg"}, {"run", "x_mm", "y_mm", "theta_deg"}};
    const std::string text = read_text_file(path);
    std::istringstream in(text);
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
      if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) {
        line.erase(0, 3);
      }
      std::string compact;
      for (char c : line) {
        if (c != ' ' && c != '\t' && c != '\r') {
          compact += c;
        }
      }
      if (compact.empty() || compact[0] == '#') {
        continue;
      }
      for (const std::vector<std::string>& form : forms) {
        std::string joined;
        for (const std::string& name : form) {
          joined += (joined.empty() ? "" : ",") + name;
        }
        if (compact == joined) {
          return form;
        }
      }
      throw InputError(path, number, "",
                       "header must be x_mm,y_mm or x_mm,y_mm,theta_deg, or a session's journal "
                       "run,x_mm,y_mm,theta_deg; got '" +
                           compact + "'");
    }
    return forms.front();  // no header at all: read_csv says so
  }
  std::string path_;
  std::vector<SessionPose> rows_;
};

/// Whether `line` has a comma between two digits (a decimal comma, or numbers typed without a
/// space after the comma).
bool comma_between_digits(const std::string& line) {
  for (std::size_t i = 1; i + 1 < line.size(); ++i) {
    if (line[i] == ',' && std::isdigit(static_cast<unsigned char>(line[i - 1])) != 0 &&
        std::isdigit(static_cast<unsigned char>(line[i + 1])) != 0) {
      return true;
    }
  }
  return false;
}

class PromptMeasure final : public MeasurementSource {
 public:
  PromptMeasure(std::istream& in, std::ostream& prompt, bool echo)
      : in_(in), prompt_(prompt), echo_(echo) {}
  bool check_next(const ReadingCheck& check, bool heading_needed) override {
    check_ = check;
    heading_needed_ = heading_needed;
    return true;
  }
  SessionPose take(const RunRecord& run, std::size_t index, std::size_t planned) override {
    prompt_ << "\nRun " << index + 1 << "/" << planned << " (" << run.label << ", trial "
            << run.trial
            << ") has stopped. The robot's odometry says x=" << fmt::format("{:.1f}", run.odom.x_mm)
            << " y=" << fmt::format("{:.1f}", run.odom.y_mm) << " mm, heading "
            << fmt::format("{:.1f}", run.odom.theta_deg.value_or(0.0)) << " deg.\n";
    return reading(index + 1, check_, heading_needed_);
  }
  std::optional<std::string> ask(const std::string& question) override {
    prompt_ << question << std::flush;
    return read_line(0, "answer to: " + question);
  }
  std::optional<SessionPose> retype(const RunRecord& run, std::size_t number,
                                    const ReadingCheck& check, bool heading_needed) override {
    prompt_ << "Run " << number << " (" << run.label << ", trial " << run.trial
            << "): its reading again (the odometry said x=" << fmt::format("{:.1f}", run.odom.x_mm)
            << " y=" << fmt::format("{:.1f}", run.odom.y_mm) << " mm, heading "
            << fmt::format("{:.1f}", run.odom.theta_deg.value_or(0.0)) << " deg).\n";
    return reading(number, check, heading_needed);
  }
  std::size_t available(std::size_t) const override {
    return std::numeric_limits<std::size_t>::max();
  }
  std::string describe() const override { return "the terminal (you type them)"; }

 private:
  /// Asks for run `number`'s reading until one is taken: checked, shown back when it does not
  /// read, holds a comma, or the check questions it (then taken as typed on `y`).
  SessionPose reading(std::size_t number, const ReadingCheck& check, bool heading_needed) {
    const std::string ask =
        heading_needed
            ? "Measured stop point from the start mark, mm, and the heading, deg (this run needs "
              "it): x (ahead) y (left) heading (counter-clockwise +): "
            : "Measured stop point from the start mark, mm: x (ahead) y (left) [heading deg]: ";
    std::optional<SessionPose> questioned;  // a reading shown back, awaiting y
    for (;;) {
      prompt_ << (questioned ? "Type the reading again, or y to take it as it is: " : ask)
              << std::flush;
      const std::string line = read_line(number, "measurement for run " + std::to_string(number));
      if (questioned && (line == "y" || line == "yes" || line == "Y")) {
        prompt_ << "  Taken as typed.\n";
        return *questioned;
      }
      SessionPose pose;
      std::string why;
      if (!parse_measurement_line(line, pose, why)) {
        prompt_ << "  Not taken: " << why
                << ". Type two numbers (x_mm y_mm) or three (x_mm y_mm theta_deg), e.g. -12.5 40"
                << (comma_between_digits(line) ? " ('.' is the decimal point: a comma separates "
                                                 "numbers)"
                                               : "")
                << "\n";
        questioned.reset();
        continue;
      }
      if (heading_needed && !pose.theta_deg) {
        prompt_ << "  Not taken: this run needs the heading too (the third number, degrees, "
                   "counter-clockwise positive), e.g. "
                << fmt::format("{:.1f} {:.1f} -12", pose.x_mm, pose.y_mm) << "\n";
        questioned.reset();
        continue;
      }
      const ReadingVerdict verdict = check ? check(pose, line) : ReadingVerdict{};
      // A comma is never a silent separator: the reading as it was read is shown back.
      const std::string comma = session::comma_note(line, pose);
      if (verdict.plausible && comma.empty()) {
        return pose;
      }
      if (!comma.empty()) {
        prompt_ << "  Note: " << comma << "\n";
      }
      prompt_ << verdict.explained();
      questioned = pose;
    }
  }
  /// One typed line, shown when it came from a pipe; the end of the input ends the session.
  std::string read_line(std::size_t number, const std::string& what) {
    std::string line;
    if (!session::read_typed_line(in_, line)) {
      throw InputError("terminal", 0, "",
                       "no " + what + " (end of input)" +
                           (number > 0 ? std::string("; nothing was saved") : std::string()));
    }
    if (echo_) {
      prompt_ << line << "\n";  // input from a file or pipe: show what was read
    }
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.pop_back();
    }
    return line;
  }
  std::istream& in_;
  std::ostream& prompt_;
  bool echo_;
  ReadingCheck check_;
  bool heading_needed_ = false;
};

}  // namespace

bool parse_measurement_line(const std::string& text, SessionPose& pose, std::string& why) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text + " ") {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r' || c == ';') {
      if (!word.empty()) {
        words.push_back(word);
        word.clear();
      }
    } else {
      word += c;
    }
  }
  if (words.size() < 2 || words.size() > 3) {
    why = words.empty() ? "empty line"
                        : "expected 2 or 3 numbers, got " + std::to_string(words.size()) + " word" +
                              (words.size() == 1 ? "" : "s");
    return false;
  }
  static const char* const names[3] = {"x_mm", "y_mm", "theta_deg"};
  double values[3] = {0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::optional<double> value = toolkit::parse_real(words[i]);
    if (!value) {
      why = std::string(names[i]) + " '" + words[i] + "' is not a number";
      return false;
    }
    values[i] = *value;
    const double limit = i < 2 ? max_reading_mm : max_theta_deg;
    if (std::fabs(values[i]) > limit) {
      why = std::string(names[i]) + " " + words[i] + " is absurd (at most " +
            fmt::format("{:.1f}", limit) + ")";
      return false;
    }
  }
  pose = SessionPose{values[0], values[1], std::nullopt};
  if (words.size() == 3) {
    pose.theta_deg = values[2];
  }
  return true;
}

std::unique_ptr<MeasurementSource> robot_measurements(RobotClient& robot) {
  return std::make_unique<RobotMeasure>(robot);
}

std::unique_ptr<MeasurementSource> file_measurements(const std::string& path) {
  return std::make_unique<FileMeasure>(path);
}

std::unique_ptr<MeasurementSource> prompt_measurements(std::istream& in, std::ostream& prompt,
                                                       bool echo) {
  return std::make_unique<PromptMeasure>(in, prompt, echo);
}

}  // namespace odocal::host
