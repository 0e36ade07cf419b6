#pragma once
/// @file
/// A minimal SVG plotter for the `--svg` pictures of `odocal sim` and the session's report.html:
/// side-by-side panels with equal-aspect axes, markers, polylines and a legend. No dependencies.

#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "odocal/host/path_geometry.hpp"

namespace odocal::host {

/// One plot area. Data units are whatever the caller uses (mm, m); x and y share one scale.
class SvgPanel {
 public:
  /// A marker: 'o' circle, 's' square, '+' and 'x' crosses, '.' small dot.
  void add_marker(double x, double y, const std::string& colour, char shape);
  /// A polyline through the points.
  void add_line(const std::vector<PathPoint>& points, const std::string& colour);
  /// Legend entries (colour, text), drawn in the top-left corner.
  void legend(std::vector<std::pair<std::string, std::string>> entries) {
    legend_ = std::move(entries);
  }

 private:
  friend class SvgFigure;
  struct Marker {
    double x, y;
    std::string colour;
    char shape;
  };
  struct Line {
    std::vector<PathPoint> points;
    std::string colour;
  };
  void include(double x, double y);
  std::string render(double left_px, double top_px, double size_px) const;

  std::string title_;
  std::string x_label_;
  std::string y_label_;
  std::vector<Marker> markers_;
  std::vector<Line> lines_;
  std::vector<std::pair<std::string, std::string>> legend_;
  double min_x_ = 0.0, max_x_ = 0.0, min_y_ = 0.0, max_y_ = 0.0;
  bool empty_ = true;
};

/// A row of square panels.
class SvgFigure {
 public:
  /// The panel at column `index` (created on first use; references stay valid).
  SvgPanel& panel(std::size_t index, const std::string& title, const std::string& x_label,
                  const std::string& y_label);
  /// The whole SVG document.
  [[nodiscard]] std::string finish() const;

 private:
  std::deque<SvgPanel> panels_;
};

}  // namespace odocal::host
