// OUT/report.html: one self-contained page (inline SVG, no script, nothing from the network) that
// shows what a session did and found (DESIGN "One command, fewest measurements").

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <deque>
#include <map>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/host/path_geometry.hpp"
#include "odocal/host/svg_plot.hpp"
#include "reading_check.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

std::string html_escape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

namespace {

constexpr double kPi = std::numbers::pi;
const char* const kPalette[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd",
                                "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

std::string escape(const std::string& text) {
  return html_escape(text);
}

/// An SvgFigure as an inline element that scales to the page (viewBox) and needs no namespace.
/// `min_width`: the viewBox is at least this wide (a row of fewer panels keeps the scale of a
/// full row, left-aligned).
std::string inline_svg(std::string svg, const std::string& label, double min_width = 1560.0) {
  const std::string head = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"";
  if (svg.rfind(head, 0) == 0) {
    const std::size_t w_end = svg.find('"', head.size());
    const std::string width = fmt::format(
        "{:.0f}", std::max(min_width, std::stod(svg.substr(head.size(), w_end - head.size()))));
    const std::string h_key = "height=\"";
    const std::size_t h_at = svg.find(h_key, w_end) + h_key.size();
    const std::string height = svg.substr(h_at, svg.find('"', h_at) - h_at);
    svg = fmt::format(
              "<svg role=\"img\" aria-label=\"{}\" viewBox=\"0 0 {} {}\" width=\"{}\" "
              "height=\"{}\"",
              escape(label), width, height, width, height) +
          svg.substr(svg.find('"', h_at) + 1);
  }
  return svg;
}

/// Poses along a run from its tick log, integrated with the geometry (D_L, D_R, b, b_arc; mm) by
/// the one model's exact arcs (drive::model::advance), the wheelbase in force per row.
std::vector<PathPoint> trace_of(const RunRecord& r, double d_l, double d_r, double b, double cpr,
                                double b_arc = 0.0) {
  std::vector<PathPoint> out;
  drive::model::PoseOf<double> pose;
  out.push_back(PathPoint{0.0, 0.0});
  for (std::size_t i = 1; i < r.ticks.size(); ++i) {
    // In doubles: counts read back from a file may lie further apart than 64 bits can subtract.
    const double count_l =
        static_cast<double>(r.ticks[i].count_l) - static_cast<double>(r.ticks[i - 1].count_l);
    const double count_r =
        static_cast<double>(r.ticks[i].count_r) - static_cast<double>(r.ticks[i - 1].count_r);
    drive::model::advance(pose, count_l * kPi * d_l / cpr, count_r * kPi * d_r / cpr,
                          drive::model::wheelbase_for(b, b_arc, count_l, count_r));
    out.push_back(PathPoint{pose.x, pose.y});
  }
  return out;
}

/// The path a run was told to drive, from its command (runs without a tick log), in mm: the one
/// path of its motion (Motion::path); none for the self-test's wheel drives.
std::vector<PathPoint> commanded_path(const RunRecord& r) {
  const drive::Path path = r.motion.path().value_or(drive::Path{});
  std::vector<PathPoint> out{PathPoint{0.0, 0.0}};
  drive::model::PoseOf<double> pose;
  for (std::uint8_t i = 0; i < path.count; ++i) {
    const double d = static_cast<double>(path.segments[i].distance_m) * 1e3;
    const double a = static_cast<double>(path.segments[i].angle_rad);
    // Arcs in 24 pieces, so that the drawn polyline follows the curve.
    const int steps = a == 0.0 || d == 0.0 ? 1 : 24;
    for (int k = 0; k < steps; ++k) {
      drive::model::advance_arc(pose, d / steps, a / steps);
      out.push_back(PathPoint{pose.x, pose.y});
    }
  }
  return out;
}

/// Panels laid out three to a row: one SvgFigure per row.
class Rows {
 public:
  SvgPanel& panel(const std::string& title, const std::string& x_label,
                  const std::string& y_label) {
    if (count_ % 3 == 0) {
      rows_.emplace_back();
    }
    return rows_.back().panel(count_++ % 3, title, x_label, y_label);
  }
  [[nodiscard]] std::string html(const std::string& label) const {
    std::string out;
    for (const SvgFigure& f : rows_) {
      out += inline_svg(f.finish(), label);
    }
    return out;
  }
  [[nodiscard]] bool empty() const { return count_ == 0; }

 private:
  std::deque<SvgFigure> rows_;
  std::size_t count_ = 0;
};

std::string figure(const std::string& title, const std::string& svg, const std::string& caption) {
  return "<figure>\n<h2>" + escape(title) + "</h2>\n" + svg + "<figcaption>" + escape(caption) +
         "</figcaption>\n</figure>\n";
}

/// [lo, hi] of `name` in a fit result's `ci`, if there.
std::string interval(const nlohmann::json& fit, const std::string& name) {
  if (!fit.is_object() || !fit.contains("ci") || !fit["ci"].contains(name) ||
      !fit["ci"][name].is_array() || fit["ci"][name].size() != 2) {
    return "";
  }
  const auto& ci = fit["ci"][name];
  return fmt::format("[{:.6g}, {:.6g}]", ci[0].get<double>(), ci[1].get<double>());
}

std::string date_text(std::uint64_t unix_s) {
  if (unix_s == 0) {
    return "unknown";
  }
  const auto t = static_cast<std::time_t>(unix_s);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[40];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &utc);
  return text;
}

/// What every section of the page shares: the runs' labels in order and a colour for each,
/// and the fitted geometry where the session fitted one (fit, auto).
struct ReportParts {
  std::vector<std::string> labels;
  std::map<std::string, std::string> colours;
  const nlohmann::json* fit = nullptr;
};

ReportParts parts_of(const ReportInput& in) {
  ReportParts p;
  for (const RunRecord& r : in.runs) {
    if (p.colours.count(r.label) == 0u) {
      p.colours[r.label] = kPalette[p.colours.size() % (sizeof kPalette / sizeof *kPalette)];
      p.labels.push_back(r.label);
    }
  }
  if (in.result.contains("wheel_diameter_left_mm")) {
    p.fit = &in.result;
  } else if (in.result.contains("fit") && in.result["fit"].is_object()) {
    p.fit = &in.result["fit"];
  }
  return p;
}

/// 1. Each run's path: the odometry (from the tick log, or the path the run was told to drive)
///    and where it stopped by odometry (+) and as measured (x).
std::string paths_figure(const ReportInput& in, ReportParts& p) {
  const std::vector<RunRecord>& runs = in.runs;
  Rows paths;
  for (const std::string& label : p.labels) {
    SvgPanel& panel =
        paths.panel(label + ": path (+ odometry end, x measured)", "x, ahead (mm)", "y, left (mm)");
    const std::string& colour = p.colours[label];
    std::size_t n = 0;
    for (const RunRecord& r : runs) {
      if (r.label != label) {
        continue;
      }
      ++n;
      const std::vector<PathPoint> trace =
          r.ticks.size() >= 2 ? trace_of(r, in.wheel_diameter_mm, in.wheel_diameter_mm,
                                         in.wheelbase_mm, in.counts_per_rev)
                              : commanded_path(r);
      panel.add_line(trace, "#999999");
      panel.add_marker(r.odom.x_mm, r.odom.y_mm, colour, '+');
      panel.add_marker(r.measured.x_mm, r.measured.y_mm, colour, 'x');
    }
    panel.add_marker(0.0, 0.0, "#000000", 's');
    panel.legend({{"#999999", "odometry path"},
                  {colour, fmt::format("{} ({}): + odometry end, x measured", label, n)},
                  {"#000000", "start"}});
  }
  if (paths.empty()) {
    return std::string();
  }
  return figure("Each run's path and stop point", paths.html("paths"),
                "Grey: the path by odometry (tick log, or the path the run was told to drive); "
                "+ where odometry says it stopped; x where it was measured; square: the start "
                "mark. Axes in millimetres from the start mark, x ahead, y to the left.");
}

/// 2. Errors per group at their own scale: UMBmark's clusters with their centres of gravity
///    before and after each pass, lateral drift, verification (runs.svg).
std::string errors_figure(const ReportInput& in) {
  std::string errors;
  for (const std::string& svg : runs_svg_rows(in.runs, in.title, 3)) {
    errors += inline_svg(svg, "errors");
  }
  return figure("Stop errors, measured minus odometry, per pass and group", errors,
                "Each panel at the scale of its own errors, so that millimetres show: x a run's "
                "error, o the centre of gravity of its kind (UMBmark: cw and ccw clusters of a "
                "pass; the next pass shows them after the correction), square: no error.");
}

/// 3. Fit: the logged runs' paths with the nominal geometry (before) and the fitted one (after).
std::string fit_figure(const ReportInput& in, ReportParts& p) {
  if (p.fit == nullptr) {
    return std::string();
  }
  const nlohmann::json& fit = *p.fit;
  const double d_l = fit["wheel_diameter_left_mm"].get<double>();
  const double d_r = fit["wheel_diameter_right_mm"].get<double>();
  const double b = fit["wheelbase_mm"].get<double>();
  const double b_arc = fit.contains("wheelbase_arc_mm") && fit["wheelbase_arc_mm"].is_number()
                           ? fit["wheelbase_arc_mm"].get<double>()
                           : 0.0;
  Rows fitted;
  for (const std::string& label : p.labels) {
    bool any = false;
    for (const RunRecord& r : in.runs) {
      any = any || (r.label == label && r.ticks.size() >= 2);
    }
    if (!any) {
      continue;
    }
    SvgPanel& panel =
        fitted.panel(label + ": before and after the fit", "x, ahead (mm)", "y, left (mm)");
    for (const RunRecord& r : in.runs) {
      if (r.label != label || r.ticks.size() < 2) {
        continue;
      }
      panel.add_line(trace_of(r, in.wheel_diameter_mm, in.wheel_diameter_mm, in.wheelbase_mm,
                              in.counts_per_rev),
                     "#bbbbbb");
      const std::vector<PathPoint> after = trace_of(r, d_l, d_r, b, in.counts_per_rev, b_arc);
      panel.add_line(after, p.colours[label]);
      panel.add_marker(r.measured.x_mm, r.measured.y_mm, "#000000", 'x');
    }
    panel.legend({{"#bbbbbb", "nominal geometry (before)"},
                  {p.colours[label], "fitted geometry (after)"},
                  {"#000000", "x measured stop"}});
  }
  if (fitted.empty()) {
    return std::string();
  }
  return figure("Fit: paths before and after", fitted.html("fit"),
                fmt::format("The runs' encoder counts integrated with the nominal geometry "
                            "(grey) and with the fitted one (D_L {:.3f} mm, D_R {:.3f} mm, "
                            "b {:.3f} mm): after the fit each path should end at its "
                            "measured stop (x). Millimetres.",
                            d_l, d_r, b));
}

/// 4. Verification: the unseen path's target and where the runs stopped.
std::string verify_figure(const ReportInput& in, ReportParts& p) {
  const PathEnd goal = path_end(drive::make_unseen_path());
  Rows verify;
  SvgPanel* target = nullptr;
  std::vector<std::pair<std::string, std::string>> verify_legend;
  for (const std::string& label : p.labels) {
    for (const RunRecord& r : in.runs) {
      if (r.label != label || r.motion != Motion::unseen()) {
        continue;
      }
      if (target == nullptr) {
        target = &verify.panel("unseen path: stops around the target", "x error, ahead (mm)",
                               "y error, left (mm)");
      }
      target->add_marker(r.measured.x_mm - goal.x_m * 1e3, r.measured.y_mm - goal.y_m * 1e3,
                         p.colours[label], 'x');
      const std::string entry = label + ": x measured stop";
      if (std::find_if(verify_legend.begin(), verify_legend.end(),
                       [&](const auto& e) { return e.second == entry; }) == verify_legend.end()) {
        verify_legend.emplace_back(p.colours[label], entry);
      }
    }
  }
  if (target == nullptr) {
    return std::string();
  }
  target->add_marker(0.0, 0.0, "#000000", 's');
  verify_legend.emplace_back("#000000", "target (where the path should end)");
  target->legend(verify_legend);
  return figure("Verification on the unseen path", verify.html("verification"),
                fmt::format("The unseen path (100 cm square, 100 cm triangle, 80 cm "
                            "semicircle) should end {:.0f} mm ahead and {:.0f} mm to the left "
                            "of the start: each x is a measured stop minus that target, in "
                            "millimetres.",
                            plain(goal.x_m * 1e3, 0), plain(goal.y_m * 1e3, 0)));
}

/// "METHOD, N runs, DATE" of a factor group's provenance (`wheel`, `lateral`).
std::string provenance_text(const ReportInput& in, const char* group) {
  const auto get = [&](const std::string& key) {
    const auto at = in.provenance.find(std::string(group) + "_" + key);
    return at == in.provenance.end() ? std::string("?") : at->second;
  };
  if (in.provenance.empty()) {
    return std::string("not reported");
  }
  const std::string date = get("date");
  const bool digits =
      !date.empty() && date.size() < 20 &&
      std::all_of(date.begin(), date.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
  return fmt::format("{}, {} runs, {}", get("method"), get("runs"),
                     digits ? date_text(std::stoull(date)) : std::string("unknown"));
}

/// The intervals of the factors in force: the fit's for the geometry; UMBmark's last pass's
/// correction (the factor in force when the robot started from the nominal factors, composed
/// with them otherwise); the lateral bootstrap's for F_lat, F_lon. `note` says which.
struct FactorIntervals {
  nlohmann::json wheel;
  nlohmann::json lateral;
  std::string note;
};

FactorIntervals intervals_of(const ReportInput& in, const nlohmann::json* fit) {
  nlohmann::json wheel_ci = nlohmann::json::object();
  FactorIntervals out;
  if (fit != nullptr && fit->contains("ci")) {
    wheel_ci = (*fit)["ci"];
  } else if (in.result.contains("passes") && in.result["passes"].is_array() &&
             !in.result["passes"].empty() && in.result["passes"].back().contains("intervals")) {
    const nlohmann::json& last = in.result["passes"].back()["intervals"];
    wheel_ci["c_l"] = last.value("c_l", nlohmann::json());
    wheel_ci["c_r"] = last.value("c_r", nlohmann::json());
    wheel_ci["wheelbase_mm"] = last.value("wheelbase_new_mm", nlohmann::json());
    out.note = "UMBmark's intervals are those of its last pass's correction.";
  }
  nlohmann::json lateral_ci = nlohmann::json::object();
  if (in.result.contains("bootstrap") && in.result["bootstrap"].is_object()) {
    lateral_ci["f_lat"] = in.result["bootstrap"].value("ci_f_lat", nlohmann::json());
    lateral_ci["f_lon"] = in.result["bootstrap"].value("ci_f_lon", nlohmann::json());
  }
  out.wheel = nlohmann::json{{"ci", wheel_ci}};
  out.lateral = nlohmann::json{{"ci", lateral_ci}};
  return out;
}

/// 5. The factors in force, with intervals and provenance.
std::string factors_table(const ReportInput& in, const nlohmann::json* fit) {
  std::ostringstream table;
  table << "<table>\n<tr><th>factor</th><th>in force</th><th>95 % interval</th>"
           "<th>provenance</th></tr>\n";
  const auto row = [&](const char* name, double value, const std::string& ci, const char* group) {
    table << fmt::format("<tr><td>{}</td><td>{:.6f}</td><td>{}</td><td>{}</td></tr>\n", name, value,
                         ci.empty() ? "&ndash;" : ci, escape(provenance_text(in, group)));
  };
  const FactorIntervals ci = intervals_of(in, fit);
  row("c_l", in.factors.c_l, interval(ci.wheel, "c_l"), "wheel");
  row("c_r", in.factors.c_r, interval(ci.wheel, "c_r"), "wheel");
  row("wheelbase_mm", in.factors.wheelbase_mm, interval(ci.wheel, "wheelbase_mm"), "wheel");
  if (in.factors.wheelbase_arc_mm != 0.0) {
    row("wheelbase_arc_mm", in.factors.wheelbase_arc_mm, interval(ci.wheel, "wheelbase_arc_mm"),
        "wheel");
  }
  row("f_lat", in.factors.f_lat, interval(ci.lateral, "f_lat"), "lateral");
  row("f_lon", in.factors.f_lon, interval(ci.lateral, "f_lon"), "lateral");
  table << "</table>\n";
  if (!ci.note.empty()) {
    table << "<p>" << escape(ci.note) << "</p>\n";
  }
  if (fit != nullptr && fit->is_object() && fit->contains("noise") && (*fit)["noise"].is_object() &&
      (*fit)["noise"].contains("k_l")) {
    // A k estimated at 0 is not resolved by the runs, not a wheel that never slips: its upper end.
    const nlohmann::json& noise = (*fit)["noise"];
    const auto k_text = [&noise](const char* name) {
      const double k = noise[name].get<double>();
      if (k > 0.0) {
        return fmt::format("{} = {:.3g} mm&sup2;/mm", name, k);
      }
      const bool has_ci = noise.contains("ci") && noise["ci"].contains(name) &&
                          noise["ci"][name].is_array() && noise["ci"][name].size() == 2u;
      return has_ci ? fmt::format("{} not resolved by the runs (at most {:.3g} mm&sup2;/mm)", name,
                                  noise["ci"][name][1].get<double>())
                    : fmt::format("{} not resolved by the runs", name);
    };
    table << "<p>Random error growth (odometry covariance, Chong &amp; Kleeman): " << k_text("k_l")
          << ", " << k_text("k_r") << ".</p>\n";
  }
  return table.str();
}

}  // namespace

std::string report_html(const ReportInput& in) {
  ReportParts p = parts_of(in);
  std::ostringstream body;
  body << walls_section(in.result) << run_checks_section(in.result) << paths_figure(in, p)
       << errors_figure(in) << fit_figure(in, p) << verify_figure(in, p)
       << before_after_line(in.result);
  const std::string table = factors_table(in, p.fit);
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<title>"
       << escape(in.title)
       << "</title>\n<style>\n"
          "body{font-family:sans-serif;max-width:1600px;margin:1em auto;padding:0 1em;"
          "color:#222}\n"
          "svg{max-width:100%;height:auto;display:block;margin:0.5em 0}\n"
          "figure{margin:1.5em 0}figcaption{color:#555;font-size:0.9em;max-width:60em}\n"
          "pre{white-space:pre-wrap}table{border-collapse:collapse}td,th{border:1px solid "
          "#ccc;padding:0.3em 0.6em;"
          "text-align:left}\n.warn{color:#a00}\n</style>\n</head>\n<body>\n<h1>"
       << escape(in.title) << "</h1>\n<p>" << escape(date_text(in.date_unix_s)) << " &middot; "
       << (in.result.is_object() && in.result.value("truth", std::string()) == "walls"
               ? std::to_string(in.runs.size()) +
                     (in.tape_readings == 0
                          ? std::string(" runs measured by the walls, no tape reading")
                          : " runs: the turns in the maze measured by the walls, " +
                                std::to_string(in.tape_readings) + " tape reading" +
                                (in.tape_readings == 1 ? "" : "s") + " on the floor")
               : std::to_string(in.runs.size()) +
                     (in.runs.size() == 1 ? " measurement" : " measurements"))
       << " &middot; "
       << (in.complete ? "complete"
                       : "<span class=\"warn\">interrupted: " + escape(in.interruption) + "</span>")
       << (in.saved ? " &middot; saved on the robot" : "") << "</p>\n";
  page << "<h2>Factors in force</h2>\n" << table << body.str();
  if (!in.summary.empty()) {  // what the console said, last: the pictures come first
    page << "<h2>What the session printed</h2>\n<pre>" << escape(in.summary) << "</pre>\n";
  }
  page << "</body>\n</html>\n";
  return page.str();
}

}  // namespace odocal::host::session
