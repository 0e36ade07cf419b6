// `odocal fit --log FILE... --wheel-diameter-mm D --wheelbase-mm b --counts-per-rev N
//  [--holdout FILE...] [--b B] [--seed S] [--level 0.95] [--model auto|one|arc|turn-rate] [--json]`

#include "odocal/host/fit_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "odocal/host/csv.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/toolkit/cli_checks.hpp"

namespace odocal::host {
namespace {

struct FitCommandOptions {
  std::vector<std::string> logs;
  std::vector<std::string> holdout;
  double wheel_diameter_mm = 0.0;
  double wheelbase_mm = 0.0;
  double counts_per_rev = 0.0;
  std::uint32_t replicates = 500;
  std::uint64_t seed = 1;
  double level = 0.95;
  std::string model = "auto";
  bool json = false;
};

/// Bootstrap progress on stderr after the first second, at most every 2 s (4 Hz on a terminal).
FitProgressFn progress_printer() {
  const auto start = std::chrono::steady_clock::now();
  auto last = std::make_shared<double>(-1.0);
  const bool tty = isatty(2) == 1;
  return [=](const std::string& message) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed < 1.0 || elapsed - *last < (tty ? 0.25 : 2.0)) {
      return;
    }
    *last = elapsed;
    std::cerr << (tty ? "\r\033[K" : "") << message << (tty ? "" : "\n") << std::flush;
  };
}

int run_fit(const FitCommandOptions& o) {
  std::vector<TickLog> logs;
  std::vector<TickLog> holdout;
  try {
    for (const std::string& path : o.logs) {
      logs.push_back(read_tick_log(path));
    }
    for (const std::string& path : o.holdout) {
      holdout.push_back(read_tick_log(path));
    }
  } catch (const InputError& e) {
    std::cerr << "odocal fit: " << e.what() << '\n';
    return 2;
  }
  FitNominal nominal;
  nominal.wheel_diameter_mm = o.wheel_diameter_mm;
  nominal.wheelbase_mm = o.wheelbase_mm;
  nominal.counts_per_rev = o.counts_per_rev;
  FitOptions options;
  options.replicates = o.replicates;
  options.seed = o.seed;
  options.level = o.level;
  options.progress = progress_printer();
  if (o.model == "one") {
    options.model = FitModelKind::one_wheelbase;
  } else if (o.model == "arc") {
    options.model = FitModelKind::arc_wheelbase;
  } else if (o.model == "turn-rate") {
    options.model = FitModelKind::turn_rate_wheelbase;
  }
  const FitOutcome outcome = fit_geometry(logs, nominal, options, holdout);
  if (isatty(2) == 1) {
    std::cerr << "\r\033[K" << std::flush;
  }
  if (!outcome) {
    std::cerr << "odocal fit: " << o.logs.front() << (o.logs.size() > 1 ? " ..." : "") << ": "
              << (outcome.error.parameter.empty() ? std::string()
                                                  : "field '" + outcome.error.parameter + "': ")
              << outcome.error.message << '\n';
    return 2;
  }
  // Beside the geometry: the random error growth from the same runs' residuals.
  const NoiseEstimate noise = noise_for_fit(logs, *outcome.result, options);
  const nlohmann::json j = fit_json(*outcome.result, noise);
  // Nothing that is not a number is printed (the bounds above keep every figure finite).
  for (const char* key : {"wheel_diameter_left_mm", "wheel_diameter_right_mm", "wheelbase_mm"}) {
    if (!std::isfinite(j.at(key).get<double>())) {
      std::cerr << "odocal fit: field '" << key << "': the result is not a finite number\n";
      return 2;
    }
  }
  if (o.json) {
    std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  } else {
    std::cout << fit_text(*outcome.result, noise);
  }
  return 0;
}

}  // namespace

void register_fit_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<FitCommandOptions>();
  auto* cmd = app.add_subcommand(
      "fit", "true wheel diameters and wheelbase from tick logs (least squares, bootstrap)");
  cmd->add_option("--log", o->logs, "tick log CSV(s) t_s,count_l,count_r[,x_mm,y_mm,theta_deg]")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--holdout", o->holdout, "tick logs kept out of the fit, to test it")
      ->expected(1, -1);
  cmd->add_option("--wheel-diameter-mm", o->wheel_diameter_mm, "nominal wheel diameter D, mm")
      ->required()
      ->check(toolkit::range_check(1.0, 1e4, "mm"));
  cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "nominal wheelbase b, mm")
      ->required()
      ->check(toolkit::range_check(1.0, 1e4, "mm"));
  cmd->add_option("--counts-per-rev", o->counts_per_rev,
                  "encoder counts per wheel turn after x4 decoding (fractions allowed)")
      ->required()
      ->check(toolkit::range_check(0.0, 1e7, "", toolkit::LowBound::open));
  cmd->add_option("--b", o->replicates, "bootstrap replicates B (0: no intervals)")
      ->check(toolkit::whole_check(0, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "bootstrap seed (same seed, same intervals)")
      ->check(toolkit::whole_check(0, UINT64_MAX))
      ->capture_default_str();
  cmd->add_option("--level", o->level, "interval level")
      ->check(toolkit::number_check("a finite number strictly between 0 and 1 (e.g. 0.95)",
                                    [](double v) { return v > 0.0 && v < 1.0; }))
      ->capture_default_str();
  cmd->add_option(
         "--model", o->model,
         "auto (chosen by held-out prediction), one, arc or turn-rate (docs/calibration.md)")
      ->check(CLI::IsMember({"auto", "one", "arc", "turn-rate"}))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "print one JSON object");
  cmd->callback([o, &exit_code] { exit_code = run_fit(*o); });
}

}  // namespace odocal::host
