// The observations' geometry without noise: each inversion gives back the pose it was made from,
// agrees with the simulator's ray cast, and refuses what it cannot use.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "walls_rig.hpp"

namespace odocal::host::walls {
namespace {

using rig::degrees;
using rig::pi;

// The simulator's sensor of gain 1 on a wall of reflectivity 1: a = k, p = 1.
SensorSet exact_sensors() {
  SensorSet set = usual_mouse_sensors();
  for (SensorResponse& response : set.responses) {
    response = SensorResponse{sim::SensorPhysics{}.k_counts_mm2, 1.0};
  }
  return set;
}

TEST(WallFaceModel, AgreesWithTheSimulatorsScene) {
  // A 1x1 maze without reflectivity spread: the scene's noiseless light is the face model's.
  sim::SensorPhysics physics;
  physics.reflectivity_spread = 0.0;
  const sim::Maze maze;
  const sim::SensorScene scene(maze, physics, 1u);
  const SensorSet sensors = exact_sensors();
  const sim::WallSensorLayout layout;
  for (const double heading_deg : {-10.0, 0.0, 7.0}) {
    const sim::MazePose robot{85.0, 80.0, heading_deg * degrees};
    // The front sensors see the east face at x = 174 (normal 0).
    for (const std::size_t i : {left_front, right_front}) {
      const double model =
          lit_from_face(sensors.responses[i], sensors.mounts[i], robot, 0.0, 174.0);
      EXPECT_NEAR(model, scene.lit_counts(layout.sensors[i], robot), 1e-9 * model) << heading_deg;
    }
  }
  // Away from the face: nothing.
  EXPECT_EQ(lit_from_face(sensors.responses[0], sensors.mounts[0], {0.0, 0.0, pi}, 0.0, 174.0),
            0.0);
}

TEST(FrontWall, GivesBackDistanceAndHeading) {
  const SensorSet sensors = exact_sensors();
  for (const double distance : {85.0, 110.0, 160.0}) {
    for (const double heading_deg : {-12.0, -3.0, 0.0, 5.0, 12.0}) {
      const sim::MazePose robot{0.0, 0.0, heading_deg * degrees};
      const double left = lit_from_face(sensors.responses[left_front], sensors.mounts[left_front],
                                        robot, 0.0, distance);
      const double right = lit_from_face(sensors.responses[right_front],
                                         sensors.mounts[right_front], robot, 0.0, distance);
      const FrontWall wall = observe_front_wall(sensors, left, right);
      ASSERT_TRUE(wall.valid) << distance << " " << heading_deg;
      EXPECT_NEAR(wall.distance_mm, distance, 1e-6);
      EXPECT_NEAR(wall.heading_rad, heading_deg * degrees, 1e-8);
    }
  }
}

TEST(FrontWall, RefusesDarkOrClippedReadings) {
  const SensorSet sensors = exact_sensors();
  EXPECT_FALSE(observe_front_wall(sensors, 50.0, 2000.0).valid);
  EXPECT_FALSE(observe_front_wall(sensors, 2000.0, 4000.0).valid);
  EXPECT_TRUE(observe_front_wall(sensors, 2000.0, 2000.0).valid);
}

TEST(Corridor, GivesBackTheOffsetGivenTheHeading) {
  const SensorSet sensors = exact_sensors();
  for (const double offset : {-20.0, 0.0, 9.0}) {
    for (const double heading_deg : {-8.0, 0.0, 3.0, 8.0}) {
      const sim::MazePose robot{0.0, offset, heading_deg * degrees};
      const double left = lit_from_face(sensors.responses[left_diagonal],
                                        sensors.mounts[left_diagonal], robot, pi / 2.0, 84.0);
      const double right = lit_from_face(sensors.responses[right_diagonal],
                                         sensors.mounts[right_diagonal], robot, -pi / 2.0, 84.0);
      const CorridorPose pose = observe_corridor(sensors, left, right, heading_deg * degrees);
      ASSERT_TRUE(pose.valid) << offset << " " << heading_deg;
      EXPECT_NEAR(pose.offset_mm, offset, 1e-6);
      EXPECT_NEAR(pose.mismatch, 0.0, 1e-9);
    }
  }
}

TEST(Corridor, DiagonalsAloneCannotTellHeadingFromOffset) {
  // Centred and straight, a turn of 1° and a step to the left change each diagonal's ln reading
  // in the same proportion (the mouse is symmetric): the 2x2 sensitivity is singular.
  const SensorSet sensors = exact_sensors();
  const auto log_lit = [&](std::size_t i, double offset, double heading) {
    const double normal = i == left_diagonal ? pi / 2.0 : -pi / 2.0;
    return std::log(lit_from_face(sensors.responses[i], sensors.mounts[i],
                                  sim::MazePose{0.0, offset, heading}, normal, 84.0));
  };
  const double h = 1e-4;
  const double left_e =
      (log_lit(left_diagonal, h, 0.0) - log_lit(left_diagonal, -h, 0.0)) / (2 * h);
  const double left_psi =
      (log_lit(left_diagonal, 0.0, h) - log_lit(left_diagonal, 0.0, -h)) / (2 * h);
  const double right_e =
      (log_lit(right_diagonal, h, 0.0) - log_lit(right_diagonal, -h, 0.0)) / (2 * h);
  const double right_psi =
      (log_lit(right_diagonal, 0.0, h) - log_lit(right_diagonal, 0.0, -h)) / (2 * h);
  EXPECT_NEAR(left_e * right_psi - left_psi * right_e, 0.0, 1e-9 * std::fabs(left_e * left_psi));
  // A gap of 64 mm across the 50° axis: 2/64 per mm in ln.
  EXPECT_NEAR(left_e, 2.0 / 64.0, 1e-6);
}

TEST(Corridor, LookAheadIsWhereTheAxisMeetsTheSideFace) {
  const sim::SensorMount right = usual_mouse_sensors().mounts[right_diagonal];
  // Centred and straight: 35 mm to the mount, then 64 mm across at 50°: 64 / tan 50°.
  EXPECT_NEAR(look_ahead_mm(right, 0.0, 0.0), 35.0 + 64.0 / std::tan(50.0 * degrees), 1e-9);
  // Closer to the right wall, the axis meets it sooner.
  EXPECT_LT(look_ahead_mm(right, -5.0, 0.0), look_ahead_mm(right, 0.0, 0.0));
}

TEST(Corridor, OnlyAWallsOwnFaceClearOfItsPostsIsACorridorReading) {
  // The gapped corridor's right side: walls in rows 0, 1 and 3, open in row 2. Centred and
  // heading north, the right diagonal meets the face line look_ahead_mm ahead.
  const sim::Maze maze = rig::gapped_corridor();
  const sim::SensorMount right = usual_mouse_sensors().mounts[right_diagonal];
  const double ahead = look_ahead_mm(right, 0.0, 0.0);
  const auto at = [&](double met_y) { return sim::MazePose{90.0, met_y - ahead, pi / 2.0}; };
  EXPECT_TRUE(on_wall_face(maze, right, at(270.0), 3.0));   // mid-wall in row 1
  EXPECT_TRUE(on_wall_face(maze, right, at(190.0), 3.0));   // 10 mm past the post at 180
  EXPECT_FALSE(on_wall_face(maze, right, at(188.0), 3.0));  // within the margin of it
  EXPECT_FALSE(on_wall_face(maze, right, at(182.0), 3.0));  // on the post's side face
  EXPECT_FALSE(on_wall_face(maze, right, at(450.0), 3.0));  // through the gap of row 2
  // Just short of the post beyond the gap: the axis goes on to the post's end face.
  EXPECT_FALSE(on_wall_face(maze, right, at(530.0), 3.0));
}

TEST(WallEdges, FoundBetweenTheSamplesWhereTheReadingCrosses) {
  std::vector<RunSample> samples;
  for (int i = 0; i <= 20; ++i) {
    RunSample sample;
    sample.travel_mm = i;
    sample.lit_counts[right_diagonal] = (i >= 5 && i < 12) ? 600.0 : 40.0;
    samples.push_back(sample);
  }
  const std::vector<WallEdge> edges = find_wall_edges(samples, right_diagonal, 300.0);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_FALSE(edges[0].falling);
  EXPECT_DOUBLE_EQ(edges[0].travel_mm, 4.5);
  EXPECT_TRUE(edges[1].falling);
  EXPECT_DOUBLE_EQ(edges[1].travel_mm, 11.5);
  EXPECT_THROW(static_cast<void>(find_wall_edges(samples, sensor_count, 300.0)),
               std::invalid_argument);
}

TEST(WallEdges, FacesAreThePostsFarOrNearSide) {
  EXPECT_DOUBLE_EQ(edge_face_mm(900.0, true), 906.0);
  EXPECT_DOUBLE_EQ(edge_face_mm(900.0, false), 894.0);
  EXPECT_DOUBLE_EQ(nearest_edge_face_mm(950.0, true), 906.0);
  EXPECT_DOUBLE_EQ(nearest_edge_face_mm(1000.0, false), 1074.0);
}

TEST(WheelScale, ALineThroughTheEdges) {
  const std::vector<double> positions{186.0, 354.0, 546.0, 900.0};
  std::vector<double> travel;
  for (const double p : positions) {
    travel.push_back(-80.0 + 0.97 * p);
  }
  const WheelScale scale = fit_wheel_scale(positions, travel);
  EXPECT_NEAR(scale.scale, 0.97, 1e-12);
  EXPECT_NEAR(scale.start_mm, -80.0, 1e-9);
  EXPECT_NEAR(scale.residual_sd_mm, 0.0, 1e-9);
  EXPECT_THROW(static_cast<void>(fit_wheel_scale({100.0}, {90.0})), std::invalid_argument);
  EXPECT_THROW(static_cast<void>(fit_wheel_scale({100.0, 100.0}, {90.0, 91.0})),
               std::invalid_argument);
}

}  // namespace
}  // namespace odocal::host::walls
