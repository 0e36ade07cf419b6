// `odocal session --procedure umbmark`: the bidirectional square, solved with the core's UMBmark,
// applied on the robot through its own `umbmark add/solve/apply` (so its provenance says
// umbmark), and a second pass when the 3·SEM rule says one would help.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "model_in_force.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/host/calib_json.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

using std::numbers::pi;
/// Two-sided 95 % normal quantile.
constexpr double z95 = 1.959963984540054;

/// Largest curve of a leg (beta) or turn error (alpha) the square formulas are trusted with.
constexpr double max_leg_curve_deg = 20.0;

std::string csv_of(const std::vector<calib::ReturnError>& errors) {
  std::ostringstream out;
  out << "# return errors (measured - odometry), mm, start frame\nx_mm,y_mm\n";
  for (const auto& e : errors) {
    char line[96];
    std::snprintf(line, sizeof line, "%.3f,%.3f\n", e.x_mm, e.y_mm);
    out << line;
  }
  return out.str();
}

/// 95 % intervals of E_d, E_b, c_l, c_r and the new wheelbase from the runs' scatter. The
/// centres' per-axis standard error is SEM/√2 (σ is a radial scatter); β and α each average an
/// x- and a y-based estimate, (x_cw ∓ x_ccw)/(−4L), so their standard error is SEM/(√2·4L);
/// E_d ≈ 1 + bβ/L and E_b ≈ 1 + α/(π/2) to first order.
nlohmann::json intervals(const calib::UmbmarkResult& r, double side_mm, double b_mm) {
  const double sd_angle = r.sem_mm / (std::sqrt(2.0) * 4.0 * side_mm);
  const double sd_ed = b_mm * sd_angle / side_mm;
  const double sd_eb = sd_angle * 2.0 / pi;
  const auto span = [](double value, double sd) {
    return nlohmann::json::array({value - z95 * sd, value + z95 * sd});
  };
  return {{"level", 0.95},
          {"method", "normal, first order, from sem_mm"},
          {"e_d", span(r.e_d, sd_ed)},
          {"e_b", span(r.e_b, sd_eb)},
          {"c_l", span(r.c_l, sd_ed / 2.0)},
          {"c_r", span(r.c_r, sd_ed / 2.0)},
          {"wheelbase_new_mm", span(r.wheelbase_new_mm, b_mm * sd_eb)}};
}

std::string describe(const calib::UmbmarkResult& r, const nlohmann::json& ci, int pass,
                     std::size_t runs, double side_mm, double b_mm) {
  const auto range = [&ci](const char* key) {
    char text[96];
    std::snprintf(text, sizeof text, "(95%%: %.6g .. %.6g)", ci[key][0].get<double>(),
                  ci[key][1].get<double>());
    return std::string(text);
  };
  char text[1536];
  std::snprintf(text, sizeof text,
                "UMBmark pass %d: %zu cw + %zu ccw %s, L = %.0f mm, b = %.3f mm\n"
                "  centre cw  x, y   %9.1f %9.1f mm\n"
                "  centre ccw x, y   %9.1f %9.1f mm\n"
                "  E_max,syst        %9.1f mm   (scatter sigma %.1f mm, SEM %.1f mm)\n"
                "  alpha (turns)     %9.4f deg\n"
                "  beta (legs)       %9.4f deg\n"
                "  E_d = D_R/D_L     %.6f %s\n"
                "  E_b               %.6f %s\n"
                "  c_l, c_r          %.6f %.6f %s\n"
                "  new wheelbase     %.3f mm %s\n"
                "  second pass       %s\n",
                pass, runs, runs, runs == 1 ? "run" : "runs", side_mm, b_mm, plain(r.x_cg_cw),
                plain(r.y_cg_cw), plain(r.x_cg_ccw), plain(r.y_cg_ccw), r.e_max_syst_mm, r.sigma_mm,
                r.sem_mm, plain(r.alpha_deg, 4), plain(r.beta_deg, 4), r.e_d, range("e_d").c_str(),
                r.e_b, range("e_b").c_str(), r.c_l, r.c_r, range("c_l").c_str(), r.wheelbase_new_mm,
                range("wheelbase_new_mm").c_str(),
                r.second_pass_recommended ? "recommended (E_max,syst >= 3 SEM)"
                                          : "not expected to help (E_max,syst < 3 SEM)");
  return text;
}

/// One pass solved both ways, and the one the session uses.
struct Solved {
  calib::UmbmarkResult result;                ///< the one used
  std::optional<calib::UmbmarkResult> other;  ///< the other solve, when it has an answer
  std::string reason;                         ///< why this solver
  double model_residual_mm = 0.0;  ///< centres against the exact square model of the result
};

