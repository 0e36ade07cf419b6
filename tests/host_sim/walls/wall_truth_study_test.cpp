// The walls' own error against the simulator's truth, per reading kind (issue 48): eight
// generated usual mice (gains 1 ± 20 %, walls 1 ± 5 %, σ = 6 counts per conversion) learn their
// sensors from a turn in the start cell of a corridor maze, then read (a) a front wall, (b) the
// corridor's offset and heading, (c) the angle turned and (d) the wall edges and the wheels'
// scale. Every error is held to four standard deviations predicted from the noise model: the
// reading's relative error (the wall's reflectivity, the learnt strength, the ADC's noise)
// propagated through the response's slope at the working distance. The table is printed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "walls_rig.hpp"

namespace odocal::host::walls {
namespace {

using rig::degrees;
using rig::pi;

// One wall's reflectivity, uniform in 1 ± 5 %: σ of ln lit.
const double study_sigma_wall = 0.05 / std::sqrt(3.0);
// A strength learnt on the start cell's three walls: their mean reflectivity's σ.
const double study_sigma_strength = study_sigma_wall / std::sqrt(3.0);
// A front wall's heading known worse than this is refused (its own predicted σ).
constexpr double study_max_front_heading_sd = 1.0 * degrees;
// One lit reading: two conversions of σ = 6 counts.
double study_sigma_noise(double lit) {
  return sim::SensorPhysics{}.noise_sigma_counts * std::sqrt(2.0) / lit;
}

struct StudyKind {
  std::string name;
  std::string unit;
  std::vector<double> errors;
  std::vector<double> predicted_sd;

  // Every reading is held to four of its predicted sd: none may go beyond.
  void add(double error, double sd) {
    errors.push_back(error);
    predicted_sd.push_back(sd);
    EXPECT_LE(std::fabs(error), 4.0 * sd)
        << name << " reading " << errors.size() << ": beyond 4 predicted sd";
  }
};

struct StudyKinds {
  StudyKind centre{"(turn) centre of the turn, x and y", "mm", {}, {}};
  StudyKind start_heading{"(turn) start heading", "deg", {}, {}};
  StudyKind turned{"(c) angle turned over 450 deg", "deg", {}, {}};
  StudyKind strength{"(turn) sensor strength a / true", "%", {}, {}};
  StudyKind front_distance{"(a) front wall distance", "mm", {}, {}};
  StudyKind front_heading{"(a) heading to the front wall", "deg", {}, {}};
  StudyKind corridor_offset{"(b) corridor offset", "mm", {}, {}};
  StudyKind corridor_heading{"(b) corridor heading (run)", "deg", {}, {}};
  StudyKind edge_position{"(d) position at a wall edge", "mm", {}, {}};
  StudyKind scale{"(d) wheel scale over the corridor", "%", {}, {}};
  std::size_t front_headings_refused = 0u;
};

// The truth's sensors: a = gain·k, p = 1 (the walls' reflectivity averaged out).
SensorSet study_true_sensors(const rig::Rig& truth) {
  SensorSet set = usual_mouse_sensors();
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    set.responses[i] = SensorResponse{truth.layout().sensors[i].gain * 6.0e6, 1.0};
  }
  return set;
}

TurnCalibration study_turn(rig::Rig& truth, std::uint64_t seed, rig::TrueTurn& turn,
                           StudyKinds& kinds) {
  turn.centre_x_mm = 90.0 + 4.0 * std::sin(seed * 1.3);
  turn.centre_y_mm = 90.0 + 4.0 * std::cos(seed * 2.1);
  turn.start_heading_rad = pi / 2.0 + 6.0 * degrees * std::sin(seed * 0.7);
  const std::vector<TurnSample> samples = rig::sample_turn(truth, turn);
  const TurnSetup setup{0u, 0u, pi / 2.0, turn.radians_per_count * 1.04};
  const TurnCalibration fit =
      calibrate_from_turn(truth.scene().maze(), setup, usual_mouse_sensors().mounts, samples);
  // Square on a wall from the centre the front sensors are 44 mm off it: a relative error ε in
  // lit is ε/2 in distance; the centre comes from one wall (y) or two (x) and the strengths.
  const double square_mm = face_from_centre_mm - 40.0;
  const double lit_square = 6.0e6 / (square_mm * square_mm);
  const double centre_sd =
      square_mm / 2.0 *
      std::hypot(study_sigma_wall, study_sigma_strength, study_sigma_noise(lit_square));
  kinds.centre.add(fit.centre_x_mm - turn.centre_x_mm, centre_sd);
  kinds.centre.add(fit.centre_y_mm - turn.centre_y_mm, centre_sd);
  // The start heading and the angle per count: the fit's own σ from its Jacobian at the solution
  // and the noise model (each reading's ADC noise, each face's reflectivity). It must be no looser
  // than the square sighting's bound (the front pair's imbalance over their 60 mm) the study used
  // before, and it must be near what the fit makes: z below 4 for each mouse.
  const double sighting_sd = square_mm / 2.0 * std::sqrt(2.0) *
                             std::hypot(study_sigma_strength, study_sigma_noise(lit_square)) / 60.0;
  EXPECT_GT(fit.start_heading_sd_rad, 0.0);
  EXPECT_LT(fit.start_heading_sd_rad, sighting_sd);
  kinds.start_heading.add((fit.start_heading_rad - turn.start_heading_rad) / degrees,
                          fit.start_heading_sd_rad / degrees);
  const double counts = samples.back().turn_counts;
  EXPECT_GT(fit.radians_per_count_sd, 0.0);
  EXPECT_LT(fit.radians_per_count_sd * counts, std::sqrt(2.0) * sighting_sd);
  kinds.turned.add((fit.radians_per_count - turn.radians_per_count) * counts / degrees,
                   fit.radians_per_count_sd * counts / degrees);
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    const double truth_a = truth.layout().sensors[i].gain * 6.0e6;
    kinds.strength.add(100.0 * (fit.sensors.responses[i].a_counts_mm2 / truth_a - 1.0),
                       100.0 * study_sigma_strength);
  }
  return fit;
}

