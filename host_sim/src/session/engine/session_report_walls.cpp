// report.html's evidence of `--truth walls` (docs/maze.md): the sensors the robot learnt from the
// start cell, the maze drawn with the place of every look (the stops the walls measured), and
// each run's stop as the walls saw it, beside the simulator's tape when there was one.

#include <algorithm>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

double num(const nlohmann::json& v, const char* key) {
  return v.contains(key) && v[key].is_number() ? v[key].get<double>() : 0.0;
}

/// The maze (north up) and a dot at every look: the runs' stops blue, the moves between grey,
/// the calibration turn's place a black ring.
std::string maze_picture(const nlohmann::json& walls) {
  double width = 180.0;
  double height = 180.0;
  for (const nlohmann::json& s : walls["walls_mm"]) {
    width = std::max({width, s[0].get<double>(), s[2].get<double>()});
    height = std::max({height, s[1].get<double>(), s[3].get<double>()});
  }
  const double scale = 480.0 / std::max(width, height);
  const auto x_of = [&](double x) { return 10.0 + x * scale; };
  const auto y_of = [&](double y) { return 10.0 + (height - y) * scale; };
  std::ostringstream svg;
  svg << fmt::format(
      "<svg viewBox=\"0 0 {0:.0f} {1:.0f}\" width=\"{0:.0f}\" height=\"{1:.0f}\" role=\"img\" "
      "aria-label=\"the maze and where each look found the robot\">\n",
      width * scale + 20.0, height * scale + 20.0);
  for (const nlohmann::json& s : walls["walls_mm"]) {
    svg << fmt::format(
        "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#333\" "
        "stroke-width=\"{:.1f}\"/>\n",
        x_of(s[0].get<double>()), y_of(s[1].get<double>()), x_of(s[2].get<double>()),
        y_of(s[3].get<double>()), std::max(1.5, 12.0 * scale));
  }
  if (walls.contains("calibration")) {
    const nlohmann::json& cal = walls["calibration"];
    svg << fmt::format(
        "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"6\" fill=\"none\" stroke=\"black\"/>\n",
        x_of(num(cal, "centre_x_mm")), y_of(num(cal, "centre_y_mm")));
  }
  for (const nlohmann::json& look : walls["looks"]) {
    svg << fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"2.5\" fill=\"{}\"/>\n",
                       x_of(num(look, "x_mm")), y_of(num(look, "y_mm")),
                       look.contains("run") ? "#1f5fbf" : "#999");
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string sensors_table(const nlohmann::json& cal) {
  static const char* names[] = {"left front", "left diagonal", "right diagonal", "right front"};
  std::ostringstream t;
  t << "<table>\n<tr><th>sensor</th><th>strength a (10<sup>6</sup> counts mm<sup>2</sup>)</th>"
       "<th>incidence power</th></tr>\n";
  std::size_t i = 0;
  for (const nlohmann::json& s : cal["sensors"]) {
    t << fmt::format("<tr><td>{}</td><td>{:.3f}</td><td>{:.3f}</td></tr>\n", names[i++ % 4],
                     num(s, "a_counts_mm2") / 1e6, num(s, "incidence_power"));
  }
  t << "</table>\n";
  t << fmt::format(
      "<p>Learnt from {:.0f} readings of the turn in the start cell (RMS {:.3f} in ln of the "
      "reading). The robot stood at ({:.1f}, {:.1f}) mm facing {:.2f}&deg; (&plusmn;{:.3f}&deg;); "
      "it turns {:.5f} times what its nominal wheelbase says.</p>\n",
      num(cal, "readings"), num(cal, "rms_log_residual"), num(cal, "centre_x_mm"),
      num(cal, "centre_y_mm"), num(cal, "start_heading_deg"), num(cal, "start_heading_sd_deg"),
      num(cal, "true_rad_per_odometry_rad"));
  return t.str();
}

std::string stops_table(const nlohmann::json& walls) {
  std::ostringstream t;
  t << "<table>\n<tr><th>run</th><th>cell</th><th>look's readings</th><th>x (mm)</th>"
       "<th>y (mm)</th><th>heading (&deg;)</th><th>walls &minus; simulator's tape</th></tr>\n";
  for (const nlohmann::json& look : walls["looks"]) {
    if (!look.contains("run")) {
      continue;
    }
    std::string against = "&ndash;";
    if (look.contains("simulator")) {
      const nlohmann::json& s = look["simulator"];
      against = fmt::format("{:+.1f} mm, {:+.1f} mm, {:+.2f}&deg;", num(s, "error_x_mm"),
                            num(s, "error_y_mm"), num(s, "error_theta_deg"));
    }
    t << fmt::format(
        "<tr><td>{}</td><td>({}, {})</td><td>{:.0f}</td><td>{:.1f}</td><td>{:.1f}</td>"
        "<td>{:.2f}</td><td>{}</td></tr>\n",
        look["run"].get<std::size_t>(), look["cell"][0].get<int>(), look["cell"][1].get<int>(),
        num(look, "readings"), num(look, "x_mm"), num(look, "y_mm"), num(look, "theta_deg"),
        against);
  }
  t << "</table>\n";
  return t.str();
}

}  // namespace

std::string walls_section(const nlohmann::json& result) {
  if (!result.is_object() || !result.contains("walls") || !result["walls"].is_object()) {
    return "";
  }
  const nlohmann::json& walls = result["walls"];
  std::ostringstream out;
  const bool taped = result.contains("tape") && result["tape"].is_object();
  out << "<h2>The walls as the tape</h2>\n<p>"
      << (taped ? "The turns in place measured by the walls: the robot learnt its sensors in "
                : "No tape reading: the robot learnt its sensors in ")
      << html_escape(walls.value("maze", std::string("the maze")))
      << "'s start cell, and after every run there it looked round (a turn in place there and "
         "back) and the walls said where it stopped.</p>\n";
  if (taped) {
    out << "<p>A tape measures the rest, on an open floor: "
        << html_escape(result["tape"].value("why", std::string())) << ".</p>\n";
  }
  if (walls.contains("calibration")) {
    out << "<h3>Its sensors, learnt from the start cell</h3>\n"
        << sensors_table(walls["calibration"]);
  }
  if (walls.contains("walls_mm") && walls.contains("looks")) {
    out << "<figure>\n<h3>The maze and every look</h3>\n"
        << maze_picture(walls)
        << "<figcaption>Where each look found the robot (blue: a run's stop; grey: a move between "
           "runs; the ring: the calibration turn).</figcaption>\n</figure>\n";
    out << "<h3>Each run's stop as the walls saw it</h3>\n" << stops_table(walls);
  }
  return out.str();
}

}  // namespace odocal::host::session