/// The small-angle and the exact solve of one pass; the exact one when asked, or when the two
/// differ by more than the 95 % half-width the measurement scatter gives E_d or E_b.
Solved solve_pass(const std::vector<calib::ReturnError> (&errors)[2], double side_mm, double b_mm,
                  bool force_exact) {
  calib::UmbmarkInput input;
  input.cw = errors[0].data();
  input.cw_count = errors[0].size();
  input.ccw = errors[1].data();
  input.ccw_count = errors[1].size();
  input.side_mm = side_mm;
  input.wheelbase_mm = b_mm;
  calib::UmbmarkResult approx;
  const calib::UmbmarkStatus approx_status = calib::solve_umbmark(input, approx);
  if (approx_status != calib::UmbmarkStatus::ok) {
    throw std::runtime_error(std::string("UMBmark cannot solve these runs: ") +
                             calib::to_string(approx_status) + " (nothing applied)");
  }
  input.exact = true;
  calib::UmbmarkResult exact;
  const bool exact_ok = calib::solve_umbmark(input, exact) == calib::UmbmarkStatus::ok;
  Solved solved;
  if (!exact_ok) {
    solved.result = approx;
    solved.reason = "the exact square solve has no answer for these runs";
    solved.model_residual_mm = std::numeric_limits<double>::infinity();
    return solved;
  }
  const nlohmann::json ci = intervals(approx, side_mm, b_mm);
  const double half_ed = 0.5 * (ci["e_d"][1].get<double>() - ci["e_d"][0].get<double>());
  const double half_eb = 0.5 * (ci["e_b"][1].get<double>() - ci["e_b"][0].get<double>());
  const double off_ed = std::fabs(approx.e_d - exact.e_d);
  const double off_eb = std::fabs(approx.e_b - exact.e_b);
  char why[200];
  if (force_exact) {
    solved.result = exact;
    solved.other = approx;
    solved.reason = "--exact";
  } else if (off_ed > half_ed || off_eb > half_eb) {
    solved.result = exact;
    solved.other = approx;
    std::snprintf(why, sizeof why,
                  "the small-angle formulas are off by %.2g in E_d and %.2g in E_b, more than "
                  "the noise (%.2g, %.2g)",
                  off_ed, off_eb, half_ed, half_eb);
    solved.reason = why;
  } else {
    solved.result = approx;
    solved.other = exact;
    std::snprintf(why, sizeof why,
                  "within the noise of the exact solve (E_d %.2g, E_b %.2g apart; noise %.2g, "
                  "%.2g)",
                  off_ed, off_eb, half_ed, half_eb);
    solved.reason = why;
  }
  // How well the exact square model explains the centres it was solved from.
  const calib::ReturnError cw =
      calib::square_return_error(side_mm, b_mm, exact.e_d, exact.e_b, true);
  const calib::ReturnError ccw =
      calib::square_return_error(side_mm, b_mm, exact.e_d, exact.e_b, false);
  solved.model_residual_mm = std::sqrt(
      0.5 * (std::pow(cw.x_mm - exact.x_cg_cw, 2) + std::pow(cw.y_mm - exact.y_cg_cw, 2) +
             std::pow(ccw.x_mm - exact.x_cg_ccw, 2) + std::pow(ccw.y_mm - exact.y_cg_ccw, 2)));
  return solved;
}

