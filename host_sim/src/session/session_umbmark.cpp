// `odocal session --procedure umbmark`: the bidirectional square, solved with the core's UMBmark,
// applied on the robot through its own `umbmark add/solve/apply` (so its provenance says
// umbmark), and a second pass when the 3·SEM rule says one would help.

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <stdexcept>

#include "odocal/calib/umbmark.hpp"
#include "odocal/host/calib_json.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

constexpr double pi = 3.14159265358979323846;
/// Two-sided 95 % normal quantile.
constexpr double z95 = 1.959963984540054;

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
                "UMBmark pass %d: %zu cw + %zu ccw runs, L = %.0f mm, b = %.3f mm\n"
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
                pass, runs, runs, side_mm, b_mm, r.x_cg_cw, r.y_cg_cw, r.x_cg_ccw, r.y_cg_ccw,
                r.e_max_syst_mm, r.sigma_mm, r.sem_mm, r.alpha_deg, r.beta_deg, r.e_d,
                range("e_d").c_str(), r.e_b, range("e_b").c_str(), r.c_l, r.c_r,
                range("c_l").c_str(), r.wheelbase_new_mm, range("wheelbase_new_mm").c_str(),
                r.second_pass_recommended ? "recommended (E_max,syst >= 3 SEM)"
                                          : "not expected to help (E_max,syst < 3 SEM)");
  return text;
}

}  // namespace

Outcome run_umbmark(Context& c) {
  const std::size_t n = c.options.runs.value_or(5);
  const double side_m = c.options.side_m.value_or(4.0);
  const double side_mm = side_m * 1000.0;
  c.need_measurements(
      2 * n, "UMBmark (" + std::to_string(n) + " cw + " + std::to_string(n) + " ccw runs)");
  c.planned = 2 * n;
  Outcome outcome;
  nlohmann::json passes = nlohmann::json::array();
  const double expected_s = c.path_seconds(4.0 * side_m, 2.0 * pi, 8);
  char side_text[32];
  std::snprintf(side_text, sizeof side_text, "%.3f", side_m);
  for (int pass = 1; pass <= 2; ++pass) {
    const double b = c.get("wheelbase_mm");
    c.log << "UMBmark pass " << pass << ": " << n << " runs clockwise, then " << n
          << " counter-clockwise, around a " << side_text << " m square.\n"
          << "Place the robot on the start mark, aligned with the first leg, before each run.\n";
    std::vector<calib::ReturnError> errors[2];
    for (int direction = 0; direction < 2; ++direction) {
      const std::string name = direction == 0 ? "cw" : "ccw";
      for (std::size_t i = 0; i < n; ++i) {
        const RunRecord r = c.run(pass == 1 ? name : "pass2-" + name,
                                  "run umbmark-" + name + " " + side_text, expected_s);
        errors[direction].push_back({r.measured.x_mm - r.odom.x_mm, r.measured.y_mm - r.odom.y_mm});
      }
    }
    calib::UmbmarkInput input;
    input.cw = errors[0].data();
    input.cw_count = errors[0].size();
    input.ccw = errors[1].data();
    input.ccw_count = errors[1].size();
    input.side_mm = side_mm;
    input.wheelbase_mm = b;
    calib::UmbmarkResult result;
    const calib::UmbmarkStatus status = calib::solve_umbmark(input, result);
    const std::string prefix = pass == 1 ? "umbmark" : "umbmark_pass2";
    c.write_file(prefix + "_cw.csv", csv_of(errors[0]));
    c.write_file(prefix + "_ccw.csv", csv_of(errors[1]));
    if (status != calib::UmbmarkStatus::ok) {
      throw std::runtime_error(std::string("UMBmark cannot solve these runs: ") +
                               calib::to_string(status) + " (nothing applied)");
    }
    const nlohmann::json ci = intervals(result, side_mm, b);
    Provenance p;
    p.method = "umbmark";
    p.runs = 2 * n;
    p.date = today_utc();
    p.interval = "normal";
    p.level = 0.95;
    p.extra = {{"side_mm", side_mm}, {"wheelbase_mm", b}, {"pass", pass}};
    nlohmann::json object = with_provenance(umbmark_to_json(result), p);
    object["intervals"] = ci;
    passes.push_back(object);
    const std::string text = describe(result, ci, pass, n, side_mm, b);
    c.log << text;
    outcome.text += text;

    // Apply on the robot with its own solver, so `provenance` reads umbmark.
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
    c.robot.expect_ok("umbmark solve");
    const Reply applied = c.robot.expect_ok(
        "umbmark apply " + std::to_string(static_cast<long long>(std::time(nullptr))));
    outcome.applied = true;
    c.log << "Applied on the robot: c_l=" << applied.pairs.at("c_l")
          << " c_r=" << applied.pairs.at("c_r")
          << " wheelbase_mm=" << applied.pairs.at("wheelbase_mm") << "\n";
    if (pass == 2 || !result.second_pass_recommended) {
      break;
    }
    if (c.source.available(c.runs.size()) < 2 * n) {
      c.log << "A second pass is recommended, but the measurement file has no rows for it: "
               "not run.\n";
      outcome.text += "  (second pass recommended but not run: no more measurement rows)\n";
      break;
    }
    c.log << "E_max,syst >= 3 SEM: a second pass with the new factors is expected to help.\n";
    c.planned += 2 * n;
  }
  outcome.result = passes[0];
  outcome.result["passes"] = passes;
  outcome.result["second_pass_run"] = passes.size() > 1;
  return outcome;
}

}  // namespace odocal::host::session
