#include "odocal/sim/maze.hpp"

#include <cmath>
#include <limits>

namespace odocal::sim {

namespace {

constexpr double half_wall_mm = wall_thickness_mm / 2.0;
constexpr double no_hit = std::numeric_limits<double>::infinity();

// Surface names: one number per wall or post, independent of the maze's size.
constexpr std::uint32_t horizontal_wall_id(std::uint32_t line, std::uint32_t column) {
  return (line * 64u + column) * 4u + 0u;
}
constexpr std::uint32_t vertical_wall_id(std::uint32_t line, std::uint32_t row) {
  return (row * 64u + line) * 4u + 1u;
}
constexpr std::uint32_t post_id(std::uint32_t line_x, std::uint32_t line_y) {
  return (line_y * 64u + line_x) * 4u + 2u;
}

constexpr std::uint64_t bit(std::uint32_t index) {
  return std::uint64_t{1u} << index;
}

}  // namespace

/// A ray in the maze frame (unit direction).
struct Maze::Candidate {
  double x_mm;
  double y_mm;
  double dx;
  double dy;

  /// The ray against the rectangle [x0, x1] x [y0, y1] (slab test): keeps the nearer hit in `best`.
  void against(double x0, double x1, double y0, double y1, SurfaceKind kind, std::uint32_t id,
               RayHit& best) const {
    double t_near = -no_hit;
    double t_far = no_hit;
    bool x_face = true;
    if (!slab(x_mm, dx, x0, x1, t_near, t_far, x_face, true) ||
        !slab(y_mm, dy, y0, y1, t_near, t_far, x_face, false) || t_near > t_far || t_far < 0.0) {
      return;
    }
    const double t = t_near > 0.0 ? t_near : 0.0;
    if (best.kind != SurfaceKind::none && t >= best.distance_mm) {
      return;
    }
    best.kind = kind;
    best.distance_mm = t;
    best.surface = id;
    // The face's normal is the x axis (a face at x = const) or the y axis.
    best.incidence_rad = x_face ? std::atan2(std::fabs(dy), std::fabs(dx))
                                : std::atan2(std::fabs(dx), std::fabs(dy));
  }