// (a): facing the start cell's south wall (its face at y = 6) from 90 to 150 mm.
void study_front(rig::Rig& truth, const TurnCalibration& fit, StudyKinds& kinds) {
  const SensorSet exact = study_true_sensors(truth);
  for (const double distance : {90.0, 120.0, 150.0}) {
    for (const double lateral : {-6.0, 0.0, 6.0}) {
      for (const double heading_deg : {-5.0, 0.0, 5.0}) {
        const double psi = heading_deg * degrees;
        const std::array<double, sensor_count> lit =
            truth.read(sim::MazePose{90.0 + lateral, 6.0 + distance, -pi / 2.0 + psi});
        const FrontWall wall = observe_front_wall(fit.sensors, lit[left_front], lit[right_front]);
        ASSERT_TRUE(wall.valid) << distance << " " << lateral << " " << heading_deg;
        SCOPED_TRACE(std::to_string(distance) + " " + std::to_string(lateral) + " " +
                     std::to_string(heading_deg));
        // Propagation: J = d ln lit / d(D, ψ) of the true sensors at the true pose; the wall's
        // and the strengths' common part is shared by both readings.
        const sim::MazePose robot{0.0, 0.0, psi};
        std::array<std::array<double, 2>, 2> j{};
        std::array<double, 2> level{};
        for (std::size_t k = 0u; k < 2u; ++k) {
          const std::size_t i = k == 0u ? left_front : right_front;
          const auto log_lit = [&](double d, double h) {
            return std::log(lit_from_face(exact.responses[i], exact.mounts[i],
                                          sim::MazePose{0.0, 0.0, h}, 0.0, d));
          };
          level[k] = lit_from_face(exact.responses[i], exact.mounts[i], robot, 0.0, distance);
          j[k][0] = (log_lit(distance + 1e-3, psi) - log_lit(distance - 1e-3, psi)) / 2e-3;
          j[k][1] = (log_lit(distance, psi + 1e-6) - log_lit(distance, psi - 1e-6)) / 2e-6;
        }
        const double det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        // Rows of J⁻¹: distance = (j11 r0 − j01 r1)/det, heading = (−j10 r0 + j00 r1)/det.
        const double common = study_sigma_wall;
        const auto sd_of = [&](double w0, double w1) {
          const double own0 = std::hypot(study_sigma_strength, study_sigma_noise(level[0]));
          const double own1 = std::hypot(study_sigma_strength, study_sigma_noise(level[1]));
          return std::sqrt((w0 + w1) * (w0 + w1) * common * common + w0 * w0 * own0 * own0 +
                           w1 * w1 * own1 * own1);
        };
        // The observation's own σ, from the same noise model at its solution and learnt sensors,
        // agrees with this one from the truth (within the learnt sensors' few %).
        const double distance_sd = sd_of(j[1][1] / det, -j[0][1] / det);
        const double heading_sd = sd_of(-j[1][0] / det, j[0][0] / det);
        EXPECT_NEAR(wall.distance_sd_mm, distance_sd, 0.1 * distance_sd);
        EXPECT_NEAR(wall.heading_sd_rad, heading_sd, 0.1 * heading_sd);
        // A heading the observation itself says is known worse than 1° is refused (squaring up
        // needs better); the distance stands.
        kinds.front_distance.add(wall.distance_mm - distance, distance_sd);
        if (wall.heading_sd_rad > study_max_front_heading_sd) {
          ++kinds.front_headings_refused;
          continue;
        }
        kinds.front_heading.add((wall.heading_rad - psi) / degrees, heading_sd / degrees);
      }
    }
  }
}

