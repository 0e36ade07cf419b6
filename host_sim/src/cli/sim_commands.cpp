#include "odocal/host/sim_commands.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "odocal/host/sim_procedures.hpp"
#include "odocal/toolkit/cli_checks.hpp"

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
  sub->add_option("--seed", o.seed, "seed of every random term (same seed, same output)")
      ->check(toolkit::whole_check(0u, UINT64_MAX));
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

/// Checks, before anything is simulated, that the picture can be written: an error found only
/// after the run would leave a whole report on stdout with exit status 2. A file this creates is
/// removed again when the run fails (`discard_svg`).
bool check_svg(const CommonOptions& o, bool& created) {
  created = false;
  if (o.svg_file.empty()) {
    return true;
  }
  created = access(o.svg_file.c_str(), F_OK) != 0;
  std::ofstream probe(o.svg_file, std::ios::app);
  if (!probe) {
    std::cerr << "odocal sim: " << o.svg_file << ": cannot write\n";
    created = false;
    return false;
  }
  return true;
}

void discard_svg(const CommonOptions& o, bool created) {
  if (created) {
    std::remove(o.svg_file.c_str());
  }
}

/// Writes the picture, then the report; returns the exit status. A failed procedure (`ok`
/// false) prints its report (the error and `simulated_s`) but no picture, says why on stderr and
/// returns 2, as every error of `odocal`; so does a picture that cannot be written, which then
/// leaves stdout empty.
int finish(const CommonOptions& o, bool svg_created, bool ok, const nlohmann::json& json,
           const std::string& text, const std::string& svg, const std::string& error) {
  if (ok && !o.svg_file.empty()) {
    std::ofstream out(o.svg_file);
    out << svg;
    out.close();
    if (!out) {
      std::cerr << "odocal sim: " << o.svg_file << ": cannot write\n";
      return 2;
    }
  }
  if (!ok) {
    discard_svg(o, svg_created);
  }
  if (o.json) {
    std::cout << json.dump(2) << "\n";
  } else {
    std::cout << text;
  }
  if (!ok) {
    std::cerr << "odocal sim: " << error << "\n";
    return 2;
  }
  return 0;
}

/// `--side-mm`: read in mm, strictly, and checked in mm; the procedures take metres.
constexpr double side_min_mm = 100.0;
constexpr double side_max_mm = 20000.0;

void add_side_mm(CLI::App* sub, double& side_mm, const char* help) {
  sub->add_option("--side-mm", side_mm, help)
      ->check(toolkit::range_check(side_min_mm, side_max_mm, "mm"));
}

/// Loads the robot and checks the picture's path: false (exit 2, reason on stderr) when either
/// fails, before anything is simulated.
bool prepare(const CommonOptions& o, RobotSpec& spec, bool& svg_created) {
  return load_robot(o, spec) && check_svg(o, svg_created);
}

/// Why a Monte Carlo run failed: how many robots could not be calibrated and the first one's
/// reason; empty when every robot was.
std::string montecarlo_error(const MonteCarloReport& report) {
  std::size_t failed = 0;
  const MonteCarloRobot* first_failure = nullptr;
  for (const MonteCarloRobot& r : report.robots) {
    if (!r.ok) {
      ++failed;
      if (first_failure == nullptr) {
        first_failure = &r;
      }
    }
  }
  return first_failure == nullptr ? std::string()
                                  : "montecarlo: " + std::to_string(failed) + " of " +
                                        std::to_string(report.robots.size()) +
                                        " robots could not be calibrated (robot " +
                                        std::to_string(first_failure - report.robots.data()) +
                                        ": " + first_failure->error + ")";
}

/// `odocal sim umbmark`: UMBmark on the simulated robot, solved, applied and repeated.
void add_sim_umbmark(CLI::App* sim, int& exit_code) {
  auto common_u = std::make_shared<CommonOptions>();
  auto umb = std::make_shared<UmbmarkOptions>();
  auto umb_side_mm = std::make_shared<double>(umb->side_m * 1e3);
  auto* u = sim->add_subcommand("umbmark", "UMBmark: 5 cw + 5 ccw squares, solve, apply, repeat");
  add_common(u, *common_u);
  add_side_mm(u, *umb_side_mm, "side of the square, mm (100 to 20000, default 4000)");
  u->add_option("--runs", umb->runs, "runs per direction per pass (2 to 64, default 5)")
      ->check(toolkit::whole_check(2u, 64u));
  u->add_flag("--exact", umb->exact, "solve without the small-angle approximations");
  u->callback([&exit_code, common_u, umb, umb_side_mm] {
    RobotSpec spec;
    bool svg_created = false;
    if (!prepare(*common_u, spec, svg_created)) {
      exit_code = 2;
      return;
    }
    UmbmarkOptions options = *umb;
    options.side_m = *umb_side_mm * 1e-3;
    options.record_paths = !common_u->svg_file.empty();
    UmbmarkReport report;
    {
      Progress progress;
      report = run_umbmark(spec, common_u->seed, options, std::ref(progress));
    }
    exit_code =
        finish(*common_u, svg_created, report.ok, umbmark_report_json(report),
               umbmark_report_text(report), umbmark_report_svg(report), "umbmark: " + report.error);
  });
}

