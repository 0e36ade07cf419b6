// The session's files: the journal (measurements.csv, one writer), session.json, report.html,
// runs.csv, and the runs of an interrupted session read back for --resume.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "odocal/host/csv.hpp"
#include "session_internal.hpp"

namespace odocal::host {
namespace session {

namespace {

/// One row of the journal: `run,x_mm,y_mm,theta_deg` (theta empty when not measured).
std::string journal_row(std::size_t number, const SessionPose& m) {
  std::string row = fmt::format("{},{:.3f},{:.3f},", number, m.x_mm, m.y_mm);
  if (m.theta_deg) {
    row += fmt::format("{:.3f}", *m.theta_deg);
  }
  return row + "\n";
}

constexpr const char* journal_header = "run,x_mm,y_mm,theta_deg\n";

}  // namespace

void Context::journal(const RunRecord& r, std::size_t number) {
  const std::string path = options.out_dir + "/measurements.csv";
  struct stat info {};
  const bool fresh = ::stat(path.c_str(), &info) != 0 || info.st_size == 0;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  const std::string text =
      (fresh ? std::string(journal_header) : std::string()) + journal_row(number, r.measured);
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  if (std::find(files.begin(), files.end(), "measurements.csv") == files.end()) {
    files.push_back("measurements.csv");
  }
}

void Context::rewrite_journal() {
  const std::vector<RunRecord> kept = kept_runs();
  std::string text = journal_header;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    text += journal_row(i + 1, kept[i].measured);
  }
  write_file("measurements.csv", text);
}

std::vector<RunRecord> Context::kept_runs() const {
  std::vector<RunRecord> kept = runs;
  for (std::size_t i = runs.size(); i < options.replay.size(); ++i) {
    kept.push_back(options.replay[i]);
  }
  return kept;
}

nlohmann::json Context::write_session_json(bool complete, const nlohmann::json& result,
                                           bool applied, bool saved,
                                           const std::string& interruption) {
  const std::vector<RunRecord> kept = kept_runs();
  nlohmann::json doc = {
      {"procedure", to_string(options.procedure)},
      {"complete", complete},
      {"date", options.started_unix_s},
      {"options", options.recorded},
      {"runs", runs_json(complete ? runs : kept)},
      {"measurements", source.tape_readings(complete ? runs.size() : kept.size())},
      {"result", result},
      {"applied", applied},
      {"saved", saved}};
  if (!interruption.empty()) {
    doc["interrupted"] = interruption;
  }
  if (last_factors) {
    doc["factors"] = factors_json(*last_factors);
  }
  // A byte the robot sent that is not UTF-8 (a damaged reply that still read) is written as U+FFFD:
  // session.json is written whatever the robot said.
  write_file("session.json",
             doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  return doc;
}

void Context::write_file(const std::string& name, const std::string& content) {
  const std::string path = options.out_dir + "/" + name;
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << content;
    out.close();
    if (!out) {
      throw InputError(path, 0, "", "cannot write");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw InputError(path, 0, "", std::string("cannot write: ") + std::strerror(errno));
  }
  if (std::find(files.begin(), files.end(), name) == files.end()) {
    files.push_back(name);
  }
}

std::string runs_csv(const std::vector<RunRecord>& runs) {
  std::ostringstream out;
  out << "trial,label,path,duration_ms,count_l,count_r,odom_x_mm,odom_y_mm,odom_theta_deg,"
         "measured_x_mm,measured_y_mm,measured_theta_deg\n";
  for (const RunRecord& r : runs) {
    char line[512];
    std::snprintf(line, sizeof line, "%lld,%s,%s,%.0f,%lld,%lld,%.3f,%.3f,%.3f,%.3f,%.3f,",
                  static_cast<long long>(r.trial), r.label.c_str(), r.path.c_str(), r.duration_ms,
                  static_cast<long long>(r.count_l), static_cast<long long>(r.count_r), r.odom.x_mm,
                  r.odom.y_mm, r.odom.theta_deg.value_or(0.0), r.measured.x_mm, r.measured.y_mm);
    out << line;
    if (r.measured.theta_deg) {
      std::snprintf(line, sizeof line, "%.3f", *r.measured.theta_deg);
      out << line;
    }
    out << "\n";
  }
  return out.str();
}

nlohmann::json runs_json(const std::vector<RunRecord>& runs) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunRecord& r : runs) {
    const auto theta = [](const std::optional<double>& t) {
      return t ? nlohmann::json(*t) : nlohmann::json(nullptr);
    };
    nlohmann::json ticks = nullptr;
    if (!r.ticks.empty()) {
      ticks = nlohmann::json::array();
      for (const TickSample& t : r.ticks) {
        ticks.push_back({t.t_ms, t.count_l, t.count_r});
      }
    }
    out.push_back(
        {{"label", r.label},
         {"command", command_of(r)},
         {"ticks", ticks},
         {"trial", r.trial},
         {"path", r.path},
         {"duration_ms", static_cast<std::int64_t>(std::llround(r.duration_ms))},
         {"count_l", r.count_l},
         {"count_r", r.count_r},
         {"odom",
          {{"x_mm", r.odom.x_mm}, {"y_mm", r.odom.y_mm}, {"theta_deg", theta(r.odom.theta_deg)}}},
         {"measured",
          {{"x_mm", r.measured.x_mm},
           {"y_mm", r.measured.y_mm},
           {"theta_deg", theta(r.measured.theta_deg)}}}});
  }
  return out;
}