// σ of one offset from the two diagonals (1-D least squares), at `offset` and `heading`.
double study_offset_sd(const SensorSet& exact, double offset, double heading) {
  double information = 0.0;
  double weighted = 0.0;
  for (const std::size_t i : {left_diagonal, right_diagonal}) {
    const double normal = i == left_diagonal ? pi / 2.0 : -pi / 2.0;
    const auto log_lit = [&](double e) {
      return std::log(lit_from_face(exact.responses[i], exact.mounts[i],
                                    sim::MazePose{0.0, e, heading}, normal, face_from_centre_mm));
    };
    const double level =
        lit_from_face(exact.responses[i], exact.mounts[i], sim::MazePose{0.0, offset, heading},
                      normal, face_from_centre_mm);
    const double slope = (log_lit(offset + 1e-3) - log_lit(offset - 1e-3)) / 2e-3;
    const double sigma =
        std::hypot(study_sigma_wall, study_sigma_strength, study_sigma_noise(level));
    information += slope * slope;
    weighted += slope * slope * sigma * sigma;
  }
  return std::sqrt(weighted) / information;
}

// Whether the diagonal `i`'s axis truly meets the flat side face of a wall (not a post, not an
// end face) at `pose`: what the robot's own rule (clear_of_posts) is meant to ensure.
bool study_on_wall_face(const rig::Rig& truth, std::size_t i, const sim::MazePose& pose) {
  const sim::SensorMount& mount = truth.layout().sensors[i].mount;
  const sim::RayHit hit = truth.scene().look(mount, pose);
  const double c = std::cos(pose.theta_rad);
  const double s = std::sin(pose.theta_rad);
  const double across = pose.x_mm + c * mount.x_mm - s * mount.y_mm +
                        hit.distance_mm * std::cos(pose.theta_rad + mount.yaw_rad);
  return hit.kind == sim::SurfaceKind::wall && std::fabs(std::fabs(across - 90.0) - 84.0) < 1e-6;
}

// The true y at `travel` (the samples' travels increase).
double study_true_y(const std::vector<RunSample>& samples, const std::vector<double>& true_y,
                    double travel) {
  const auto after = std::lower_bound(
      samples.begin(), samples.end(), travel,
      [](const RunSample& sample, double value) { return sample.travel_mm < value; });
  const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(after - samples.begin(), 1));
  const double t0 = samples[k - 1u].travel_mm;
  const double t1 = samples[k].travel_mm;
  return true_y[k - 1u] + (true_y[k] - true_y[k - 1u]) * (travel - t0) / (t1 - t0);
}

// The run's truth and what the robot learnt of it.
struct StudyRun {
  rig::TrueRun run;
  std::vector<double> true_y;
  std::vector<RunSample> samples;
  CorridorLine line;
  WheelScale scale;
  double heading_sd = 0.0;  // predicted, of line.heading_rad
  double edge_sd = 0.0;     // predicted, of one edge's position
};

// The robot's true pose at sample j of the run.
sim::MazePose study_pose(const StudyRun& run, std::size_t j) {
  const double psi = run.run.heading_error_rad;
  const double y = run.true_y[j];
  return sim::MazePose{run.run.x_mm - (y - run.run.y_start_mm) * std::tan(psi), y, pi / 2.0 + psi};
}

