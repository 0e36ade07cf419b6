// runs.svg: where each run stopped, by odometry and as measured, in the start frame.

#include <map>

#include "odocal/host/sim_svg.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

std::string runs_svg(const std::vector<RunRecord>& runs, const std::string& title) {
  static const char* const palette[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd",
                                        "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  SvgFigure figure;
  SvgPanel& panel =
      figure.panel(0, title + ": stop points (x measured, + odometry)", "x (mm)", "y (mm)");
  std::map<std::string, std::string> colours;
  std::vector<std::pair<std::string, std::string>> legend;
  for (const RunRecord& r : runs) {
    if (colours.count(r.label) == 0u) {
      const std::string colour = palette[colours.size() % (sizeof palette / sizeof *palette)];
      colours[r.label] = colour;
      legend.emplace_back(colour, r.label);
    }
    const std::string& colour = colours[r.label];
    panel.add_line(
        {PathPoint{r.odom.x_mm, r.odom.y_mm}, PathPoint{r.measured.x_mm, r.measured.y_mm}}, colour);
    panel.add_marker(r.odom.x_mm, r.odom.y_mm, "#555555", '+');
    panel.add_marker(r.measured.x_mm, r.measured.y_mm, colour, 'x');
  }
  panel.add_marker(0.0, 0.0, "#000000", 's');
  legend.emplace_back("#000000", "start");
  panel.legend(legend);
  return figure.finish();
}

}  // namespace odocal::host::session
