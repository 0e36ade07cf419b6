// The ray cast against known micromouse geometry: 180 mm cells, 12 mm walls, 12x12 mm posts.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "odocal/sim/maze.hpp"
#include "odocal/sim/random.hpp"

namespace odocal::sim {
namespace {

constexpr double ray_pi = std::numbers::pi;
// From a cell's centre to a face of its own wall: half a pitch less half a wall.
constexpr double centre_to_face_mm = 90.0 - 6.0;
constexpr double far_mm = 10000.0;

TEST(MazeRay, FromTheCellCentreEachWallFaceIs84mmAwaySquareOn) {
  const Maze maze(1u, 1u);
  const MazePose centre = Maze::cell_centre(0u, 0u);
  for (int quarter = 0; quarter < 4; ++quarter) {
    const RayHit hit = maze.cast(centre.x_mm, centre.y_mm, quarter * ray_pi / 2.0, far_mm);
    EXPECT_EQ(hit.kind, SurfaceKind::wall) << quarter;
    EXPECT_NEAR(hit.distance_mm, centre_to_face_mm, 1e-9) << quarter;
    EXPECT_NEAR(hit.incidence_rad, 0.0, 1e-9) << quarter;
  }
}

TEST(MazeRay, PassesBetweenPostsWhereThereIsNoWall) {
  const Maze maze(3u, 1u);  // three cells in a row, no inner wall
  const RayHit hit = maze.cast(90.0, 90.0, 0.0, far_mm);
  EXPECT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, 3.0 * 180.0 - 6.0 - 90.0, 1e-9);
}

TEST(MazeRay, HitsAPostWhereTheWallEnds) {
  Maze maze(2u, 2u);
  // 3 mm below the line y = 180, heading east: the post at (180, 180) spans y in [174, 186].
  RayHit hit = maze.cast(90.0, 177.0, 0.0, far_mm);
  EXPECT_EQ(hit.kind, SurfaceKind::post);
  EXPECT_NEAR(hit.distance_mm, 180.0 - 6.0 - 90.0, 1e-9);
  EXPECT_NEAR(hit.incidence_rad, 0.0, 1e-9);
  // With the wall between (0, 0) and (1, 0), the same ray still meets the post (the wall ends at
  // y = 174), and a ray 7 mm lower meets the wall.
  maze.set_wall(0u, 0u, Side::east, true);
  EXPECT_EQ(maze.cast(90.0, 177.0, 0.0, far_mm).kind, SurfaceKind::post);
  hit = maze.cast(90.0, 170.0, 0.0, far_mm);
  EXPECT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, 84.0, 1e-9);
}

TEST(MazeRay, ADiagonalRayMeetsTheWallAtItsIncidence) {
  const Maze maze(1u, 1u);
  const MazePose centre = Maze::cell_centre(0u, 0u);
  // 60° from east: the north wall, 30° off its normal, at 84 / sin 60°; it meets the wall 48.5 mm
  // east of the centre, well inside the wall's span (±84 mm), not a post.
  RayHit hit = maze.cast(centre.x_mm, centre.y_mm, ray_pi / 3.0, far_mm);
  EXPECT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, centre_to_face_mm / std::sin(ray_pi / 3.0), 1e-9);
  EXPECT_NEAR(hit.incidence_rad, ray_pi / 6.0, 1e-12);
  // 20° from east: the east wall, 20° off its normal.
  hit = maze.cast(centre.x_mm, centre.y_mm, ray_pi / 9.0, far_mm);
  EXPECT_NEAR(hit.distance_mm, centre_to_face_mm / std::cos(ray_pi / 9.0), 1e-9);
  EXPECT_NEAR(hit.incidence_rad, ray_pi / 9.0, 1e-12);
  // 200° (south of west): the west wall, 20° off.
  hit = maze.cast(centre.x_mm, centre.y_mm, ray_pi + ray_pi / 9.0, far_mm);
  EXPECT_NEAR(hit.distance_mm, centre_to_face_mm / std::cos(ray_pi / 9.0), 1e-9);
  EXPECT_NEAR(hit.incidence_rad, ray_pi / 9.0, 1e-12);
}

TEST(MazeRay, LooksNoFurtherThanItsLimit) {
  const Maze maze(3u, 1u);
  const RayHit hit = maze.cast(90.0, 90.0, 0.0, 200.0);
  EXPECT_EQ(hit.kind, SurfaceKind::none);
  EXPECT_EQ(hit.distance_mm, 200.0);
  EXPECT_EQ(maze.cast(90.0, 90.0, 0.0, 444.0).kind, SurfaceKind::wall);
}

