#pragma once
// Tick logs of a robot of known geometry for the fit tests: whole encoder counts from each wheel's
// ground travel and the pose those counts give by exact arc integration (so the logs fit the
// geometry exactly; tests add their own noise).

#include <cmath>
#include <utility>
#include <vector>

#include "odocal/host/fit.hpp"

namespace odocal::host::synthetic {

inline constexpr double pi = 3.14159265358979323846;

struct Truth {
  double left_mm = 59.9;
  double right_mm = 60.05;
  double wheelbase_mm = 151.5;
  double counts_per_rev = 1440.0;
};

/// One piece of motion: each wheel's ground travel, mm, spread over `steps` rows.
struct Move {
  double left_mm;
  double right_mm;
  int steps;
};

inline Move line(double mm) {
  return Move{mm, mm, static_cast<int>(std::fabs(mm) / 2.0) + 1};
}
inline Move turn(double rad, const Truth& t) {
  const double d = 0.5 * rad * t.wheelbase_mm;
  return Move{-d, d, static_cast<int>(std::fabs(rad) * 100.0) + 1};
}

/// An arc of `length_mm` along the centre on a radius of `radius_mm` (> 0 to the left) for the
/// wheelbase of `t`.
inline Move arc(double length_mm, double radius_mm, const Truth& t) {
  const double half = 0.5 * t.wheelbase_mm / radius_mm;
  return Move{length_mm * (1.0 - half), length_mm * (1.0 + half),
              static_cast<int>(std::fabs(length_mm) / 2.0) + 1};
}

/// Where a log holds ground truth: every row, every third row, the end only (the start at
/// (0, 0, 0), a tape measure), the end's x and y only, or the start and the end (a measured start
/// pose).
enum class Truthing { path, every_third_row, end_only, end_xy_only, start_and_end };

/// A log of a robot of geometry `t`: whole encoder counts (rounded from the wheel travel), and
/// the pose those counts give by exact arc integration (so the data fit `t` exactly).
inline TickLog make_log(const Truth& t, const std::vector<Move>& moves, Truthing truthing,
                        double x0_mm = 0.0, double y0_mm = 0.0, double theta0_deg = 0.0) {
  TickLog log;
  log.source = "synthetic";
  double travel_l = 0.0, travel_r = 0.0;
  std::vector<std::pair<double, double>> counts{{0.0, 0.0}};
  for (const Move& m : moves) {
    for (int i = 0; i < m.steps; ++i) {
      travel_l += m.left_mm / m.steps;
      travel_r += m.right_mm / m.steps;
      counts.emplace_back(std::round(travel_l / (pi * t.left_mm / t.counts_per_rev)),
                          std::round(travel_r / (pi * t.right_mm / t.counts_per_rev)));
    }
  }
  const bool start_known = truthing == Truthing::path || truthing == Truthing::every_third_row ||
                           truthing == Truthing::start_and_end;
  double x = start_known ? x0_mm : 0.0, y = start_known ? y0_mm : 0.0;
  double theta = start_known ? theta0_deg * pi / 180.0 : 0.0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (i > 0) {
      const double dl = (counts[i].first - counts[i - 1].first) * pi * t.left_mm / t.counts_per_rev;
      const double dr =
          (counts[i].second - counts[i - 1].second) * pi * t.right_mm / t.counts_per_rev;
      const double dtheta = (dr - dl) / t.wheelbase_mm;
      const double h = 0.5 * dtheta;
      const double chord = 0.5 * (dl + dr) * (h == 0.0 ? 1.0 : std::sin(h) / h);
      x += chord * std::cos(theta + h);
      y += chord * std::sin(theta + h);
      theta += dtheta;
    }
    TickRow row;
    row.t_s = 0.01 * static_cast<double>(i);
    row.count_l = counts[i].first;
    row.count_r = counts[i].second;
    const bool last = i + 1 == counts.size();
    const bool truth = truthing == Truthing::path || (i == 0 && start_known) ||
                       (truthing == Truthing::every_third_row && i % 3 == 0) ||
                       ((truthing == Truthing::end_only || truthing == Truthing::end_xy_only ||
                         truthing == Truthing::start_and_end) &&
                        last);
    if (truth) {
      row.has_xy = true;
      row.x_mm = x;
      row.y_mm = y;
      row.has_theta = truthing != Truthing::end_xy_only;
      row.theta_deg = theta * 180.0 / pi;  // never wrapped: unwrapped headings must work
    }
    log.rows.push_back(row);
  }
  check_tick_log(log);
  return log;
}

inline std::vector<Move> square(const Truth& t, double side_mm, bool clockwise) {
  std::vector<Move> moves;
  for (int i = 0; i < 4; ++i) {
    moves.push_back(line(side_mm));
    moves.push_back(turn(clockwise ? -pi / 2 : pi / 2, t));
  }
  return moves;
}

}  // namespace odocal::host::synthetic
