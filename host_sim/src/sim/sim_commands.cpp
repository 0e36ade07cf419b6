#include "odocal/host/sim_commands.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

/// Options every `sim` subcommand takes.
struct CommonOptions {
  std::string robot_file;
  std::uint64_t seed = 1;
  bool json = false;
  std::string svg_file;
};

void add_common(CLI::App* sub, CommonOptions& o) {
  sub->add_option("--robot", o.robot_file, "robot file (flat JSON; see docs/simulation.md)");
  sub->add_option("--seed", o.seed, "seed of every random term (same seed, same output)");
  sub->add_flag("--json", o.json, "print one JSON object on stdout");
  sub->add_option("--svg", o.svg_file, "write a picture (SVG) to this file");
}

/// A progress line on stderr, only once the procedure has taken more than a second, at most a few
/// times a second; overwritten in place on a terminal.
class Progress {
 public:
  Progress() : start_(std::chrono::steady_clock::now()), tty_(isatty(2) == 1) {}
  ~Progress() {
    if (shown_ && tty_) {
      std::cerr << "\r\033[K" << std::flush;
    }
  }
  void operator()(const std::string& message) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed < 1.0 || elapsed - last_s_ < (tty_ ? 0.25 : 2.0)) {
      return;
    }
    last_s_ = elapsed;
    shown_ = true;
    char time[32];
    std::snprintf(time, sizeof time, " [%.0f s]", elapsed);
    if (tty_) {
      std::cerr << "\r\033[K" << message << time << std::flush;
    } else {
      std::cerr << message << time << "\n";
    }
  }

 private:
  std::chrono::steady_clock::time_point start_;
  bool tty_;
  bool shown_ = false;
  double last_s_ = -1.0;
};

bool load_robot(const CommonOptions& o, RobotSpec& spec) {
  spec = default_robot();
  if (o.robot_file.empty()) {
    return true;
  }
  std::string error;
  if (!load_robot_file(o.robot_file, spec, error)) {
    std::cerr << "odocal sim: " << error << "\n";
    return false;
  }
  return true;
}

bool write_svg(const std::string& path, const std::string& svg) {
  if (path.empty()) {
    return true;
  }
  std::ofstream out(path);
  out << svg;
  if (!out) {
    std::cerr << "odocal sim: " << path << ": cannot write\n";
    return false;
  }
  return true;
}

/// Prints the report and the picture; returns the exit status.
int finish(const CommonOptions& o, bool ok, const nlohmann::json& json, const std::string& text,
           const std::string& svg, const std::string& error) {
  if (o.json) {
    std::cout << json.dump(2) << "\n";
  } else {
    std::cout << text;
  }
  if (!ok) {
    std::cerr << "odocal sim: " << error << "\n";
    return 1;
  }
  return write_svg(o.svg_file, svg) ? 0 : 2;
}

}  // namespace

void register_sim_commands(CLI::App& app, int& exit_code) {
  auto* sim = app.add_subcommand("sim", "Simulated calibration procedures on the simulated robot");
  sim->require_subcommand(1);

  // The option storage lives as long as the app (the callbacks run from app.parse).
  auto common_u = std::make_shared<CommonOptions>();
  auto umb = std::make_shared<UmbmarkOptions>();
  auto* u = sim->add_subcommand("umbmark", "UMBmark: 5 cw + 5 ccw squares, solve, apply, repeat");
  add_common(u, *common_u);
  u->add_option("--side-mm", umb->side_m, "side of the square, mm")
      ->transform([](std::string s) { return std::to_string(std::stod(s) / 1000.0); })
      ->check(CLI::Range(0.1, 20.0));
  u->add_option("--runs", umb->runs, "runs per direction per pass")->check(CLI::Range(2, 64));
  u->add_flag("--exact", umb->exact, "solve without the small-angle approximations");
  u->callback([&exit_code, common_u, umb] {
    RobotSpec spec;
    if (!load_robot(*common_u, spec)) {
      exit_code = 2;
      return;
    }
    UmbmarkOptions options = *umb;
    options.record_paths = !common_u->svg_file.empty();
    UmbmarkReport report;
    {
      Progress progress;
      report = run_umbmark(spec, common_u->seed, options, std::ref(progress));
    }
    exit_code = finish(*common_u, report.ok, umbmark_report_json(report),
                       umbmark_report_text(report), umbmark_report_svg(report), report.error);
  });

  auto common_v = std::make_shared<CommonOptions>();
  auto val = std::make_shared<ValidateOptions>();
  auto* v = sim->add_subcommand(
      "validate",
      "Maddahi & Zareinia: straight trials, F_lat/F_lon by LR and bootstrap, unseen path");
  add_common(v, *common_v);
  v->add_option("--trials", val->trials, "straight calibration trials per floor")
      ->check(CLI::Range(6, 200));
  v->add_option("--runs", val->runs, "unseen-path runs per scenario")->check(CLI::Range(1, 100));
  v->add_option("--replicates", val->replicates, "bootstrap replicates B")
      ->check(CLI::Range(100, 100000));
  v->callback([&exit_code, common_v, val] {
    RobotSpec spec;
    if (!load_robot(*common_v, spec)) {
      exit_code = 2;
      return;
    }
    ValidateOptions options = *val;
    options.record_paths = !common_v->svg_file.empty();
    ValidateReport report;
    {
      Progress progress;
      report = run_validate(spec, common_v->seed, options, std::ref(progress));
    }
    exit_code = finish(*common_v, report.ok, validate_report_json(report),
                       validate_report_text(report), validate_report_svg(report), report.error);
  });

  auto common_m = std::make_shared<CommonOptions>();
  auto mc = std::make_shared<MonteCarloOptions>();
  mc->umbmark.side_m = 1.5;
  mc->umbmark.v_max_mps = 0.4;
  mc->umbmark.control_hz = 500.0f;
  auto* m = sim->add_subcommand("montecarlo", "Many random robots calibrated by UMBmark");
  add_common(m, *common_m);
  m->add_option("--robots", mc->robots, "how many robots")->check(CLI::Range(1, 1000000));
  m->add_option("--threads", mc->threads, "worker threads (default 2)")->check(CLI::Range(1, 64));
  m->add_option("--side-mm", mc->umbmark.side_m, "side of the square, mm (default 1500)")
      ->transform([](std::string s) { return std::to_string(std::stod(s) / 1000.0); })
      ->check(CLI::Range(0.1, 20.0));
  m->callback([&exit_code, common_m, mc] {
    RobotSpec spec;
    if (!load_robot(*common_m, spec)) {
      exit_code = 2;
      return;
    }
    MonteCarloReport report;
    {
      Progress progress;
      report = run_montecarlo(spec, common_m->seed, *mc, std::ref(progress));
    }
    bool ok = true;
    for (const MonteCarloRobot& r : report.robots)
      ok = ok && r.ok;
    exit_code =
        finish(*common_m, ok, montecarlo_report_json(report), montecarlo_report_text(report),
               montecarlo_report_svg(report), "some robots could not be calibrated");
  });
}

}  // namespace odocal::host
