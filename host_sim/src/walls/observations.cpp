// The flat-face model of a wall sensor and the observations (a), (b) and (d)'s geometry: each
// reading inverted through lit = a · cos(φ)^p / d² with the face's place as the unknown.

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "odocal/host/walls.hpp"

namespace odocal::host::walls {

namespace {

// A reading this close to the 12-bit full scale (less a usual ambient) may be clipped.
constexpr double max_usable_lit_counts = 3800.0;

// Where the axis of `mount` meets the face {q : n·q = offset}: distance along the axis, the
// cosine of the incidence and the point; false when it does not meet it ahead.
struct AxisHit {
  double distance_mm = 0.0;
  double cos_incidence = 0.0;
  double x_mm = 0.0;
  double y_mm = 0.0;
};

bool hit_face(const sim::SensorMount& mount, const sim::MazePose& robot, double normal_rad,
              double offset_mm, AxisHit& hit) {
  const double c = std::cos(robot.theta_rad);
  const double s = std::sin(robot.theta_rad);
  const double px = robot.x_mm + c * mount.x_mm - s * mount.y_mm;
  const double py = robot.y_mm + s * mount.x_mm + c * mount.y_mm;
  const double direction = robot.theta_rad + mount.yaw_rad;
  const double nx = std::cos(normal_rad);
  const double ny = std::sin(normal_rad);
  const double cos_incidence = std::cos(direction - normal_rad);
  const double gap = offset_mm - (nx * px + ny * py);
  if (!(cos_incidence > 1e-6) || !(gap > 0.0)) {
    return false;
  }
  hit.distance_mm = gap / cos_incidence;
  hit.cos_incidence = cos_incidence;
  hit.x_mm = px + hit.distance_mm * std::cos(direction);
  hit.y_mm = py + hit.distance_mm * std::sin(direction);
  return true;
}

bool usable(double lit, double min_lit_counts) {
  return std::isfinite(lit) && lit >= min_lit_counts && lit < max_usable_lit_counts;
}

// Gauss-Newton on two unknowns with two residuals (numerical derivatives): true when it
// converged to a point where both residuals are finite.
using TwoResiduals = std::function<bool(double, double, double&, double&)>;

bool solve_two(const TwoResiduals& residuals, double& u, double& v, double step_u, double step_v) {
  for (int iteration = 0; iteration < 30; ++iteration) {
    double r0 = 0.0;
    double r1 = 0.0;
    double ru0 = 0.0;
    double ru1 = 0.0;
    double rv0 = 0.0;
    double rv1 = 0.0;
    if (!residuals(u, v, r0, r1) || !residuals(u + step_u, v, ru0, ru1) ||
        !residuals(u, v + step_v, rv0, rv1)) {
      return false;
    }
    const double j00 = (ru0 - r0) / step_u;
    const double j10 = (ru1 - r1) / step_u;
    const double j01 = (rv0 - r0) / step_v;
    const double j11 = (rv1 - r1) / step_v;
    const double det = j00 * j11 - j01 * j10;
    if (!(std::fabs(det) > 1e-15)) {
      return false;
    }
    const double du = -(j11 * r0 - j01 * r1) / det;
    const double dv = -(-j10 * r0 + j00 * r1) / det;
    // A step no larger than a tenth of a radian in the angle keeps the solution on its branch.
    const double limit = std::fabs(dv) > 0.1 ? 0.1 / std::fabs(dv) : 1.0;
    u += limit * du;
    v += limit * dv;
    if (std::fabs(du) < 1e-3 * step_u && std::fabs(dv) < 1e-3 * step_v) {
      return residuals(u, v, r0, r1);
    }
  }
  return false;
}

// The σ of a front wall's distance and heading: J = d(ln lit)/d(D, ψ) at the solution; each
// reading's own error (noise, own strength) and the shared one (the face, the strengths' common
// part) through J⁻¹.
void front_wall_sd(const TwoResiduals& residuals, const ReadingNoise& noise,
                   const std::array<double, 2>& lit, FrontWall& out) {
  constexpr double step_d = 1e-3;
  constexpr double step_h = 1e-6;
  std::array<double, 2> r{};
  std::array<double, 2> rd{};
  std::array<double, 2> rh{};
  if (!residuals(out.distance_mm, out.heading_rad, r[0], r[1]) ||
      !residuals(out.distance_mm + step_d, out.heading_rad, rd[0], rd[1]) ||
      !residuals(out.distance_mm, out.heading_rad + step_h, rh[0], rh[1])) {
    out.valid = false;
    return;
  }
  const double j00 = (rd[0] - r[0]) / step_d;
  const double j10 = (rd[1] - r[1]) / step_d;
  const double j01 = (rh[0] - r[0]) / step_h;
  const double j11 = (rh[1] - r[1]) / step_h;
  const double det = j00 * j11 - j01 * j10;
  const double own0 = std::hypot(noise.own_strength_relative, noise.sigma_counts / lit[0]);
  const double own1 = std::hypot(noise.own_strength_relative, noise.sigma_counts / lit[1]);
  // A row (w0, w1) of J⁻¹ applied to the two ln errors.
  const auto sd_of = [&](double w0, double w1) {
    return std::sqrt((w0 + w1) * (w0 + w1) * noise.common_relative * noise.common_relative +
                     w0 * w0 * own0 * own0 + w1 * w1 * own1 * own1);
  };
  out.distance_sd_mm = sd_of(j11 / det, -j01 / det);
  out.heading_sd_rad = sd_of(-j10 / det, j00 / det);
}

// A single sensor's distance along its axis from its reading, square on.
double square_on_distance(const SensorResponse& response, double lit) {
  return std::sqrt(response.a_counts_mm2 / lit);
}

}  // namespace

SensorSet usual_mouse_sensors() {
  SensorSet set;
  const sim::WallSensorLayout layout;
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    set.mounts[i] = layout.sensors[i].mount;
  }
  return set;
}