void write_report(Context& c, const nlohmann::json& result, const std::string& summary,
                  bool complete, bool saved, const std::string& interruption) {
  ReportInput in;
  in.title = std::string("odocal session ") + to_string(c.options.procedure);
  in.date_unix_s = c.date();
  in.complete = complete;
  in.interruption = interruption;
  in.saved = saved;
  in.runs = c.runs;
  in.tape_readings = c.source.tape_readings(c.runs.size());
  in.result = result;
  in.summary = summary;
  in.side_m = c.options.side_m.value_or(4.0);
  try {
    // From the robot when it still answers (after an interruption it may not).
    in.factors = c.last_factors.value_or(c.initial);
    in.wheel_diameter_mm = c.get(ParamId::wheel_diameter_mm);
    // The wheelbase in force when the session started: the geometry the runs were driven and
    // their odometry computed with (the fit's "before").
    in.wheelbase_mm = c.initial.wheelbase_mm;
    in.counts_per_rev = c.get(ParamId::counts_per_rev);
    const Reply provenance = c.robot.command("provenance", 2000);
    if (provenance.ok) {
      in.provenance = provenance.pairs;
    }
  } catch (const std::exception&) {
    in.wheelbase_mm = in.factors.wheelbase_mm > 0.0 ? in.factors.wheelbase_mm : in.wheelbase_mm;
  }
  c.write_file("report.html", report_html(in));
}

}  // namespace session

namespace {

/// What a whole number of session.json must be: an integer within 64 bits (a number with a
/// fraction, or beyond the range, is not one).
struct NotWhole {
  std::string key;
};

std::int64_t whole_of(const nlohmann::json& v, const char* key) {
  if (v.is_number_unsigned()) {
    if (v.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT64_MAX)) {
      return static_cast<std::int64_t>(v.get<std::uint64_t>());
    }
  } else if (v.is_number_integer()) {
    return v.get<std::int64_t>();
  } else if (v.is_number_float()) {
    const double d = v.get<double>();
    // 2^63 is exact in a double; every integral double in (-2^63, 2^63) converts exactly.
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9223372036854775808.0) {
      return static_cast<std::int64_t>(d);
    }
  }
  throw NotWhole{key};
}

}  // namespace

