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
  if (a.label != b.label || a.motion != b.motion || a.trial != b.trial || a.path != b.path ||
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
    // As Context::run takes over a logged run: its ticks checked (InputError naming
    // session.json), then written as its tick log.
    try {
      session::check_replayed_ticks(r, 1, scratch.path() + "/session.json");
    } catch (const InputError& e) {
      if (e.file() != scratch.path() + "/session.json")
        __builtin_trap();
      continue;
    }
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
  if (session.is_discarded())
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
