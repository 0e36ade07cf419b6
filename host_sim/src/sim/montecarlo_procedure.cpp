// `odocal sim montecarlo`: many random robots, each calibrated by UMBmark, on all cores.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "odocal/calib/quantile.hpp"
#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/svg_plot.hpp"
#include "odocal/sim/random.hpp"

namespace odocal::host {
namespace {

/// Robot `index` of a run: its geometry drawn from its own generator, so the result does not
/// depend on which thread simulates it or in which order.
MonteCarloRobot simulate_robot(const RobotSpec& base, std::uint64_t seed, std::size_t index,
                               const MonteCarloOptions& o) {
  sim::Random random = sim::Random::derive(seed, index);
  RobotSpec spec = base;
  const double d = static_cast<double>(base.nominal.wheel_diameter_mm) * 1e-3;
  const double b = static_cast<double>(base.nominal.wheelbase_mm) * 1e-3;
  spec.truth.left_diameter_m = d * (1.0 + random.uniform(-o.diameter_spread, o.diameter_spread));
  spec.truth.right_diameter_m = d * (1.0 + random.uniform(-o.diameter_spread, o.diameter_spread));
  spec.truth.wheelbase_m = b * (1.0 + random.uniform(-o.wheelbase_spread, o.wheelbase_spread));
  spec.truth.physics_step_ns = o.physics_step_ns;
  const std::uint64_t plant_seed = random.next_u64();
  MonteCarloRobot r;
  UmbmarkOptions u = o.umbmark;
  u.record_paths = false;
  const UmbmarkReport report = run_umbmark(spec, plant_seed, u);
  r.truth = report.truth;
  r.simulated_s = report.simulated_s;
  if (!report.ok) {
    r.error = report.error;
    return r;
  }
  r.ok = true;
  r.recovered_e_d = report.recovered_e_d;
  r.recovered_e_b = report.recovered_e_b;
  r.e_max_before_mm = report.passes.front().result.e_max_syst_mm;
  r.e_max_after_mm = report.passes.back().result.e_max_syst_mm;
  r.improvement_fold = report.improvement_fold;
  r.passes = report.passes.size() - 1;
  return r;
}

struct Summary {
  double min = 0.0, p05 = 0.0, median = 0.0, mean = 0.0, p95 = 0.0, max = 0.0;
};

Summary summarise(std::vector<double> v) {
  Summary s;
  if (v.empty()) {
    return s;
  }
  // The mean over the sorted values (its rounding as before), then the quantiles, which reorder.
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  double sum = 0.0;
  for (double x : v) {
    sum += x;
  }
  const auto quantile = [&v](double q) { return calib::sample_quantile(v.data(), v.size(), q); };
  s.p05 = quantile(0.05);
  s.median = quantile(0.5);
  s.p95 = quantile(0.95);
  s.mean = sum / static_cast<double>(v.size());
  return s;
}

nlohmann::json summary_json(const Summary& s) {
  return {{"min", s.min},   {"p05", s.p05}, {"median", s.median},
          {"mean", s.mean}, {"p95", s.p95}, {"max", s.max}};
}

struct Columns {
  std::vector<double> fold, e_d_error, e_b_error, before, after;
  std::size_t ok = 0, tenfold = 0, second = 0;
};

Columns columns(const MonteCarloReport& r) {
  Columns c;
  for (const MonteCarloRobot& robot : r.robots) {
    if (!robot.ok)
      continue;
    ++c.ok;
    c.fold.push_back(robot.improvement_fold);
    c.e_d_error.push_back(std::fabs(robot.recovered_e_d - robot.truth.e_d));
    c.e_b_error.push_back(std::fabs(robot.recovered_e_b - robot.truth.e_b));
    c.before.push_back(robot.e_max_before_mm);
    c.after.push_back(robot.e_max_after_mm);
    if (robot.improvement_fold >= 10.0)
      ++c.tenfold;
    if (robot.passes > 1)
      ++c.second;
  }
  return c;
}

}  // namespace

MonteCarloReport run_montecarlo(const RobotSpec& robot, std::uint64_t seed,
                                const MonteCarloOptions& options, const ProgressFn& progress) {
  MonteCarloReport report;
  report.seed = seed;
  report.options = options;
  report.robots.resize(options.robots);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::mutex progress_mutex;
  auto worker = [&]() {
    for (std::size_t i = next.fetch_add(1); i < options.robots; i = next.fetch_add(1)) {
      report.robots[i] = simulate_robot(robot, seed, i, options);
      const std::size_t finished = done.fetch_add(1) + 1;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress("montecarlo: robot " + std::to_string(finished) + "/" +
                 std::to_string(options.robots));
      }
    }
  };
  const unsigned threads = std::max(1u, options.threads);
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) {
    pool.emplace_back(worker);
  }
  worker();
  for (std::thread& t : pool) {
    t.join();
  }
  for (const MonteCarloRobot& r : report.robots) {
    report.simulated_s += r.simulated_s;
  }
  return report;
}