/// Empty when the pass may be applied; otherwise what is wrong and what to do (the ranges and
/// their reasons are in docs/calibration.md, "Plausible results").
std::string implausible(const calib::UmbmarkResult& r, const Solved& solved,
                        const calib::WheelFactors& next, double wheelbase_at_start,
                        double side_mm) {
  char text[400];
  const double beta = std::fabs(r.beta_deg);
  const double alpha = std::fabs(r.alpha_deg);
  // A smaller square that keeps each leg's curve near 5 degrees, in half metres.
  const double worst = std::max(beta, alpha);
  const double smaller_m = std::max(
      0.5, std::floor(side_mm / 1000.0 * std::min(1.0, 5.0 / std::max(worst, 1e-9)) * 2.0) / 2.0);
  if (beta > max_leg_curve_deg || alpha > max_leg_curve_deg || !solved.other) {
    std::snprintf(text, sizeof text,
                  "outside the validity of the square formulas: beta %.1f deg, alpha %.1f deg "
                  "(at most %.0f deg each: the robot must end its square near the start). Use "
                  "a smaller square, e.g. --side-m %.1f, and check the wiring "
                  "(docs/wiring.md).",
                  r.beta_deg, r.alpha_deg, max_leg_curve_deg, smaller_m);
    return text;
  }
  const double residual_limit = std::max(3.0 * r.sem_mm + 2.0, 0.1 * r.e_max_syst_mm);
  if (solved.model_residual_mm > residual_limit) {
    std::snprintf(text, sizeof text,
                  "the runs do not fit the square model: its centres are %.0f mm from what any "
                  "wheel ratio and wheelbase predict (at most %.0f mm). Check the wiring "
                  "(docs/wiring.md), that every run started on the mark, and the measurements; "
                  "or use a smaller square, e.g. --side-m %.1f.",
                  solved.model_residual_mm, residual_limit, smaller_m);
    return text;
  }
  // The one table of plausible results (model_in_force.hpp).
  using namespace plausible;
  const double b_lo = wheelbase_at_start * wheelbase_share[0];
  const double b_hi = wheelbase_at_start * wheelbase_share[1];
  const PlausibleCheck checks[] = {
      {{"E_d", wheel_ratio[0], wheel_ratio[1]}, r.e_d},
      {{"E_b", wheelbase_share[0], wheelbase_share[1]}, r.e_b},
      {{"c_l", wheel_ratio[0], wheel_ratio[1]}, next.c_l},
      {{"c_r", wheel_ratio[0], wheel_ratio[1]}, next.c_r},
      {{"wheelbase_mm", b_lo, b_hi}, next.wheelbase_mm},
  };
  const std::string refusal = first_implausible(checks);
  if (!refusal.empty()) {
    std::snprintf(text, sizeof text,
                  "%s. Check the wiring (docs/wiring.md) and the measurements, or use a smaller "
                  "square, e.g. --side-m %.1f.",
                  refusal.c_str(), smaller_m);
    return text;
  }
  return std::string();
}

/// Drives one pass: `n` clockwise squares, then `n` counter-clockwise; their return errors
/// (measured minus odometry) into errors[0] (cw) and errors[1] (ccw).
void drive_pass(Context& c, std::size_t pass, std::size_t n, double side_m, double expected_s,
                std::vector<calib::ReturnError> (&errors)[2]) {
  for (int direction = 0; direction < 2; ++direction) {
    const std::string name = direction == 0 ? "cw" : "ccw";
    for (std::size_t i = 0; i < n; ++i) {
      const RunRecord r = c.run(pass == 1 ? name : "pass" + std::to_string(pass) + "-" + name,
                                Motion::square(direction == 0, side_m), expected_s);
      errors[direction].push_back({r.measured.x_mm - r.odom.x_mm, r.measured.y_mm - r.odom.y_mm});
    }
  }
}

/// A pass's `result.passes` entry: `odocal umbmark`'s keys with provenance, the intervals and
/// which solver (and why).
nlohmann::json pass_json(const Solved& solved, const nlohmann::json& ci, std::size_t runs_so_far,
                         double side_mm, double b, std::size_t pass) {
  const calib::UmbmarkResult& result = solved.result;
  Provenance p;
  p.method = result.exact ? "umbmark-exact" : "umbmark";
  p.runs = runs_so_far;
  p.date = today_utc();
  p.interval = "normal";
  p.level = 0.95;
  p.extra = {{"side_mm", side_mm}, {"wheelbase_mm", b}, {"pass", pass}};
  nlohmann::json object = with_provenance(umbmark_to_json(result), p);
  object["intervals"] = ci;
  object["solver"] = result.exact ? "exact" : "small-angle";
  object["solver_reason"] = solved.reason;
  return object;
}

/// Applies the pass on the robot with its own solver, so that its provenance reads umbmark (or
/// umbmark-exact) with every run of every pass and the session's date; the robot composes it
/// with the factors in force (`umbmark apply`).
void apply_on_robot(Context& c, const std::vector<calib::ReturnError> (&errors)[2],
                    const char* side_text, bool exact, std::size_t runs_so_far) {
  c.robot.expect_ok("umbmark clear");
  c.robot.expect_ok(std::string("umbmark side ") + side_text);
  for (int direction = 0; direction < 2; ++direction) {
    for (const auto& e : errors[direction]) {
      char line[128];
      std::snprintf(line, sizeof line, "umbmark add %s %.3f %.3f", direction == 0 ? "cw" : "ccw",
                    e.x_mm, e.y_mm);
      c.robot.expect_ok(line);
    }
  }
  c.robot.expect_ok(exact ? "umbmark solve exact" : "umbmark solve");
  const Reply applied = c.robot.expect_ok("umbmark apply " + std::to_string(c.date()) + " " +
                                          std::to_string(runs_so_far));
  c.log << "Applied on the robot: c_l=" << applied.pairs.at("c_l")
        << " c_r=" << applied.pairs.at("c_r")
        << " wheelbase_mm=" << applied.pairs.at("wheelbase_mm") << "\n";
}

}  // namespace