TEST(MazeRay, InsideAWallTheDistanceIsZeroAndOutsideTheMazeItFindsTheOuterFace) {
  const Maze maze(1u, 1u);
  EXPECT_EQ(maze.cast(2.0, 90.0, 0.0, far_mm).distance_mm, 0.0);
  const RayHit hit = maze.cast(-100.0, 90.0, 0.0, far_mm);
  EXPECT_EQ(hit.kind, SurfaceKind::wall);
  EXPECT_NEAR(hit.distance_mm, 100.0 - 6.0, 1e-9);
}

TEST(MazeRay, AWallIsOneSurfaceFromEitherSide) {
  Maze maze(2u, 1u);
  maze.set_wall(0u, 0u, Side::east, true);
  const RayHit from_west = maze.cast(90.0, 90.0, 0.0, far_mm);
  const RayHit from_east = maze.cast(270.0, 90.0, ray_pi, far_mm);
  EXPECT_EQ(from_west.surface, from_east.surface);
  EXPECT_NE(from_west.surface, maze.cast(90.0, 90.0, ray_pi, far_mm).surface);
  EXPECT_NE(from_west.surface, maze.cast(90.0, 177.0, 0.0, far_mm).surface);  // the post
}

// Every wall and post of a maze as a rectangle [x0, x1] x [y0, y1].
struct Box {
  double x0, x1, y0, y1;
};
std::vector<Box> boxes_of(const Maze& maze) {
  std::vector<Box> boxes;
  for (std::uint32_t r = 0u; r <= maze.height(); ++r) {
    for (std::uint32_t c = 0u; c <= maze.width(); ++c) {
      boxes.push_back({c * 180.0 - 6.0, c * 180.0 + 6.0, r * 180.0 - 6.0, r * 180.0 + 6.0});
      if (c < maze.width() &&
          (maze.has_wall(c, r, Side::south) || (r > 0u && maze.has_wall(c, r - 1u, Side::north)))) {
        boxes.push_back({c * 180.0 + 6.0, c * 180.0 + 174.0, r * 180.0 - 6.0, r * 180.0 + 6.0});
      }
      if (r < maze.height() &&
          (maze.has_wall(c, r, Side::west) || (c > 0u && maze.has_wall(c - 1u, r, Side::east)))) {
        boxes.push_back({c * 180.0 - 6.0, c * 180.0 + 6.0, r * 180.0 + 6.0, r * 180.0 + 174.0});
      }
    }
  }
  return boxes;
}
bool inside_any(const std::vector<Box>& boxes, double x, double y, double margin) {
  for (const Box& b : boxes) {
    if (x >= b.x0 - margin && x <= b.x1 + margin && y >= b.y0 - margin && y <= b.y1 + margin) {
      return true;
    }
  }
  return false;
}

TEST(MazeRay, EveryHitInThePracticeMazeLiesOnAFaceWithNothingBefore) {
  const Maze maze = practice_maze();
  const std::vector<Box> boxes = boxes_of(maze);
  Random random(48u);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const double x = random.uniform(0.0, 6.0 * 180.0);
    const double y = random.uniform(0.0, 6.0 * 180.0);
    if (inside_any(boxes, x, y, 0.0)) {
      continue;
    }
    const double heading = random.uniform(-ray_pi, ray_pi);
    const RayHit hit = maze.cast(x, y, heading, far_mm);
    ASSERT_NE(hit.kind, SurfaceKind::none);  // the perimeter is closed
    const double dx = std::cos(heading);
    const double dy = std::sin(heading);
    EXPECT_TRUE(inside_any(boxes, x + hit.distance_mm * dx, y + hit.distance_mm * dy, 1e-6));
    for (int k = 0; k < 200; ++k) {
      const double t = hit.distance_mm * k / 200.0 - 1e-6;
      ASSERT_FALSE(inside_any(boxes, x + t * dx, y + t * dy, 0.0)) << i << " " << k;
    }
    // The incidence is the angle to the normal of an axis-aligned face.
    const double along_x = std::atan2(std::fabs(dy), std::fabs(dx));
    const double along_y = std::atan2(std::fabs(dx), std::fabs(dy));
    EXPECT_TRUE(std::fabs(hit.incidence_rad - along_x) < 1e-12 ||
                std::fabs(hit.incidence_rad - along_y) < 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 1500);
}

}  // namespace
}  // namespace odocal::sim
