#include "odocal/host/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

namespace odocal::host {
namespace {

constexpr double panel_px = 520.0;
constexpr double margin_px = 60.0;

/// A coordinate in the picture, 0.1 px.
std::string num(double v) {
  return fmt::format("{:.1f}", v);
}

/// An axis label as printf's %g writes it.
std::string label(double v) {
  return fmt::format("{:g}", v);
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) for about 6 ticks over `span`.
double tick_step(double span) {
  const double raw = span / 6.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw) {
      return m * power;
    }
  }
  return 10.0 * power;
}

}  // namespace

void SvgPanel::include(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) {
    return;
  }
  if (empty_) {
    min_x_ = max_x_ = x;
    min_y_ = max_y_ = y;
    empty_ = false;
    return;
  }
  min_x_ = std::min(min_x_, x);
  max_x_ = std::max(max_x_, x);
  min_y_ = std::min(min_y_, y);
  max_y_ = std::max(max_y_, y);
}

void SvgPanel::add_marker(double x, double y, const std::string& colour, char shape) {
  markers_.push_back(Marker{x, y, colour, shape});
  include(x, y);
}

void SvgPanel::add_line(const std::vector<PathPoint>& points, const std::string& colour) {
  lines_.push_back(Line{points, colour});
  for (const PathPoint& p : points) {
    include(p.x_m, p.y_m);
  }
}

std::string SvgPanel::render(double left, double top, double size) const {
  std::ostringstream s;
  const double plot = size - 2.0 * margin_px;
  const double x0 = left + margin_px;
  const double y0 = top + margin_px;
  s << "<text x=\"" << num(left + size / 2) << "\" y=\"" << num(top + 24)
    << "\" text-anchor=\"middle\" font-size=\"14\">" << title_ << "</text>\n";
  s << "<rect x=\"" << num(x0) << "\" y=\"" << num(y0) << "\" width=\"" << num(plot)
    << "\" height=\"" << num(plot) << "\" fill=\"none\" stroke=\"#444\"/>\n";
  if (empty_) {
    return s.str();
  }
  // Equal aspect: one scale for both axes, centred, 5 % padding.
  double span = std::max(max_x_ - min_x_, max_y_ - min_y_);
  if (!(span > 0.0)) {
    span = 1.0;
  }
  span *= 1.1;
  // The legend has a band of its own at the top: no data point under its text.
  const double band = legend_.empty() ? 0.0 : 15.0 * static_cast<double>(legend_.size()) + 10.0;
  const double cx = 0.5 * (min_x_ + max_x_);
  const double cy = 0.5 * (min_y_ + max_y_);
  const double scale = (plot - band) / span;
  // The data span in the lower (plot - band) square; the axes show everything the frame holds.
  const double lo_x = cx - 0.5 * plot / scale;
  const double lo_y = cy - 0.5 * span;
  span = plot / scale;
  auto px = [&](double x) { return x0 + (x - lo_x) * scale; };
  auto py = [&](double y) { return y0 + plot - (y - lo_y) * scale; };
  const double step = tick_step(span);
  for (double t = std::ceil(lo_x / step) * step; t <= lo_x + span; t += step) {
    s << "<line x1=\"" << num(px(t)) << "\" y1=\"" << num(y0) << "\" x2=\"" << num(px(t))
      << "\" y2=\"" << num(y0 + plot) << "\" stroke=\"#eee\"/>\n";
    s << "<text x=\"" << num(px(t)) << "\" y=\"" << num(y0 + plot + 16)
      << "\" text-anchor=\"middle\" font-size=\"11\">"
      << label(std::fabs(t) < step * 1e-6 ? 0.0 : t) << "</text>\n";
  }
  for (double t = std::ceil(lo_y / step) * step; t <= lo_y + span; t += step) {
    s << "<line x1=\"" << num(x0) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(x0 + plot)
      << "\" y2=\"" << num(py(t)) << "\" stroke=\"#eee\"/>\n";
    s << "<text x=\"" << num(x0 - 6) << "\" y=\"" << num(py(t) + 4)
      << "\" text-anchor=\"end\" font-size=\"11\">" << label(std::fabs(t) < step * 1e-6 ? 0.0 : t)
      << "</text>\n";
  }
  s << "<text x=\"" << num(x0 + plot / 2) << "\" y=\"" << num(y0 + plot + 36)
    << "\" text-anchor=\"middle\" font-size=\"12\">" << x_label_ << "</text>\n";
  s << "<text x=\"" << num(left + 16) << "\" y=\"" << num(y0 + plot / 2)
    << "\" text-anchor=\"middle\" font-size=\"12\" transform=\"rotate(-90 " << num(left + 16) << " "
    << num(y0 + plot / 2) << ")\">" << y_label_ << "</text>\n";
  s << "<g class=\"data\">\n";
  for (const Line& line : lines_) {
    s << "<polyline fill=\"none\" stroke=\"" << line.colour
      << "\" stroke-width=\"1\" stroke-opacity=\"0.7\" points=\"";
    for (const PathPoint& p : line.points) {
      s << num(px(p.x_m)) << "," << num(py(p.y_m)) << " ";
    }
    s << "\"/>\n";
  }
  for (const Marker& m : markers_) {
    const double x = px(m.x);
    const double y = py(m.y);
    switch (m.shape) {
      case 's':
        s << "<rect x=\"" << num(x - 4) << "\" y=\"" << num(y - 4)
          << "\" width=\"8\" height=\"8\" fill=\"none\" stroke=\"" << m.colour << "\"/>\n";
        break;
      case '+':
        s << "<path d=\"M" << num(x - 7) << " " << num(y) << "h14M" << num(x) << " " << num(y - 7)
          << "v14\" stroke=\"" << m.colour << "\" stroke-width=\"2\"/>\n";
        break;
      case 'x':
        s << "<path d=\"M" << num(x - 5) << " " << num(y - 5) << "l10 10M" << num(x - 5) << " "
          << num(y + 5) << "l10 -10\" stroke=\"" << m.colour << "\" stroke-width=\"2\"/>\n";
        break;
      case '.':
        s << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"2\" fill=\"" << m.colour
          << "\"/>\n";
        break;
      default:
        s << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y)
          << "\" r=\"4\" fill=\"none\" stroke=\"" << m.colour << "\"/>\n";
        break;
    }
  }
  s << "</g>\n<g class=\"legend\">\n";
  double ly = y0 + 16;
  for (const auto& entry : legend_) {
    s << "<rect x=\"" << num(x0 + 8) << "\" y=\"" << num(ly - 9)
      << "\" width=\"10\" height=\"10\" fill=\"" << entry.first << "\"/>\n";
    s << "<text x=\"" << num(x0 + 24) << "\" y=\"" << num(ly) << "\" font-size=\"11\">"
      << entry.second << "</text>\n";
    ly += 15;
  }
  s << "</g>\n";
  return s.str();
}

SvgPanel& SvgFigure::panel(std::size_t index, const std::string& title, const std::string& x_label,
                           const std::string& y_label) {
  while (panels_.size() <= index) {
    panels_.emplace_back();
  }
  SvgPanel& p = panels_[index];
  p.title_ = title;
  p.x_label_ = x_label;
  p.y_label_ = y_label;
  return p;
}

std::string SvgFigure::finish() const {
  std::ostringstream s;
  const double width = panel_px * static_cast<double>(panels_.empty() ? 1 : panels_.size());
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\""
    << num(panel_px) << "\" font-family=\"sans-serif\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (std::size_t i = 0; i < panels_.size(); ++i) {
    s << panels_[i].render(panel_px * static_cast<double>(i), 0.0, panel_px);
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace odocal::host
