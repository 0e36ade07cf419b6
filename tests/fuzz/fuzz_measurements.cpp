// libFuzzer target: arbitrary bytes as the measurements a session reads: a measurements CSV
// (`--measurements FILE`: `x_mm,y_mm`, `x_mm,y_mm,theta_deg` or a session's journal
// `run,x_mm,y_mm,theta_deg`), and the same bytes typed at the prompt, line by line. Besides the
// sanitizers it checks the contract of session.hpp: file_measurements throws InputError naming
// the file or serves at least one row, every row finite and within the documented bounds (a
// heading only where the file has one), and one row too many is an InputError; the prompt
// returns only readings that parse and keep the same bounds (with the heading when the run needs
// it), and ends with InputError at the end of the input. Every reading goes through the reading
// check (judge_reading) as a session's run would, against a UMBmark square's run and a turn in
// place's, with the readings before it as the same run's earlier ones.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_scratch.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/session.hpp"
#include "reading_check.hpp"

namespace {

using odocal::host::SessionPose;
using odocal::host::session::ReadingFacts;

const odocal::fuzz::ScratchDir scratch("measurements");

// session_measure.cpp's bounds: 1 km of stop point, ten turns of heading.
bool within_bounds(const SessionPose& p) {
  return std::isfinite(p.x_mm) && std::isfinite(p.y_mm) && std::fabs(p.x_mm) <= 1e6 &&
         std::fabs(p.y_mm) <= 1e6 &&
         (!p.theta_deg || (std::isfinite(*p.theta_deg) && std::fabs(*p.theta_deg) <= 3600.0));
}

// What a session knows of the run being measured (Context::measure), for `command` driven by the
// default robot (60 mm wheels, 150 mm wheelbase) that its odometry says stopped at `odom`.
ReadingFacts facts_of(const std::string& command, const SessionPose& odom, bool heading_needed) {
  using namespace odocal::host::session;
  ReadingFacts facts;
  facts.odom = odom;
  facts.heading_needed = heading_needed;
  const std::optional<odocal::host::Motion> motion = odocal::host::Motion::of_command(command);
  const std::optional<odocal::drive::Path> path = motion ? motion->path() : std::nullopt;
  if (!path)
    __builtin_trap();
  const odocal::drive::model::Geometry<double> g{60.0, 60.0, 150.0, 0.0};
  facts.allowance = allowance_of(*path, g);
  facts.extent = extent_of(*path);
  facts.extent.wheelbase_mm = g.wheelbase;
  return facts;
}

std::vector<ReadingFacts> runs() {
  return {facts_of("run umbmark-cw 4.000", SessionPose{-12.0, 25.0, 1.5}, false),
          facts_of("drive 0.000 1.571 1000", SessionPose{0.0, 0.0, 90.0}, true)};
}

// Judges `pose` (typed as `typed`) as the reading of each run, the earlier ones kept.
void judge(std::vector<ReadingFacts>& facts, const SessionPose& pose, const std::string& typed) {
  for (ReadingFacts& f : facts) {
    const odocal::host::ReadingVerdict verdict =
        odocal::host::session::judge_reading(f, pose, typed);
    if (verdict.plausible != verdict.problem.empty() ||
        verdict.plausible != verdict.explained().empty())
      __builtin_trap();
    if (verdict.suggestion && !within_bounds(*verdict.suggestion))
      __builtin_trap();
    if (f.earlier.size() < 8u)
      f.earlier.push_back({f.odom, pose, f.earlier.size() % 2u == 0u});
  }
}

void from_file(const std::string& path) {
  std::unique_ptr<odocal::host::MeasurementSource> source;
  try {
    source = odocal::host::file_measurements(path);
  } catch (const odocal::host::InputError& e) {
    if (e.file() != path)
      __builtin_trap();
    return;
  }
  const std::size_t rows = source->available(0);
  if (rows == 0u || source->describe() != path || source->available(rows) != 0u)
    __builtin_trap();
  std::vector<ReadingFacts> facts = runs();
  const odocal::host::RunRecord run;
  for (std::size_t i = 0; i < rows; ++i) {
    const SessionPose pose = source->take(run, i, rows);
    if (!within_bounds(pose))
      __builtin_trap();
    judge(facts, pose, "");
  }
  try {
    static_cast<void>(source->take(run, rows, rows));
    __builtin_trap();  // a row too many is no reading
  } catch (const odocal::host::InputError&) {
  }
}

void typed(const std::string& input, bool heading_needed) {
  std::istringstream in(input);
  std::ostringstream prompt;
  const std::unique_ptr<odocal::host::MeasurementSource> source =
      odocal::host::prompt_measurements(in, prompt, true);
  std::vector<ReadingFacts> facts = runs();
  const odocal::host::RunRecord run;
  for (std::size_t i = 0;; ++i) {
    std::vector<ReadingFacts>& all = facts;
    const odocal::host::ReadingCheck check = [&all](const SessionPose& p, const std::string& t) {
      return odocal::host::session::judge_reading(all[0], p, t);
    };
    if (!source->check_next(check, heading_needed))
      __builtin_trap();  // a person is asked again, never judged afterwards
    SessionPose pose;
    try {
      pose = source->take(run, i, i + 1u);
    } catch (const odocal::host::InputError&) {
      return;  // the end of the input
    }
    if (!within_bounds(pose) || (heading_needed && !pose.theta_deg) || i > input.size())
      __builtin_trap();
    judge(facts, pose, "");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  from_file(scratch.write("measurements.csv", input));
  typed(input, false);
  typed(input, true);
  {
    // parse_measurement_line alone, on each line: a reading it takes keeps the bounds.
    std::istringstream in(input);
    for (std::string line; std::getline(in, line);) {
      SessionPose pose;
      std::string why;
      if (odocal::host::parse_measurement_line(line, pose, why) ? !within_bounds(pose)
                                                                : why.empty())
        __builtin_trap();
    }
  }
  return 0;
}