  /// One axis of the slab test; `x_face` records which axis the entry happened on last.
  static bool slab(double origin, double direction, double lo, double hi, double& t_near,
                   double& t_far, bool& x_face, bool this_is_x) {
    if (direction == 0.0) {
      return origin >= lo && origin <= hi;
    }
    double t1 = (lo - origin) / direction;
    double t2 = (hi - origin) / direction;
    if (t1 > t2) {
      const double swap = t1;
      t1 = t2;
      t2 = swap;
    }
    if (t1 > t_near) {
      t_near = t1;
      x_face = this_is_x;
    }
    if (t2 < t_far) {
      t_far = t2;
    }
    return true;
  }
};

Maze::Maze(std::uint32_t width, std::uint32_t height)
    : width_(width < 1u ? 1u : (width > max_maze_cells ? max_maze_cells : width)),
      height_(height < 1u ? 1u : (height > max_maze_cells ? max_maze_cells : height)) {
  for (std::uint32_t c = 0u; c < width_; ++c) {
    horizontal_[0] |= bit(c);
    horizontal_[height_] |= bit(c);
  }
  for (std::uint32_t r = 0u; r < height_; ++r) {
    vertical_[r] |= bit(0u) | bit(width_);
  }
}

bool Maze::has_wall(std::uint32_t column, std::uint32_t row, Side side) const {
  if (column >= width_ || row >= height_) {
    return false;
  }
  switch (side) {
    case Side::north:
      return (horizontal_[row + 1u] & bit(column)) != 0u;
    case Side::south:
      return (horizontal_[row] & bit(column)) != 0u;
    case Side::east:
      return (vertical_[row] & bit(column + 1u)) != 0u;
    case Side::west:
      return (vertical_[row] & bit(column)) != 0u;
  }
  return false;
}

void Maze::set_wall(std::uint32_t column, std::uint32_t row, Side side, bool present) {
  if (column >= width_ || row >= height_) {
    return;
  }
  std::uint64_t* word = nullptr;
  std::uint64_t mask = 0u;
  switch (side) {
    case Side::north:
      word = &horizontal_[row + 1u];
      mask = bit(column);
      break;
    case Side::south:
      word = &horizontal_[row];
      mask = bit(column);
      break;
    case Side::east:
      word = &vertical_[row];
      mask = bit(column + 1u);
      break;
    case Side::west:
      word = &vertical_[row];
      mask = bit(column);
      break;
  }
  if (word != nullptr) {
    *word = present ? (*word | mask) : (*word & ~mask);
  }
}

MazePose Maze::cell_centre(std::uint32_t column, std::uint32_t row, double heading_rad) {
  return MazePose{(column + 0.5) * cell_pitch_mm, (row + 0.5) * cell_pitch_mm, heading_rad};
}

// Everything that overlaps the cell's square: the walls on its four sides and its four corner
// posts (a wall or post of another cell ends at least 6 mm outside it).
void Maze::test_cell(std::int64_t column, std::int64_t row, const Candidate& ray,
                     RayHit& best) const {
  const auto c = static_cast<std::uint32_t>(column);
  const auto r = static_cast<std::uint32_t>(row);
  const double x0 = c * cell_pitch_mm;
  const double y0 = r * cell_pitch_mm;
  const double x1 = x0 + cell_pitch_mm;
  const double y1 = y0 + cell_pitch_mm;
  for (std::uint32_t line = r; line <= r + 1u; ++line) {
    if ((horizontal_[line] & bit(c)) != 0u) {
      const double y = line * cell_pitch_mm;
      ray.against(x0 + half_wall_mm, x1 - half_wall_mm, y - half_wall_mm, y + half_wall_mm,
                  SurfaceKind::wall, horizontal_wall_id(line, c), best);
    }
  }
  for (std::uint32_t line = c; line <= c + 1u; ++line) {
    if ((vertical_[r] & bit(line)) != 0u) {
      const double x = line * cell_pitch_mm;
      ray.against(x - half_wall_mm, x + half_wall_mm, y0 + half_wall_mm, y1 - half_wall_mm,
                  SurfaceKind::wall, vertical_wall_id(line, r), best);
    }
  }
  for (std::uint32_t line_y = r; line_y <= r + 1u; ++line_y) {
    for (std::uint32_t line_x = c; line_x <= c + 1u; ++line_x) {
      const double x = line_x * cell_pitch_mm;
      const double y = line_y * cell_pitch_mm;
      ray.against(x - half_wall_mm, x + half_wall_mm, y - half_wall_mm, y + half_wall_mm,
                  SurfaceKind::post, post_id(line_x, line_y), best);
    }
  }
}

// A ray from outside the cells' squares: every cell's walls and posts (slow, and never the case
// for a robot inside its maze).
RayHit Maze::cast_everything(const Candidate& ray, double max_distance_mm) const {
  RayHit best{};
  for (std::uint32_t r = 0u; r < height_; ++r) {
    for (std::uint32_t c = 0u; c < width_; ++c) {
      test_cell(c, r, ray, best);
    }
  }
  if (best.kind == SurfaceKind::none || best.distance_mm > max_distance_mm) {
    return RayHit{SurfaceKind::none, max_distance_mm, 0.0, 0u};
  }
  return best;
}

RayHit Maze::cast(double x_mm, double y_mm, double heading_rad, double max_distance_mm) const {
  const RayHit nothing{SurfaceKind::none, max_distance_mm, 0.0, 0u};
  if (!std::isfinite(x_mm) || !std::isfinite(y_mm) || !std::isfinite(heading_rad) ||
      !(max_distance_mm >= 0.0)) {
    return nothing;
  }
  const Candidate ray{x_mm, y_mm, std::cos(heading_rad), std::sin(heading_rad)};
  const double right_mm = width_ * cell_pitch_mm;
  const double top_mm = height_ * cell_pitch_mm;
  if (x_mm < 0.0 || y_mm < 0.0 || x_mm > right_mm || y_mm > top_mm) {
    return cast_everything(ray, max_distance_mm);
  }
  // Walk the cells the ray crosses (Amanatides & Woo), nearest first.
  auto column = static_cast<std::int64_t>(x_mm / cell_pitch_mm);
  auto row = static_cast<std::int64_t>(y_mm / cell_pitch_mm);
  column = column >= static_cast<std::int64_t>(width_) ? width_ - 1 : column;
  row = row >= static_cast<std::int64_t>(height_) ? height_ - 1 : row;
  const std::int64_t step_x = ray.dx > 0.0 ? 1 : -1;
  const std::int64_t step_y = ray.dy > 0.0 ? 1 : -1;
  RayHit best{};
  while (true) {
    test_cell(column, row, ray, best);
    const double edge_x = (ray.dx > 0.0 ? column + 1 : column) * cell_pitch_mm;
    const double edge_y = (ray.dy > 0.0 ? row + 1 : row) * cell_pitch_mm;
    const double t_x = ray.dx != 0.0 ? (edge_x - x_mm) / ray.dx : no_hit;
    const double t_y = ray.dy != 0.0 ? (edge_y - y_mm) / ray.dy : no_hit;
    const double t_exit = t_x < t_y ? t_x : t_y;
    if (best.kind != SurfaceKind::none && best.distance_mm <= t_exit) {
      break;
    }
    if (t_exit > max_distance_mm) {
      return nothing;
    }
    if (t_x < t_y) {
      column += step_x;
    } else {
      row += step_y;
    }
    if (column < 0 || row < 0 || column >= static_cast<std::int64_t>(width_) ||
        row >= static_cast<std::int64_t>(height_)) {
      break;  // out through an open perimeter: what this cell's border held, if anything
    }
  }
  if (best.kind == SurfaceKind::none || best.distance_mm > max_distance_mm) {
    return nothing;
  }
  return best;
}

}  // namespace odocal::sim