// (b): the offset at every tenth sample whose diagonals both land clear of the posts, by where
// the robot knows itself along the corridor from the edges it has passed (its wheel scale line).
void study_offsets(rig::Rig& truth, const TurnCalibration& fit, const StudyRun& run,
                   StudyKinds& kinds) {
  const SensorSet exact = study_true_sensors(truth);
  // The robot's position along the corridor is the edges' line: each edge's error is edge_sd,
  // the line's is less; four of them keep the rule honest.
  const double margin = 4.0 * run.edge_sd;
  std::size_t refused = 0u;
  for (std::size_t j = 0u; j < run.samples.size(); j += 10u) {
    const RunSample& sample = run.samples[j];
    const CorridorPose pose =
        observe_corridor(fit.sensors, sample.lit_counts[left_diagonal],
                         sample.lit_counts[right_diagonal], run.line.heading_rad);
    if (!pose.valid) {
      continue;
    }
    // Where the robot holds itself: along from the edges' line, across from the corridor's line,
    // the line's heading; the maze is its map.
    const sim::MazePose believed{90.0 - run.line.offset_at(sample.travel_mm),
                                 (sample.travel_mm - run.scale.start_mm) / run.scale.scale,
                                 pi / 2.0 + run.line.heading_rad};
    if (!on_wall_face(truth.scene().maze(), fit.sensors.mounts[left_diagonal], believed, margin) ||
        !on_wall_face(truth.scene().maze(), fit.sensors.mounts[right_diagonal], believed, margin)) {
      ++refused;
      continue;
    }
    const sim::MazePose truth_pose = study_pose(run, j);
    EXPECT_TRUE(study_on_wall_face(truth, left_diagonal, truth_pose) &&
                study_on_wall_face(truth, right_diagonal, truth_pose))
        << "a reading the rule kept lands off a wall's face at y = " << truth_pose.y_mm;
    const double true_offset = 90.0 - truth_pose.x_mm;
    kinds.corridor_offset.add(pose.offset_mm - true_offset,
                              study_offset_sd(exact, true_offset, run.run.heading_error_rad));
  }
  // The posts take 12 mm and the margins 2 · margin of every 180 mm, for either diagonal.
  const double expected = 2.0 * (sim::wall_thickness_mm + 2.0 * margin) / sim::cell_pitch_mm;
  EXPECT_LE(static_cast<double>(refused),
            1.2 * expected * static_cast<double>(run.samples.size()) / 10.0);
}

// (d): the edges the right diagonal sees and the wheels' scale from them.
void study_edges(const TurnCalibration& fit, StudyRun& run, StudyKinds& kinds) {
  const sim::SensorMount& mount = fit.sensors.mounts[right_diagonal];
  const double threshold = 0.5 * lit_from_face(fit.sensors.responses[right_diagonal], mount,
                                               sim::MazePose{}, -pi / 2.0, face_from_centre_mm);
  const double nominal_ahead = look_ahead_mm(mount, 0.0, 0.0);
  std::vector<double> positions;
  std::vector<double> travels;
  for (const WallEdge& edge : find_wall_edges(run.samples, right_diagonal, threshold)) {
    const double face =
        nearest_edge_face_mm(fit.centre_y_mm + edge.travel_mm + nominal_ahead, edge.falling);
    const double position = position_at_edge_mm(
        mount, face, edge.falling, run.line.offset_at(edge.travel_mm), run.line.heading_rad);
    kinds.edge_position.add(position - study_true_y(run.samples, run.true_y, edge.travel_mm),
                            run.edge_sd);
    positions.push_back(position);
    travels.push_back(edge.travel_mm);
  }
  ASSERT_GE(positions.size(), 6u);
  run.scale = fit_wheel_scale(positions, travels);
  double mean = 0.0;
  for (const double p : positions) {
    mean += p / static_cast<double>(positions.size());
  }
  double spread = 0.0;
  for (const double p : positions) {
    spread += (p - mean) * (p - mean);
  }
  kinds.scale.add(100.0 * (run.scale.scale / run.run.scale - 1.0),
                  100.0 * run.edge_sd / std::sqrt(spread));
}