Outcome run_umbmark(Context& c) {
  const std::size_t n = c.options.runs.value_or(5);
  const double side_m = c.options.side_m.value_or(4.0);
  const double side_mm = side_m * 1000.0;
  const std::size_t max_passes = c.options.passes;
  c.need_measurements(
      2 * n, "UMBmark (" + std::to_string(n) + " cw + " + std::to_string(n) + " ccw runs)");
  c.planned = 2 * n;
  Outcome outcome;
  nlohmann::json passes = nlohmann::json::array();
  const double expected_s = c.path_seconds(4.0 * side_m, 2.0 * pi, 8);
  const double wheelbase_at_start = c.initial.wheelbase_mm;
  char side_text[32];
  std::snprintf(side_text, sizeof side_text, "%.3f", side_m);
  for (std::size_t pass = 1; pass <= max_passes; ++pass) {
    const double b = c.get(ParamId::wheelbase_mm);
    c.log << "UMBmark pass " << pass << ": " << count_of(n, "run", "runs") << " clockwise, then "
          << n << " counter-clockwise, around a " << side_text << " m square.\n"
          << "Place the robot on the start mark, aligned with the first leg, before each run.\n";
    std::vector<calib::ReturnError> errors[2];
    drive_pass(c, pass, n, side_m, expected_s, errors);
    const std::string prefix = pass == 1 ? "umbmark" : "umbmark_pass" + std::to_string(pass);
    c.write_file(prefix + "_cw.csv", csv_of(errors[0]));
    c.write_file(prefix + "_ccw.csv", csv_of(errors[1]));
    const Solved solved = solve_pass(errors, side_mm, b, c.options.exact.value_or(false));
    const calib::UmbmarkResult& result = solved.result;
    const nlohmann::json ci = intervals(result, side_mm, b);
    const std::size_t runs_so_far = 2 * n * pass;
    nlohmann::json object = pass_json(solved, ci, runs_so_far, side_mm, b, pass);
    const std::string text = describe(result, ci, static_cast<int>(pass), n, side_mm, b) +
                             "  solver            " + object["solver"].get<std::string>() + " (" +
                             solved.reason + ")\n";
    c.log << text;
    outcome.text += text;
    // Plausible or refused: nothing is applied from a pass outside the formulas' validity or
    // outside what a real robot can be (docs/calibration.md, "Plausible results").
    const calib::WheelFactors next =
        calib::compose(calib::WheelFactors{c.get(ParamId::c_l), c.get(ParamId::c_r), b}, result);
    const std::string refusal = implausible(result, solved, next, wheelbase_at_start, side_mm);
    object["plausible"] = refusal.empty();
    passes.push_back(object);
    c.partial = passes[0];
    c.partial["passes"] = passes;
    if (!refusal.empty()) {
      throw std::runtime_error("UMBmark pass " + std::to_string(pass) + ": " + refusal +
                               " Nothing from this session stays applied.");
    }

    apply_on_robot(c, errors, side_text, result.exact, runs_so_far);
    outcome.applied = true;
    if (!result.second_pass_recommended) {
      c.log << "E_max,syst < 3 SEM: another pass is not expected to help; done.\n";
      break;
    }
    if (pass == max_passes) {
      c.log << "E_max,syst >= 3 SEM, but this was pass " << pass << " of at most " << max_passes
            << " (--passes): stopping here.\n";
      outcome.text +=
          "  (another pass recommended; --passes " + std::to_string(max_passes) + " reached)\n";
      break;
    }
    if (c.source.available(c.runs.size()) < 2 * n) {
      c.log << "Another pass is recommended, but the measurement file has no rows for it: "
               "not run.\n";
      outcome.text += "  (another pass recommended but not run: no more measurement rows)\n";
      break;
    }
    c.log << "E_max,syst >= 3 SEM: pass " << pass + 1 << " with the new factors is expected to "
          << "help.\n";
    c.planned += 2 * n;
  }
  outcome.result = passes[0];
  outcome.result["passes"] = passes;
  outcome.result["second_pass_run"] = passes.size() > 1;
  outcome.result["solver"] = passes.back()["solver"];
  return outcome;
}

}  // namespace odocal::host::session
