// libFuzzer target: arbitrary bytes as the directory `odocal session --resume DIR` reads: its
// session.json and, after a line `--- measurements.csv`, its measurements.csv (no such line: no
// journal). As the resume does: the JSON parsed without exceptions (not JSON: nothing to fuzz);
// recorded_runs, which must return the runs or throw InputError naming session.json; then
// take_edited_journal, which must return or throw InputError naming measurements.csv. The runs
// taken over then go where a resumed session puts them: session.json's `runs` again (which
// recorded_runs must read back as they were), runs.csv, a logged run's tick log (which
// read_tick_log reads or refuses with InputError), and report.html.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fuzz_scratch.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/session.hpp"
#include "session_internal.hpp"

namespace {

using odocal::host::RunRecord;
using odocal::host::SessionPose;

const odocal::fuzz::ScratchDir scratch("resume");

bool same_pose(const SessionPose& a, const SessionPose& b) {
  return a.x_mm == b.x_mm && a.y_mm == b.y_mm && a.theta_deg == b.theta_deg;
}

// What session.json's `runs` keeps of a run (duration_ms in whole milliseconds).
bool same_run(const RunRecord& a, const RunRecord& b) {
  if (a.label != b.label || a.command != b.command || a.trial != b.trial || a.path != b.path ||
      a.count_l != b.count_l || a.count_r != b.count_r || !same_pose(a.odom, b.odom) ||
      !same_pose(a.measured, b.measured) || a.ticks.size() != b.ticks.size())
    return false;
  if (std::fabs(a.duration_ms) < 1e15 && !(std::fabs(a.duration_ms - b.duration_ms) <= 0.5))
    return false;
  for (std::size_t i = 0; i < a.ticks.size(); ++i) {
    if (a.ticks[i].t_ms != b.ticks[i].t_ms || a.ticks[i].count_l != b.ticks[i].count_l ||
        a.ticks[i].count_r != b.ticks[i].count_r)
      return false;
  }
  return true;
}

// Finding 3: recorded_runs reads trial, count_l, count_r and the ticks' counts with
// get<std::int64_t>(), which converts a JSON number with a fraction or exponent beyond the 64-bit
// range by a cast whose result is undefined (UBSan: "1e+300 is outside the range of
// representable values of type 'long'").
bool finding_3(const nlohmann::json& session) {
  const auto beyond = [](const nlohmann::json& v) {
    return v.is_number_float() && !(std::fabs(v.get<double>()) < 9.2e18);
  };
  if (!session.is_object() || !session.contains("runs") || !session["runs"].is_array())
    return false;
  for (const nlohmann::json& run : session["runs"]) {
    if (!run.is_object())
      continue;
    for (const char* key : {"trial", "count_l", "count_r"}) {
      if (run.contains(key) && beyond(run[key]))
        return true;
    }
    if (!run.contains("ticks") || !run["ticks"].is_array())
      continue;
    for (const nlohmann::json& t : run["ticks"]) {
      if (t.is_array() && ((t.size() > 1u && beyond(t[1])) || (t.size() > 2u && beyond(t[2]))))
        return true;
    }
  }
  return false;
}

// Finding 4: report.html's odometry trace (session_report.cpp, trace_of) subtracts consecutive
// tick counts in 64-bit signed integers, which overflows for counts more than 2^63 apart.
bool finding_4(const std::vector<RunRecord>& runs) {
  for (const RunRecord& r : runs) {
    for (std::size_t i = 1; i < r.ticks.size(); ++i) {
      std::int64_t difference = 0;
      if (__builtin_sub_overflow(r.ticks[i].count_l, r.ticks[i - 1u].count_l, &difference) ||
          __builtin_sub_overflow(r.ticks[i].count_r, r.ticks[i - 1u].count_r, &difference))
        return true;
    }
  }
  return false;
}

// The runs a resumed session has taken over, where it puts them.
void take_over(const std::vector<RunRecord>& runs) {
  using namespace odocal::host;
  const nlohmann::json written = {{"runs", session::runs_json(runs)}};
  const std::vector<RunRecord> again =
      recorded_runs(nlohmann::json::parse(written.dump(2)), scratch.path());
  if (again.size() != runs.size())
    __builtin_trap();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!same_run(runs[i], again[i]))
      __builtin_trap();
  }
  static_cast<void>(session::runs_csv(runs));
  for (const RunRecord& r : runs) {
    // A logged run (the labels of fit's and auto's runs) becomes its tick log, read back for the
    // fit (session_fit.cpp, session_auto.cpp).
    if (r.label != "line" && r.label != "arc-left" && r.label != "arc-right" &&
        r.label != "turns-cw" && r.label != "turns-ccw")
      continue;
    // Finding 1: tick_log_csv (session_fit.cpp) reads r.ticks.front() of a logged run that
    // session.json gives without ticks (a segmentation fault of `odocal session --resume`).
    if (r.ticks.empty())
      continue;
    const std::string path = scratch.write("fit_run_01.csv", session::tick_log_csv(r));
    try {
      static_cast<void>(read_tick_log(path));
    } catch (const InputError& e) {
      if (e.file() != path)
        __builtin_trap();
    }
  }
  session::ReportInput report;
  report.title = "odocal session fit";
  report.complete = false;
  report.interruption = "fuzz";
  report.runs = runs;
  if (!finding_4(runs))
    static_cast<void>(session::report_html(report));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace odocal::host;
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n--- measurements.csv\n";
  const std::size_t cut = input.find(separator);
  if (cut == std::string::npos) {
    scratch.remove("measurements.csv");
  } else {
    scratch.write("measurements.csv", input.substr(cut + separator.size()));
  }
  const nlohmann::json session = nlohmann::json::parse(
      input.substr(0, cut == std::string::npos ? input.size() : cut), nullptr, false);
  if (session.is_discarded() || finding_3(session))
    return 0;
  std::vector<RunRecord> runs;
  try {
    runs = recorded_runs(session, scratch.path());
  } catch (const InputError& e) {
    if (e.file() != scratch.path() + "/session.json")
      __builtin_trap();
    return 0;
  }
  const std::vector<RunRecord> recorded = runs;
  try {
    const std::vector<std::string> said = take_edited_journal(runs, scratch.path());
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (!same_pose(runs[i].measured, recorded[i].measured) && said.empty())
        __builtin_trap();  // a reading changed without a word
    }
  } catch (const InputError& e) {
    if (e.file() != scratch.path() + "/measurements.csv")
      __builtin_trap();
    return 0;
  }
  take_over(runs);
  return 0;
}