// (b) and (d): a straight run north along the corridor from where the robot turned.
void study_run(rig::Rig& truth, std::uint64_t seed, const rig::TrueTurn& turn,
               const TurnCalibration& fit, StudyKinds& kinds) {
  StudyRun run;
  run.run.x_mm = turn.centre_x_mm;
  run.run.y_start_mm = turn.centre_y_mm;
  run.run.heading_error_rad = 0.3 * degrees * std::sin(seed * 2.9);
  run.run.scale = 1.0 + 0.03 * std::sin(seed * 1.7);
  run.run.length_mm = 1500.0;
  run.samples = rig::sample_run(truth, run.run, run.true_y);
  const SensorSet exact = study_true_sensors(truth);
  run.line = fit_corridor_line(fit.sensors, run.samples);
  const double offset_sd = study_offset_sd(exact, 0.0, 0.0);
  // The slope of offsets wrong by one wall's error at each end of the span; the encoders' scale
  // stretches the run.
  const double span = run.samples.back().travel_mm - run.samples.front().travel_mm;
  run.heading_sd = std::hypot(offset_sd * std::sqrt(6.0) / span,
                              run.run.heading_error_rad * (1.0 - 1.0 / run.run.scale));
  kinds.corridor_heading.add((run.line.heading_rad - run.run.heading_error_rad) / degrees,
                             run.heading_sd / degrees);
  const sim::SensorMount& mount = fit.sensors.mounts[right_diagonal];
  const double ahead_per_mm =
      (look_ahead_mm(mount, 1e-3, 0.0) - look_ahead_mm(mount, -1e-3, 0.0)) / 2e-3;
  const double ahead_per_rad =
      (look_ahead_mm(mount, 0.0, 1e-6) - look_ahead_mm(mount, 0.0, -1e-6)) / 2e-6;
  const double spacing = run.run.step_mm * run.run.scale;
  run.edge_sd = std::hypot(spacing / std::sqrt(12.0), ahead_per_mm * offset_sd,
                           ahead_per_rad * run.heading_sd);
  study_edges(fit, run, kinds);
  study_offsets(truth, fit, run, kinds);
}

void print_kind(const StudyKind& kind) {
  double mean = 0.0;
  double worst = 0.0;
  for (const double e : kind.errors) {
    mean += e / static_cast<double>(kind.errors.size());
    worst = std::max(worst, std::fabs(e));
  }
  double variance = 0.0;
  for (const double e : kind.errors) {
    variance += (e - mean) * (e - mean) / static_cast<double>(kind.errors.size());
  }
  std::vector<double> sds = kind.predicted_sd;
  std::nth_element(sds.begin(), sds.begin() + sds.size() / 2u, sds.end());
  std::printf("%-38s %-4s %6zu %9.4f %9.4f %9.4f %9.4f\n", kind.name.c_str(), kind.unit.c_str(),
              kind.errors.size(), mean, std::sqrt(variance), worst, sds[sds.size() / 2u]);
}

TEST(WallTruthStudy, ErrorPerReadingKindWithinTheNoiseModel) {
  StudyKinds kinds;
  for (std::uint64_t seed = 1u; seed <= 8u; ++seed) {
    rig::Rig truth(rig::gapped_corridor(), seed);
    rig::TrueTurn turn;
    const TurnCalibration fit = study_turn(truth, seed, turn, kinds);
    study_front(truth, fit, kinds);
    study_run(truth, seed, turn, fit, kinds);
  }
  std::printf("%-38s %-4s %6s %9s %9s %9s %9s\n", "reading kind (8 mice)", "unit", "n", "mean",
              "sd", "max|err|", "pred. sd");
  for (const StudyKind* kind : {&kinds.centre, &kinds.start_heading, &kinds.turned, &kinds.strength,
                                &kinds.front_distance, &kinds.front_heading, &kinds.corridor_offset,
                                &kinds.corridor_heading, &kinds.edge_position, &kinds.scale}) {
    ASSERT_FALSE(kind->errors.empty()) << kind->name;
    print_kind(*kind);
  }
  std::printf("(a) front headings refused (predicted sd > 1 deg): %zu\n",
              kinds.front_headings_refused);
  // At 150 mm the front pair's heading is known to about 1.8°, at 120 mm to about 1°: of the 27
  // poses per mouse the 9 at 150 mm are refused and none at 90 mm.
  EXPECT_GE(kinds.front_headings_refused, 8u * 9u);
  EXPECT_LE(kinds.front_headings_refused, 8u * 18u);
}

}  // namespace
}  // namespace odocal::host::walls
