// runs.svg: where each run stopped, by odometry and as measured, in the start frame.

#include <algorithm>
#include <deque>
#include <map>

#include "odocal/host/svg_plot.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

namespace {

/// Runs drawn in one error panel: UMBmark's passes (cw and ccw together), else one per label.
std::string group_of(const std::string& label) {
  if (label == "cw" || label == "ccw") {
    return "pass 1";
  }
  if (label.rfind("pass", 0) == 0 && label.find('-') != std::string::npos) {
    return "pass " + label.substr(4, label.find('-') - 4);
  }
  return label;
}

}  // namespace

std::vector<std::string> runs_svg_rows(const std::vector<RunRecord>& runs, const std::string& title,
                                       std::size_t columns) {
  static const char* const palette[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd",
                                        "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  std::deque<SvgFigure> rows;
  const auto panel_at = [&rows, columns](std::size_t index, const std::string& name,
                                         const std::string& x_label,
                                         const std::string& y_label) -> SvgPanel& {
    while (rows.size() <= index / columns) {
      rows.emplace_back();
    }
    return rows[index / columns].panel(index % columns, name, x_label, y_label);
  };
  // One panel per group (a UMBmark pass, lateral's lines, verify's before and after): each run's
  // error, measured minus odometry, at the scale of that group's errors, with each label's
  // centre (UMBmark's centres of gravity for cw and ccw). Then, last, where the runs stopped.
  std::vector<std::string> groups;
  for (const RunRecord& r : runs) {
    if (std::find(groups.begin(), groups.end(), group_of(r.label)) == groups.end()) {
      groups.push_back(group_of(r.label));
    }
  }
  std::map<std::string, std::string> colours;
  std::map<std::string, std::pair<PathPoint, int>> sums;
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> legends;
  std::vector<std::pair<std::string, std::string>> all;
  const auto panel_of = [&](const std::string& group) -> SvgPanel& {
    const auto at =
        static_cast<std::size_t>(std::find(groups.begin(), groups.end(), group) - groups.begin());
    return panel_at(at, group + ": measured - odometry (x run, o centre)", "x error, ahead (mm)",
                    "y error, left (mm)");
  };
  // Every panel made before any is filled: the deque keeps references valid, but the stops
  // panel's index must follow the groups'.
  for (const std::string& group : groups) {
    static_cast<void>(panel_of(group));
  }
  SvgPanel& stops = panel_at(groups.size(), title + ": stops (+ odometry, x measured)",
                             "x, ahead (mm)", "y, left (mm)");
  for (const RunRecord& r : runs) {
    if (colours.count(r.label) == 0u) {
      const std::string colour = palette[colours.size() % (sizeof palette / sizeof *palette)];
      colours[r.label] = colour;
      legends[group_of(r.label)].emplace_back(colour, r.label);
      all.emplace_back(colour, r.label);
    }
    const std::string& colour = colours[r.label];
    const double ex = r.measured.x_mm - r.odom.x_mm;
    const double ey = r.measured.y_mm - r.odom.y_mm;
    panel_of(group_of(r.label)).add_marker(ex, ey, colour, 'x');
    auto& sum = sums[r.label];
    sum.first.x_m += ex;
    sum.first.y_m += ey;
    ++sum.second;
    stops.add_line(
        {PathPoint{r.odom.x_mm, r.odom.y_mm}, PathPoint{r.measured.x_mm, r.measured.y_mm}}, colour);
    stops.add_marker(r.odom.x_mm, r.odom.y_mm, colour, '+');
    stops.add_marker(r.measured.x_mm, r.measured.y_mm, colour, 'x');
  }
  for (const auto& [label, sum] : sums) {
    panel_of(group_of(label))
        .add_marker(sum.first.x_m / sum.second, sum.first.y_m / sum.second, colours[label], 'o');
  }
  for (const std::string& group : groups) {
    SvgPanel& panel = panel_of(group);
    panel.add_marker(0.0, 0.0, "#000000", 's');
    auto legend = legends[group];
    legend.emplace_back("#000000", "no error");
    panel.legend(legend);
  }
  stops.add_marker(0.0, 0.0, "#000000", 's');
  all.emplace_back("#000000", "start");
  stops.legend(all);
  std::vector<std::string> out;
  for (const SvgFigure& row : rows) {
    out.push_back(row.finish());
  }
  return out;
}

std::string runs_svg(const std::vector<RunRecord>& runs, const std::string& title) {
  return runs_svg_rows(runs, title, static_cast<std::size_t>(-1)).front();
}

}  // namespace odocal::host::session