/// `odocal sim validate`: Maddahi and Zareinia: straight trials and unseen path.
void add_sim_validate(CLI::App* sim, int& exit_code) {
  auto common_v = std::make_shared<CommonOptions>();
  auto val = std::make_shared<ValidateOptions>();
  auto* v = sim->add_subcommand(
      "validate",
      "Maddahi & Zareinia: straight trials, F_lat/F_lon by LR and bootstrap, unseen path");
  add_common(v, *common_v);
  v->add_option("--trials", val->trials,
                "straight calibration trials per floor (6 to 200, default 20)")
      ->check(toolkit::whole_check(6u, 200u));
  v->add_option("--runs", val->runs, "unseen-path runs per scenario (1 to 100, default 5)")
      ->check(toolkit::whole_check(1u, 100u));
  v->add_option("--replicates", val->replicates,
                "bootstrap replicates B (100 to 100000, default 1000)")
      ->check(toolkit::whole_check(100u, 100000u));
  v->callback([&exit_code, common_v, val] {
    RobotSpec spec;
    bool svg_created = false;
    if (!prepare(*common_v, spec, svg_created)) {
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
    exit_code = finish(*common_v, svg_created, report.ok, validate_report_json(report),
                       validate_report_text(report), validate_report_svg(report),
                       "validate: " + report.error);
  });
}

/// `odocal sim extended`: extended UMBmark, with and without cables under one wheel.
void add_sim_extended(CLI::App* sim, int& exit_code) {
  auto common_e = std::make_shared<CommonOptions>();
  auto ext = std::make_shared<ExtendedOptions>();
  auto ext_side_mm = std::make_shared<double>(ext->side_m * 1e3);
  auto* e = sim->add_subcommand(
      "extended",
      "Extended UMBmark: squares with and without ten cables under one wheel (non-systematic)");
  add_common(e, *common_e);
  add_side_mm(e, *ext_side_mm, "side of the square, mm (100 to 20000, default 4000)");
  e->add_option("--runs", ext->runs, "runs per direction on each floor (2 to 64, default 5)")
      ->check(toolkit::whole_check(2u, 64u));
  e->callback([&exit_code, common_e, ext, ext_side_mm] {
    RobotSpec spec;
    bool svg_created = false;
    if (!prepare(*common_e, spec, svg_created)) {
      exit_code = 2;
      return;
    }
    ExtendedOptions options = *ext;
    options.side_m = *ext_side_mm * 1e-3;
    options.record_paths = !common_e->svg_file.empty();
    ExtendedReport report;
    {
      Progress progress;
      report = run_extended(spec, common_e->seed, options, std::ref(progress));
    }
    exit_code = finish(*common_e, svg_created, report.ok, extended_report_json(report),
                       extended_report_text(report), extended_report_svg(report),
                       "extended: " + report.error);
  });
}

/// `odocal sim montecarlo`: many random robots calibrated by UMBmark.
void add_sim_montecarlo(CLI::App* sim, int& exit_code) {
  auto common_m = std::make_shared<CommonOptions>();
  auto mc = std::make_shared<MonteCarloOptions>();
  mc->umbmark.side_m = 1.5;
  mc->umbmark.v_max_mps = 0.4;
  mc->umbmark.control_hz = 500.0f;
  auto mc_side_mm = std::make_shared<double>(mc->umbmark.side_m * 1e3);
  auto* m = sim->add_subcommand("montecarlo", "Many random robots calibrated by UMBmark");
  add_common(m, *common_m);
  m->add_option("--robots", mc->robots, "how many robots (1 to 1000000, default 100)")
      ->check(toolkit::whole_check(1u, 1000000u));
  m->add_option("--threads", mc->threads, "worker threads (1 to 64, default 2)")
      ->check(toolkit::whole_check(1u, 64u));
  add_side_mm(m, *mc_side_mm, "side of the square, mm (100 to 20000, default 1500)");
  m->callback([&exit_code, common_m, mc, mc_side_mm] {
    RobotSpec spec;
    bool svg_created = false;
    if (!prepare(*common_m, spec, svg_created)) {
      exit_code = 2;
      return;
    }
    MonteCarloOptions options = *mc;
    options.umbmark.side_m = *mc_side_mm * 1e-3;
    MonteCarloReport report;
    {
      Progress progress;
      report = run_montecarlo(spec, common_m->seed, options, std::ref(progress));
    }
    const std::string error = montecarlo_error(report);
    exit_code = finish(*common_m, svg_created, error.empty(), montecarlo_report_json(report),
                       montecarlo_report_text(report), montecarlo_report_svg(report), error);
  });
}

}  // namespace

void register_sim_commands(CLI::App& app, int& exit_code) {
  auto* sim = app.add_subcommand("sim", "Simulated calibration procedures on the simulated robot");
  sim->require_subcommand(1);
  // Each adds its subcommand, whose option storage lives as long as the app (the callbacks run
  // from app.parse).
  add_sim_umbmark(sim, exit_code);
  add_sim_validate(sim, exit_code);
  add_sim_extended(sim, exit_code);
  add_sim_montecarlo(sim, exit_code);
}

}  // namespace odocal::host