std::vector<RunRecord> recorded_runs(const nlohmann::json& session, const std::string& dir) {
  const std::string file = dir + "/session.json";
  std::vector<RunRecord> runs;
  if (!session.contains("runs") || !session["runs"].is_array()) {
    throw InputError(file, 0, "runs", "missing or not an array");
  }
  std::size_t index = 0;
  for (const nlohmann::json& run : session["runs"]) {
    ++index;
    try {
      RunRecord r;
      r.label = run.at("label").get<std::string>();
      const std::string command = run.at("command").get<std::string>();
      const std::optional<Motion> motion = Motion::of_command(command);
      if (!motion) {
        throw InputError(file, 0, "runs",
                         "run " + std::to_string(index) + ": command '" + command +
                             "' is not a motion the robot knows (run, drive <v> <w> <ms>, "
                             "selftest)");
      }
      r.motion = *motion;
      r.trial = whole_of(run.at("trial"), "trial");
      r.path = run.at("path").get<std::string>();
      r.duration_ms = run.at("duration_ms").get<double>();
      r.count_l = whole_of(run.at("count_l"), "count_l");
      r.count_r = whole_of(run.at("count_r"), "count_r");
      const auto pose = [](const nlohmann::json& j) {
        SessionPose p;
        p.x_mm = j.at("x_mm").get<double>();
        p.y_mm = j.at("y_mm").get<double>();
        if (!j.at("theta_deg").is_null()) {
          p.theta_deg = j.at("theta_deg").get<double>();
        }
        return p;
      };
      r.odom = pose(run.at("odom"));
      r.measured = pose(run.at("measured"));
      if (run.contains("ticks") && run["ticks"].is_array()) {
        for (const nlohmann::json& t : run["ticks"]) {
          r.ticks.push_back(TickSample{t.at(0).get<double>(), whole_of(t.at(1), "ticks"),
                                       whole_of(t.at(2), "ticks")});
        }
      }
      runs.push_back(r);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file, 0, "runs", "run " + std::to_string(index) + ": " + e.what());
    } catch (const NotWhole& e) {
      throw InputError(
          file, 0, "runs",
          "run " + std::to_string(index) + ": " + e.key + " is not a whole number within 64 bits");
    }
  }
  return runs;
}

std::vector<std::string> take_edited_journal(std::vector<RunRecord>& runs, const std::string& dir) {
  const std::string path = dir + "/measurements.csv";
  std::vector<std::string> said;
  if (::access(path.c_str(), F_OK) != 0) {
    return said;
  }
  std::size_t lines = 0;  // the header alone: an interruption before the first measurement
  std::istringstream text(read_text_file(path));
  for (std::string line; std::getline(text, line);) {
    lines += line.find_first_not_of(" \t\r") != std::string::npos ? 1u : 0u;
  }
  if (lines <= 1) {
    return said;
  }
  const std::unique_ptr<MeasurementSource> journal = file_measurements(path);
  const std::size_t rows = journal->available(0);
  const auto differs = [](double a, double b) { return std::fabs(a - b) > 0.0005; };
  for (std::size_t i = 0; i < runs.size() && i < rows; ++i) {
    const SessionPose edited = journal->take(runs[i], i, runs.size());
    SessionPose& kept = runs[i].measured;
    const bool theta_changed = edited.theta_deg.has_value() != kept.theta_deg.has_value() ||
                               (edited.theta_deg && differs(*edited.theta_deg, *kept.theta_deg));
    if (differs(edited.x_mm, kept.x_mm) || differs(edited.y_mm, kept.y_mm) || theta_changed) {
      const auto text = [](const SessionPose& p) {
        return fmt::format("{:.3f} {:.3f} {}", p.x_mm, p.y_mm,
                           p.theta_deg ? fmt::format("{:.3f}", *p.theta_deg) : "(no heading)");
      };
      said.push_back(fmt::format("run {}: {} from measurements.csv (session.json had {})", i + 1,
                                 text(edited), text(kept)));
      kept = edited;
    }
  }
  if (rows < runs.size()) {
    said.push_back(fmt::format(
        "measurements.csv has {} of the {} runs measured: the others as session.json has them",
        rows, runs.size()));
  }
  return said;
}

}  // namespace odocal::host
