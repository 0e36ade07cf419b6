// `odocal sim umbmark`: UMBmark (Borenstein & Feng, section 6) on the simulated robot.

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/svg_plot.hpp"

namespace odocal::host {
namespace {

/// The firmware's sticky fault bits in words.
std::string fault_names(std::uint8_t faults) {
  std::string names;
  const std::pair<std::uint8_t, const char*> bits[] = {
      {drive::fault_encoder_left, "left encoder"},
      {drive::fault_encoder_right, "right encoder"},
      {drive::fault_stall_left, "left wheel stalled"},
      {drive::fault_stall_right, "right wheel stalled"}};
  for (const auto& [bit, name] : bits) {
    if ((faults & bit) != 0u) {
      names += (names.empty() ? "" : ", ") + std::string(name);
    }
  }
  return names;
}

/// One pass: `runs` cw then `runs` ccw squares with the factors in the firmware.
bool run_pass(SimulatedRobot& robot, const UmbmarkOptions& options, std::size_t pass_index,
              UmbmarkPass& pass, std::string& error, const ProgressFn& progress) {
  const std::size_t total = 2 * options.runs;
  for (std::size_t i = 0; i < total; ++i) {
    const bool clockwise = i < options.runs;
    if (progress) {
      progress("umbmark: pass " + std::to_string(pass_index + 1) + ", run " +
               std::to_string(i + 1) + "/" + std::to_string(total) +
               (clockwise ? " (cw)" : " (ccw)"));
    }
    std::vector<PathPoint> trace;
    TraceFn tracer;
    if (options.record_paths) {
      tracer = [&trace](const sim::WorldPose& p) { trace.push_back(PathPoint{p.x_m, p.y_m}); };
    }
    constexpr double timeout_s = 3600.0;
    const RunOutcome out =
        robot.run_path(drive::make_umbmark_square(clockwise, static_cast<float>(options.side_m)),
                       timeout_s, tracer, 200u);
    if (!out.completed) {
      const drive::LoopStatus status = robot.loop().status();
      error = "pass " + std::to_string(pass_index + 1) + ", " + (clockwise ? "cw" : "ccw") +
              " run " + std::to_string(i % options.runs + 1) + ": the square did not complete (" +
              (status.faults != drive::fault_none
                   ? "firmware fault: " + fault_names(status.faults)
                   : "not finished after " + fmt::format(FMT_STRING("{:.0f}"), timeout_s) +
                         " s of robot time") +
              ")";
      return false;
    }
    // Return position error: absolute (measured) minus perceived (odometry), start frame.
    const calib::ReturnError error{
        (out.measured.x_m - static_cast<double>(out.odometry.x_m)) * 1e3,
        (out.measured.y_m - static_cast<double>(out.odometry.y_m)) * 1e3};
    (clockwise ? pass.cw : pass.ccw).push_back(error);
    if (options.record_paths) {
      (clockwise ? pass.cw_paths : pass.ccw_paths).push_back(std::move(trace));
    }
  }
  return true;
}

}  // namespace

UmbmarkReport run_umbmark(const RobotSpec& robot_spec, std::uint64_t seed,
                          const UmbmarkOptions& options, const ProgressFn& progress) {
  UmbmarkReport report;
  report.seed = seed;
  report.options = options;
  report.truth = true_errors(robot_spec);
  RobotSpec spec = robot_spec;
  spec.nominal.v_max_mps = static_cast<float>(options.v_max_mps);
  if (options.control_hz > 0.0f) {
    spec.nominal.control_hz = options.control_hz;
  }
  SimulatedRobot robot(spec, seed);
  const double nominal_b = static_cast<double>(spec.nominal.wheelbase_mm);
  calib::WheelFactors factors{1.0, 1.0, nominal_b};

  for (std::size_t pass_index = 0;; ++pass_index) {
    drive::DriveConfig config = spec.nominal;
    config.c_l = static_cast<float>(factors.c_l);
    config.c_r = static_cast<float>(factors.c_r);
    config.wheelbase_mm = static_cast<float>(factors.wheelbase_mm);
    if (!robot.configure(config)) {
      report.error = "the factors left the firmware's parameter ranges";
      report.simulated_s = robot.simulated_s();
      return report;
    }
    UmbmarkPass pass;
    pass.factors = factors;
    if (!run_pass(robot, options, pass_index, pass, report.error, progress)) {
      report.simulated_s = robot.simulated_s();
      return report;
    }
    calib::UmbmarkInput input;
    input.cw = pass.cw.data();
    input.cw_count = pass.cw.size();
    input.ccw = pass.ccw.data();
    input.ccw_count = pass.ccw.size();
    input.side_mm = options.side_m * 1e3;
    input.wheelbase_mm = factors.wheelbase_mm;  // the wheelbase the robot used in these runs
    input.exact = options.exact;
    const calib::UmbmarkStatus status = calib::solve_umbmark(input, pass.result);
    if (status != calib::UmbmarkStatus::ok) {
      report.error = std::string("UMBmark solve: ") + calib::to_string(status);
      report.simulated_s = robot.simulated_s();
      return report;
    }
    report.passes.push_back(std::move(pass));
    const UmbmarkPass& done = report.passes.back();
    // Pass 0 is always followed by a correction; later passes only when 3·SEM says so.
    const bool correct =
        pass_index == 0 || (done.result.second_pass_recommended && pass_index < options.max_passes);
    if (!correct) {
      break;
    }
    factors = calib::compose(factors, done.result);
  }
  report.applied = report.passes.back().factors;
  report.recovered_e_d = report.applied.c_r / report.applied.c_l;
  report.recovered_e_b = report.applied.wheelbase_mm / nominal_b;
  const double after = report.passes.back().result.e_max_syst_mm;
  report.improvement_fold = after > 0.0 ? report.passes.front().result.e_max_syst_mm / after : 0.0;
  report.simulated_s = robot.simulated_s();
  report.ok = true;
  return report;
}

nlohmann::json umbmark_report_json(const UmbmarkReport& r) {
  nlohmann::json j;
  j["simulated_s"] = r.simulated_s;
  j["seed"] = r.seed;
  if (!r.ok) {
    j["error"] = r.error;
    return j;
  }
  j["before"] = umbmark_to_json(r.passes.front().result);
  j["after"] = umbmark_to_json(r.passes.back().result);
  j["improvement_fold"] = r.improvement_fold;
  j["true"] = {{"e_d", r.truth.e_d}, {"e_b", r.truth.e_b}};
  j["recovered"] = {{"e_d", r.recovered_e_d},
                    {"e_b", r.recovered_e_b},
                    {"e_d_error", r.recovered_e_d - r.truth.e_d},
                    {"e_b_error", r.recovered_e_b - r.truth.e_b},
                    {"c_l", r.applied.c_l},
                    {"c_r", r.applied.c_r},
                    {"wheelbase_mm", r.applied.wheelbase_mm}};
  j["corrections"] = r.passes.size() - 1;
  nlohmann::json passes = nlohmann::json::array();
  for (const UmbmarkPass& p : r.passes) {
    nlohmann::json pj;
    pj["c_l"] = p.factors.c_l;
    pj["c_r"] = p.factors.c_r;
    pj["wheelbase_mm"] = p.factors.wheelbase_mm;
    pj["result"] = umbmark_to_json(p.result);
    nlohmann::json cw = nlohmann::json::array();
    nlohmann::json ccw = nlohmann::json::array();
    for (const auto& e : p.cw)
      cw.push_back({e.x_mm, e.y_mm});
    for (const auto& e : p.ccw)
      ccw.push_back({e.x_mm, e.y_mm});
    pj["cw"] = cw;
    pj["ccw"] = ccw;
    passes.push_back(pj);
  }
  j["passes"] = passes;
  j["side_mm"] = r.options.side_m * 1e3;
  j["runs_per_direction"] = r.options.runs;
  j["exact"] = r.options.exact;
  return j;
}

std::string umbmark_report_text(const UmbmarkReport& r) {
  std::ostringstream out;
  out << "UMBmark on the simulated robot ("
      << fmt::format(FMT_STRING("{:.0f}"), r.options.side_m * 1e3) << " mm square, "
      << r.options.runs << " cw + " << r.options.runs << " ccw runs per pass, seed " << r.seed
      << ")\n";
  out << "E_d = D_R/D_L (right over left wheel diameter), E_b = actual over nominal wheelbase;\n"
         "E_max,syst = the larger distance r of the two centres of gravity; SEM = standard error\n"
         "of a centre (sigma/sqrt(n)); 3 SEM rule: another pass while E_max,syst >= 3 SEM, i.e.\n"
         "while the systematic error still stands out of the run-to-run scatter.\n";
  if (!r.ok) {
    out << "failed: " << r.error << "\n";
    return out.str();
  }
  for (std::size_t i = 0; i < r.passes.size(); ++i) {
    const UmbmarkPass& p = r.passes[i];
    const calib::UmbmarkResult& res = p.result;
    out << "\n"
        << (i == 0 ? "Before calibration" : "After correction " + std::to_string(i))
        << fmt::format(FMT_STRING("  (c_L {:.6f}, c_R {:.6f}, b {:.3f} mm)\n"), p.factors.c_l,
                       p.factors.c_r, p.factors.wheelbase_mm);
    out << "  return errors, mm (measured minus odometry), x and y of each run:\n";
    out << "         " << fmt::format("   cw {:>8} {:>8}", "x", "y")
        << fmt::format("   ccw {:>8} {:>8}", "x", "y") << "\n";
    for (std::size_t k = 0; k < p.cw.size() || k < p.ccw.size(); ++k) {
      out << "    run " << (k + 1);
      if (k < p.cw.size())
        out << fmt::format(FMT_STRING("   cw {:8.1f} {:8.1f}"), p.cw[k].x_mm, p.cw[k].y_mm);
      if (k < p.ccw.size())
        out << fmt::format(FMT_STRING("   ccw {:8.1f} {:8.1f}"), p.ccw[k].x_mm, p.ccw[k].y_mm);
      out << "\n";
    }
    out << fmt::format(FMT_STRING("  centre of gravity cw  ({:.1f}, {:.1f}) mm, r = {:.1f} mm\n"),
                       res.x_cg_cw, res.y_cg_cw, res.r_cg_cw);
    out << fmt::format(FMT_STRING("  centre of gravity ccw ({:.1f}, {:.1f}) mm, r = {:.1f} mm\n"),
                       res.x_cg_ccw, res.y_cg_ccw, res.r_cg_ccw);
    out << fmt::format(FMT_STRING("  E_max,syst = {:.1f} mm   SEM = {:.1f} mm   alpha = {:.4f} deg "
                                  "  beta = {:.4f} deg\n"),
                       res.e_max_syst_mm, res.sem_mm, res.alpha_deg, res.beta_deg);
    out << fmt::format(FMT_STRING("  solves to E_d = {:.6f}, E_b = {:.5f}"), res.e_d, res.e_b)
        << (res.second_pass_recommended ? "  (E_max,syst >= 3 SEM: correct again)\n"
                                        : "  (E_max,syst < 3 SEM: no further pass)\n");
  }
  out << "\nResult\n";
  out << fmt::format(FMT_STRING("  E_max,syst {:.1f} mm -> {:.1f} mm: {:.1f}-fold improvement\n"),
                     r.passes.front().result.e_max_syst_mm, r.passes.back().result.e_max_syst_mm,
                     r.improvement_fold);
  out << fmt::format(FMT_STRING("  E_d recovered {:.6f}, true {:.6f} (error {:+.1e})\n"),
                     r.recovered_e_d, r.truth.e_d, r.recovered_e_d - r.truth.e_d);
  out << fmt::format(FMT_STRING("  E_b recovered {:.5f}, true {:.5f} (error {:+.1e})\n"),
                     r.recovered_e_b, r.truth.e_b, r.recovered_e_b - r.truth.e_b);
  out << fmt::format(FMT_STRING("  factors to save: c_l {:.6f}  c_r {:.6f}  wheelbase_mm {:.3f}\n"),
                     r.applied.c_l, r.applied.c_r, r.applied.wheelbase_mm);
  out << fmt::format(FMT_STRING("  simulated {:.0f} s of robot time\n"), r.simulated_s);
  return out.str();
}

std::string umbmark_report_svg(const UmbmarkReport& r) {
  SvgFigure fig;
  if (!r.ok) {
    return fig.finish();
  }
  // Left panel: return position errors before/after with centres of gravity (UMBmark Fig. 6.5).
  SvgPanel& scatter = fig.panel(0, "Return position errors (mm): before and after calibration",
                                "x error, mm", "y error, mm");
  for (std::size_t i = 0; i < r.passes.size(); i += r.passes.size() - 1) {
    const UmbmarkPass& p = r.passes[i];
    const bool before = i == 0;
    for (const auto& e : p.cw)
      scatter.add_marker(e.x_mm, e.y_mm, before ? "#c0392b" : "#2471a3", 'o');
    for (const auto& e : p.ccw)
      scatter.add_marker(e.x_mm, e.y_mm, before ? "#c0392b" : "#2471a3", 's');
    scatter.add_marker(p.result.x_cg_cw, p.result.y_cg_cw, "#000000", '+');
    scatter.add_marker(p.result.x_cg_ccw, p.result.y_cg_ccw, "#000000", 'x');
    if (r.passes.size() == 1)
      break;
  }
  scatter.add_marker(0.0, 0.0, "#888888", '.');
  scatter.legend({{"#c0392b", "before (o cw, square ccw)"},
                  {"#2471a3", "after"},
                  {"#000000", "centres of gravity (+ cw, x ccw)"}});
  // Right panel: driven (true) paths of the first pass and of the last.
  SvgPanel& paths = fig.panel(1, "True paths, before (red) and after (blue)", "x, m", "y, m");
  for (std::size_t i = 0; i < r.passes.size(); i += r.passes.size() - 1) {
    const UmbmarkPass& p = r.passes[i];
    const char* colour = i == 0 ? "#c0392b" : "#2471a3";
    for (const auto& path : p.cw_paths)
      paths.add_line(path, colour);
    for (const auto& path : p.ccw_paths)
      paths.add_line(path, colour);
    if (r.passes.size() == 1)
      break;
  }
  return fig.finish();
}

}  // namespace odocal::host
