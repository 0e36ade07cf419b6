// report.html's evidence of the readings (DESIGN "Readings judged by all the runs"): every run's
// measured stop beside what all the other runs predict for it (the heading of a turn in place is
// what it shows), those that disagreed marked; and the unseen path before and after.

#include <cmath>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

std::string number(const nlohmann::json& value, int decimals) {
  return value.is_number() ? fmt::format("{:.{}f}", plain(value.get<double>(), decimals), decimals)
                           : std::string("&ndash;");
}

/// One bar per run, its height the distance from the others' prediction in standard deviations,
/// with the line where a run disagrees; bars of runs that disagreed are red.
std::string sigma_bars(const nlohmann::json& checks) {
  constexpr double width = 900.0, height = 180.0, left = 40.0, bottom = 24.0;
  constexpr double limit_sigmas = 5.5;  // about where AgreementOptions' threshold lies
  double top = 2.0 * limit_sigmas;
  for (const nlohmann::json& c : checks) {
    top = std::max(top, c["sigmas"].get<double>());
  }
  const double bar = (width - left) / static_cast<double>(checks.size());
  const auto y_of = [&](double sigmas) {
    return height - bottom - (height - bottom - 8.0) * std::min(sigmas, top) / top;
  };
  std::ostringstream svg;
  svg << fmt::format(
      "<svg viewBox=\"0 0 {0} {1}\" width=\"{0}\" height=\"{1}\" role=\"img\" "
      "aria-label=\"each run's distance from what the others predict\">\n",
      width, height);
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const nlohmann::json& c = checks[i];
    const std::string status = c["status"].get<std::string>();
    const bool off = status == "disagrees" || status == "kept" || status == "left out" ||
                     status == "driven again";
    const double x = left + bar * static_cast<double>(i);
    const double y = y_of(c["sigmas"].get<double>());
    svg << fmt::format(
        "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\"/>"
        "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"11\" text-anchor=\"middle\">{}</text>\n",
        x + 0.15 * bar, y, 0.7 * bar, height - bottom - y, off ? "#d62728" : "#1f77b4",
        x + 0.5 * bar, height - 8.0, c["run"].get<int>());
  }
  svg << fmt::format(
      "<line x1=\"{0}\" x2=\"{1}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#a00\" "
      "stroke-dasharray=\"4 3\"/><text x=\"2\" y=\"{3:.1f}\" font-size=\"11\">{4:.1f} sd</text>"
      "<text x=\"2\" y=\"{5:.1f}\" font-size=\"11\">0</text>\n</svg>\n",
      left, width, y_of(limit_sigmas), y_of(limit_sigmas) + 4.0, limit_sigmas, height - bottom);
  return svg.str();
}

}  // namespace

std::string run_checks_section(const nlohmann::json& result) {
  if (!result.is_object() || !result.contains("run_checks") || !result["run_checks"].is_array() ||
      result["run_checks"].empty()) {
    return std::string();
  }
  const nlohmann::json& checks = result["run_checks"];
  std::ostringstream out;
  out << "<h2>Every run against the others</h2>\n<p>Each run's measured stop beside where all the "
         "other runs, through the fitted model, say it ended (the run itself left out). A reading "
         "far from it, in standard deviations of what the others allow, was asked about "
         "(docs/calibration.md, \"Every run judged by the others\").</p>\n"
      << sigma_bars(checks)
      << "<table class=\"run-checks\">\n<tr><th>run</th><th>kind</th><th>measured x, y "
         "(mm)</th><th>heading (deg)</th><th>the others predict x, y (mm)</th><th>heading "
         "(deg)</th><th>off (mm, deg)</th><th>sd off</th><th>reading</th></tr>\n";
  for (const nlohmann::json& c : checks) {
    const std::string status = c["status"].get<std::string>();
    const bool off = status != "agrees";
    out << fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}, {}</td><td>{}</td><td>{}, {}</td><td>{}</td>"
        "<td>{}, {}</td><td>{:.1f}</td><td>{}</td></tr>\n",
        off ? " class=\"warn\"" : "", c["run"].get<int>(),
        html_escape(c["label"].get<std::string>()), number(c["measured"]["x_mm"], 1),
        number(c["measured"]["y_mm"], 1), number(c["measured"]["theta_deg"], 1),
        number(c["predicted"]["x_mm"], 1), number(c["predicted"]["y_mm"], 1),
        number(c["predicted"]["theta_deg"], 1), number(c["off_mm"], 1), number(c["off_deg"], 1),
        c["sigmas"].get<double>(), html_escape(status));
  }
  out << "</table>\n";
  if (result.contains("disagreeing_runs") && result["disagreeing_runs"].is_array()) {
    for (const nlohmann::json& d : result["disagreeing_runs"]) {
      const std::string choice = d.value("choice", std::string());
      out << "<p class=\"warn\">Run " << d.value("run", 0) << " ("
          << html_escape(d.value("label", std::string())) << ") disagreed with the other runs: "
          << html_escape(choice == "kept"
                             ? "kept as read, against the runs' advice (you confirmed it)"
                             : choice)
          << ".</p>\n";
    }
  }
  return out.str();
}

std::string before_after_line(const nlohmann::json& result) {
  if (!result.is_object() || !result.contains("verify") || !result["verify"].is_object() ||
      !result["verify"].contains("before_rms_mm")) {
    return std::string();
  }
  const nlohmann::json& v = result["verify"];
  return fmt::format(
      "<p class=\"before-after\">The unseen path, before and after: with the factors it had "
      "before the session the robot would have ended about {:.1f} mm RMS from the goal (the "
      "verification runs' counts replayed through them: no extra measurement); with the new "
      "factors it ended {:.1f} mm RMS off.</p>\n",
      v["before_rms_mm"].get<double>(), v["rms_mm"].get<double>());
}

}  // namespace odocal::host::session
