// libFuzzer target: arbitrary bytes as the tick logs `odocal fit --log` reads (docs/calibration.md,
// "What to record"). The input holds up to three logs, separated by a line `---`; each is written
// to a file and read with read_tick_log, which must return a log that keeps the documented rules
// (at least 2 rows, time never going back, finite values within their bounds, ground truth after
// the first row) or throw InputError naming the file, and nothing else. A log read is written
// back with write_tick_log and must read back the same. The logs read are then scored and fitted
// as `odocal fit` does (without the bootstrap and the lag probe, whose cost is per input): no
// exception, and a result, when there is one, is a finite, positive geometry.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_scratch.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/fit.hpp"

namespace {

const odocal::fuzz::ScratchDir scratch("tick_log");

// The documented bounds (host_sim/src/fit/tick_log.cpp).
bool keeps_the_rules(const odocal::host::TickLog& log) {
  if (log.rows.size() < 2u)
    return false;
  bool truth_after_start = false;
  for (std::size_t i = 0; i < log.rows.size(); ++i) {
    const odocal::host::TickRow& r = log.rows[i];
    if (!std::isfinite(r.t_s) || !(std::fabs(r.t_s) <= 1e11) || !(std::fabs(r.count_l) <= 1.1e15) ||
        !(std::fabs(r.count_r) <= 1.1e15) ||
        (r.has_xy && !(std::fabs(r.x_mm) <= 1e9 && std::fabs(r.y_mm) <= 1e9)) ||
        (r.has_theta && !(std::fabs(r.theta_deg) <= 3.6e8)))
      return false;
    if (i > 0u && r.t_s < log.rows[i - 1u].t_s)
      return false;
    truth_after_start = truth_after_start || (i > 0u && (r.has_xy || r.has_theta));
  }
  return truth_after_start && log.rows.front().has_xy == log.rows.front().has_theta;
}

bool same_rows(const odocal::host::TickLog& a, const odocal::host::TickLog& b) {
  if (a.rows.size() != b.rows.size())
    return false;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    const odocal::host::TickRow& x = a.rows[i];
    const odocal::host::TickRow& y = b.rows[i];
    if (x.t_s != y.t_s || x.count_l != y.count_l || x.count_r != y.count_r ||
        x.has_xy != y.has_xy || x.has_theta != y.has_theta ||
        (x.has_xy && (x.x_mm != y.x_mm || x.y_mm != y.y_mm)) ||
        (x.has_theta && x.theta_deg != y.theta_deg))
      return false;
  }
  return true;
}

bool positive_finite(double value) {
  return std::isfinite(value) && value > 0.0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace odocal;
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<host::TickLog> logs;
  std::size_t start = 0u;
  for (int n = 0; n < 3 && start <= input.size(); ++n) {
    std::size_t end = input.find("\n---\n", start);
    if (n == 2 || end == std::string::npos)
      end = input.size();
    const std::string name = "log_" + std::to_string(n + 1) + ".csv";
    const std::string path = scratch.write(name, input.data() + start, end - start);
    start = end + 5u;
    try {
      host::TickLog log = host::read_tick_log(path);
      if (log.source != path || !keeps_the_rules(log))
        __builtin_trap();
      std::ostringstream written;
      host::write_tick_log(log, written);
      const host::TickLog again = host::read_tick_log(scratch.write("again.csv", written.str()));
      if (!same_rows(log, again))
        __builtin_trap();
      logs.push_back(std::move(log));
    } catch (const host::InputError& e) {
      if (e.file() != path)
        __builtin_trap();
    }
  }
  if (logs.empty())
    return 0;

  const host::FitNominal nominal{};
  host::FitOptions options;
  options.replicates = 0u;
  options.estimate_lag = false;
  options.model = host::FitModelKind::one_wheelbase;
  const host::FitGeometry as_told{nominal.wheel_diameter_mm, nominal.wheel_diameter_mm,
                                  nominal.wheelbase_mm, host::FitModelKind::one_wheelbase, 0.0};
  const host::FitFigures before =
      host::score_runs(logs, nominal, as_told, options.heading_length_mm);
  if (before.runs != logs.size() || std::isnan(before.end_rms_before_mm) ||
      std::isnan(before.path_rms_before_mm))
    __builtin_trap();
  const host::FitOutcome outcome = host::fit_geometry(logs, nominal, options);
  if (outcome) {
    const host::FitGeometry& g = outcome.result->geometry;
    if (!positive_finite(g.wheel_diameter_left_mm) || !positive_finite(g.wheel_diameter_right_mm) ||
        !positive_finite(g.wheelbase_mm) || !std::isfinite(outcome.result->c_l) ||
        !std::isfinite(outcome.result->c_r))
      __builtin_trap();
    static_cast<void>(host::fit_result_json(*outcome.result).dump());
    static_cast<void>(host::fit_result_text(*outcome.result));
  } else if (outcome.error.message.empty()) {
    __builtin_trap();
  }
  return 0;
}