double lit_from_face(const SensorResponse& response, const sim::SensorMount& mount,
                     const sim::MazePose& robot, double normal_rad, double offset_mm) {
  AxisHit hit;
  if (!hit_face(mount, robot, normal_rad, offset_mm, hit)) {
    return 0.0;
  }
  return response.a_counts_mm2 * std::pow(hit.cos_incidence, response.incidence_power) /
         (hit.distance_mm * hit.distance_mm);
}

double point_on_face(const sim::SensorMount& mount, const sim::MazePose& robot, double normal_rad,
                     double offset_mm) {
  AxisHit hit;
  if (!hit_face(mount, robot, normal_rad, offset_mm, hit)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return -std::sin(normal_rad) * hit.x_mm + std::cos(normal_rad) * hit.y_mm;
}

FrontWall observe_front_wall(const SensorSet& sensors, double lit_left_front,
                             double lit_right_front, double min_lit_counts,
                             const ReadingNoise& noise) {
  FrontWall out;
  if (!usable(lit_left_front, min_lit_counts) || !usable(lit_right_front, min_lit_counts)) {
    return out;
  }
  const sim::SensorMount& left = sensors.mounts[left_front];
  const sim::SensorMount& right = sensors.mounts[right_front];
  const double d_left = square_on_distance(sensors.responses[left_front], lit_left_front);
  const double d_right = square_on_distance(sensors.responses[right_front], lit_right_front);
  // Start: each sensor square on; the line through the two points met gives the heading.
  double distance = 0.5 * (d_left + left.x_mm + d_right + right.x_mm);
  double heading = std::atan2(d_left + left.x_mm - d_right - right.x_mm, left.y_mm - right.y_mm);
  const double log_left = std::log(lit_left_front);
  const double log_right = std::log(lit_right_front);
  // The robot at the origin turned by `h`, the face {x = D}.
  const TwoResiduals residuals = [&](double d, double h, double& r0, double& r1) {
    const sim::MazePose robot{0.0, 0.0, h};
    const double model_left = lit_from_face(sensors.responses[left_front], left, robot, 0.0, d);
    const double model_right = lit_from_face(sensors.responses[right_front], right, robot, 0.0, d);
    if (!(model_left > 0.0) || !(model_right > 0.0)) {
      return false;
    }
    r0 = std::log(model_left) - log_left;
    r1 = std::log(model_right) - log_right;
    return true;
  };
  out.valid = solve_two(residuals, distance, heading, 1e-3, 1e-5);
  out.distance_mm = distance;
  out.heading_rad = heading;
  if (out.valid) {
    front_wall_sd(residuals, noise, {lit_left_front, lit_right_front}, out);
  }
  return out;
}

CorridorPose observe_corridor(const SensorSet& sensors, double lit_left_diagonal,
                              double lit_right_diagonal, double heading_rad, double half_width_mm,
                              double min_lit_counts) {
  CorridorPose out;
  out.heading_rad = heading_rad;
  if (!usable(lit_left_diagonal, min_lit_counts) || !usable(lit_right_diagonal, min_lit_counts)) {
    return out;
  }
  constexpr double quarter_turn = 1.5707963267948966;
  const std::array<double, 2> measured{std::log(lit_left_diagonal), std::log(lit_right_diagonal)};
  const std::array<std::size_t, 2> which{left_diagonal, right_diagonal};
  const std::array<double, 2> normal{quarter_turn, -quarter_turn};
  // The corridor along +x, its faces at y = ±half_width; the robot at (0, e) turned by the
  // heading. Least squares in e on the two ln residuals.
  const auto residuals = [&](double e, std::array<double, 2>& r) {
    const sim::MazePose robot{0.0, e, heading_rad};
    for (std::size_t k = 0u; k < 2u; ++k) {
      const double model = lit_from_face(sensors.responses[which[k]], sensors.mounts[which[k]],
                                         robot, normal[k], half_width_mm);
      if (!(model > 0.0)) {
        return false;
      }
      r[k] = std::log(model) - measured[k];
    }
    return true;
  };
  double offset = 0.0;
  std::array<double, 2> r{};
  std::array<double, 2> moved{};
  constexpr double step = 1e-3;
  for (int iteration = 0; iteration < 30; ++iteration) {
    if (!residuals(offset, r) || !residuals(offset + step, moved)) {
      return out;
    }
    const double j0 = (moved[0] - r[0]) / step;
    const double j1 = (moved[1] - r[1]) / step;
    const double change = -(j0 * r[0] + j1 * r[1]) / (j0 * j0 + j1 * j1);
    offset += std::clamp(change, -20.0, 20.0);
    if (std::fabs(change) < 1e-7) {
      out.valid = residuals(offset, r);
      out.offset_mm = offset;
      // The two diagonals' disagreement, in ln: what the walls' differences leave.
      out.mismatch = r[0] - r[1];
      return out;
    }
  }
  return out;
}

double look_ahead_mm(const sim::SensorMount& mount, double offset_mm, double heading_rad,
                     double half_width_mm) {
  constexpr double quarter_turn = 1.5707963267948966;
  const double normal = mount.yaw_rad >= 0.0 ? quarter_turn : -quarter_turn;
  AxisHit hit;
  if (!hit_face(mount, sim::MazePose{0.0, offset_mm, heading_rad}, normal, half_width_mm, hit)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return hit.x_mm;
}

bool on_wall_face(const sim::Maze& maze, const sim::SensorMount& mount,
                  const sim::MazePose& believed, double margin_mm) {
  const double c = std::cos(believed.theta_rad);
  const double s = std::sin(believed.theta_rad);
  const double x = believed.x_mm + c * mount.x_mm - s * mount.y_mm;
  const double y = believed.y_mm + s * mount.x_mm + c * mount.y_mm;
  const double direction = believed.theta_rad + mount.yaw_rad;
  constexpr double look_mm = 400.0;
  const sim::RayHit hit = maze.cast(x, y, direction, look_mm);
  if (hit.kind != sim::SurfaceKind::wall) {
    return false;
  }
  // A wall's face lies half a wall from a grid line across it; along it, the posts take the
  // grid lines ± half a wall. The larger of the two distances to a grid line is the one along.
  const auto from_grid = [](double v) {
    return std::fabs(v - sim::cell_pitch_mm * std::round(v / sim::cell_pitch_mm));
  };
  const double hit_x = x + hit.distance_mm * std::cos(direction);
  const double hit_y = y + hit.distance_mm * std::sin(direction);
  const bool face_along_y = from_grid(hit_x) < from_grid(hit_y);
  const double along = face_along_y ? from_grid(hit_y) : from_grid(hit_x);
  // The wall must border the robot's own cell (not one seen through a gap).
  const double across = face_along_y ? hit_x : hit_y;
  const double own = face_along_y ? believed.x_mm : believed.y_mm;
  const double line = std::round(across / sim::cell_pitch_mm);
  const double cell = std::floor(own / sim::cell_pitch_mm);
  if (line != cell && line != cell + 1.0) {
    return false;
  }
  return along >= sim::wall_thickness_mm / 2.0 + margin_mm;
}

double edge_face_mm(double boundary_mm, bool falling) {
  const double half_post = sim::wall_thickness_mm / 2.0;
  return falling ? boundary_mm + half_post : boundary_mm - half_post;
}

}  // namespace odocal::host::walls