nlohmann::json montecarlo_report_json(const MonteCarloReport& r) {
  const Columns c = columns(r);
  nlohmann::json j;
  j["simulated_s"] = r.simulated_s;
  j["seed"] = r.seed;
  j["robots"] = r.robots.size();
  j["robots_ok"] = c.ok;
  j["side_mm"] = r.options.umbmark.side_m * 1e3;
  j["diameter_spread"] = r.options.diameter_spread;
  j["wheelbase_spread"] = r.options.wheelbase_spread;
  j["improvement_fold"] = summary_json(summarise(c.fold));
  j["e_d_abs_error"] = summary_json(summarise(c.e_d_error));
  j["e_b_abs_error"] = summary_json(summarise(c.e_b_error));
  j["e_max_syst_before_mm"] = summary_json(summarise(c.before));
  j["e_max_syst_after_mm"] = summary_json(summarise(c.after));
  j["fraction_at_least_10_fold"] = c.ok > 0 ? static_cast<double>(c.tenfold) / c.ok : 0.0;
  j["fraction_second_correction"] = c.ok > 0 ? static_cast<double>(c.second) / c.ok : 0.0;
  return j;
}

std::string montecarlo_report_text(const MonteCarloReport& r) {
  const Columns c = columns(r);
  std::ostringstream out;
  out << "Monte Carlo: " << r.robots.size() << " random robots calibrated by UMBmark (seed "
      << r.seed << ")\n";
  out << fmt::format(FMT_STRING("  true diameters nominal x (1 +- {:.2f} %), wheelbase x (1 +- "
                                "{:.1f} %), {:.0f} mm square\n"),
                     r.options.diameter_spread * 100.0, r.options.wheelbase_spread * 100.0,
                     r.options.umbmark.side_m * 1e3);
  out << "                           min        p05     median       mean        p95        max\n";
  // One row: the six statistics in 10 columns, fixed-point or (for tiny errors) exponent form.
  auto row = [&out](const char* name, const Summary& s, bool exponent) {
    const double v[] = {s.min, s.p05, s.median, s.mean, s.p95, s.max};
    out << fmt::format("  {:<20}", name)
        << (exponent ? fmt::format("{:10.1e}", fmt::join(v, " "))
                     : fmt::format("{:10.1f}", fmt::join(v, " ")))
        << "\n";
  };
  row("fold improvement", summarise(c.fold), false);
  row("E_max,syst before mm", summarise(c.before), false);
  row("E_max,syst after mm", summarise(c.after), false);
  row("|E_d error|", summarise(c.e_d_error), true);
  row("|E_b error|", summarise(c.e_b_error), true);
  out << fmt::format(
      FMT_STRING(
          "  robots calibrated {:.0f}/{:.0f}, >= 10-fold: {:.1f} %, second correction: {:.1f} %\n"),
      static_cast<double>(c.ok), static_cast<double>(r.robots.size()),
      c.ok ? 100.0 * c.tenfold / c.ok : 0.0, c.ok ? 100.0 * c.second / c.ok : 0.0);
  out << fmt::format(FMT_STRING("  simulated {:.0f} s of robot time\n"), r.simulated_s);
  return out.str();
}

std::string montecarlo_report_svg(const MonteCarloReport& r) {
  SvgFigure fig;
  SvgPanel& p =
      fig.panel(0, "E_max,syst before vs after (mm, log10)", "log10 before", "log10 after");
  SvgPanel& q = fig.panel(1, "Recovery error: E_d (x 1e4) vs E_b (x 1e3)", "E_d error x 1e4",
                          "E_b error x 1e3");
  for (const MonteCarloRobot& robot : r.robots) {
    if (!robot.ok || !(robot.e_max_before_mm > 0.0) || !(robot.e_max_after_mm > 0.0))
      continue;
    p.add_marker(std::log10(robot.e_max_before_mm), std::log10(robot.e_max_after_mm),
                 robot.improvement_fold >= 10.0 ? "#2471a3" : "#c0392b", '.');
    q.add_marker((robot.recovered_e_d - robot.truth.e_d) * 1e4,
                 (robot.recovered_e_b - robot.truth.e_b) * 1e3, "#2471a3", '.');
  }
  p.legend({{"#2471a3", ">= 10-fold"}, {"#c0392b", "< 10-fold"}});
  return fig.finish();
}

}  // namespace odocal::host
