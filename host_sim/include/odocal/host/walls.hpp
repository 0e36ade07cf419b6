#pragma once
/// @file
/// The walls of a maze as a measuring instrument (issue 48, DESIGN "No tape measure"): a maze
/// robot's reflective wall sensors learnt from the maze's known geometry alone, and the
/// measurements they then give in place of a tape measure.
///
/// Sensor model (what each sensor is fitted to): above ambient, a sensor whose axis meets a flat
/// face at distance d (mm, along the axis from the sensor's nominal mount) and incidence φ reads
///   lit = a · cos(φ)^p / d²,
/// a the sensor's own strength (emitter, receiver and the walls' mean reflectivity, counts·mm²) and
/// p the incidence power, shared by the robot's sensors. Both are fitted from a turn in place in
/// the start cell (calibrate_from_turn), whose three walls stand at known places.
///
/// Observations: (a) the distance to a front wall and the heading relative to it from the two
/// front sensors (observe_front_wall); (b) the heading and lateral offset in a corridor walled on
/// both sides from the two diagonals (observe_corridor); (c) the angle turned in place from the
/// walls seen going round (TurnCalibration::radians_per_count); (d) where a side wall ends or
/// starts, at a known multiple of the cell pitch, against the encoders' distance
/// (find_wall_edges, fit_wheel_scale): the absolute scale of the wheels.
///
/// Frames: the maze frame of sim::Maze (mm, rad counter-clockwise from east); a robot's frame has
/// x forward and y left. Host code: it allocates and throws std::invalid_argument on input it
/// cannot use.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "odocal/sim/maze.hpp"
#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::host::walls {

/// From a cell's centre to the face of any of its walls, mm (half the pitch less half a wall).
inline constexpr double face_from_centre_mm =
    sim::cell_pitch_mm / 2.0 - sim::wall_thickness_mm / 2.0;

/// Sensors of the usual mouse, by index (sim::SensorPlace's order).
inline constexpr std::size_t left_front = 0u;
inline constexpr std::size_t left_diagonal = 1u;
inline constexpr std::size_t right_diagonal = 2u;
inline constexpr std::size_t right_front = 3u;
inline constexpr std::size_t sensor_count = 4u;

/// One sensor's learnt response: lit = a · cos(φ)^p / d².
struct SensorResponse {
  double a_counts_mm2 = 6.0e6;
  double incidence_power = 1.0;
};

/// The robot's sensors: where the robot's drawing puts them, and their learnt responses.
struct SensorSet {
  std::array<sim::SensorMount, sensor_count> mounts{};
  std::array<SensorResponse, sensor_count> responses{};
};

/// The usual mouse's mounts (sim::WallSensorLayout's) with the nominal response.
[[nodiscard]] SensorSet usual_mouse_sensors();

/// The light `mount` sees from the flat face {q : n·q = offset_mm}, n the unit vector at
/// `normal_rad` (pointing from the robot towards the face), with the robot at `robot` in the same
/// frame; 0 when the sensor's axis points away from the face or starts behind it.
[[nodiscard]] double lit_from_face(const SensorResponse& response, const sim::SensorMount& mount,
                                   const sim::MazePose& robot, double normal_rad, double offset_mm);

/// Where the axis of `mount` meets the face {q : n·q = offset_mm}: its distance along the face's
/// direction n rotated +90° (mm; with the face ahead, n = +x, it is the y of the point met), for a
/// robot at `robot`. NaN when the axis does not meet the face ahead.
[[nodiscard]] double point_on_face(const sim::SensorMount& mount, const sim::MazePose& robot,
                                   double normal_rad, double offset_mm);

/// What a reading's error is made of, as relative errors of lit (σ of ln lit).
struct ReadingNoise {
  /// σ of one reading above ambient, counts (two conversions of the usual mouse's 6 counts).
  double sigma_counts = 8.5;
  /// Each sensor's learnt strength's error, taken as its own (not shared with the other sensor,
  /// the cautious side for a heading): the start cell's three walls' mean reflectivity,
  /// 0.05 / √3 / √3.
  double own_strength_relative = 0.0167;
  /// Shared by both readings of one face: its reflectivity, uniform in 1 ± 5 %: 0.05 / √3.
  double common_relative = 0.0289;
};

/// (a) A wall ahead seen by both front sensors.
struct FrontWall {
  bool valid = false;        ///< both readings usable and the solution converged
  double distance_mm = 0.0;  ///< from the robot's origin to the face, along the face's normal
  double heading_rad = 0.0;  ///< the robot's heading from the face's normal, counter-clockwise
  /// Predicted σ of each, the noise carried through the inverse of the 2x2 sensitivity at the
  /// solution: the heading is the two readings' imbalance over the sensors' 60 mm, so its σ grows
  /// with the square of the distance (and the ADC's noise with it): about 0.6° at 90 mm, 1.8° at
  /// 150 mm for the usual mouse. Refuse a heading whose σ is more than the use can bear.
  double distance_sd_mm = 0.0;
  double heading_sd_rad = 0.0;
};

/// (a) Solves the front sensors' two readings (counts above ambient) for the wall's distance and
/// the heading: the face is taken flat and seen by both sensors. Readings below `min_lit_counts`
/// or at full scale give valid = false. `noise` gives the predicted σ.
[[nodiscard]] FrontWall observe_front_wall(const SensorSet& sensors, double lit_left_front,
                                           double lit_right_front, double min_lit_counts = 100.0,
                                           const ReadingNoise& noise = {});

/// (b) A corridor walled on both sides seen by the two diagonals.
struct CorridorPose {
  bool valid = false;
  double offset_mm = 0.0;    ///< the robot's origin from the corridor's centre line, + to the left
  double heading_rad = 0.0;  ///< from the corridor's direction, counter-clockwise (as given)
  double mismatch = 0.0;     ///< ln(left) − ln(right) model-minus-measured at the solution
};

/// (b) Solves the diagonals' two readings for the lateral offset in a corridor whose faces stand
/// `half_width_mm` either side of its centre line (84 mm in a standard maze), the robot's heading
/// from the corridor given. The heading cannot come from the same two readings: to first order
/// a turn towards one side and a step towards it change both diagonals alike (the usual mouse is
/// symmetric), so it comes from the offset's change along the run (fit_corridor_line) or from a
/// front wall.
[[nodiscard]] CorridorPose observe_corridor(const SensorSet& sensors, double lit_left_diagonal,
                                            double lit_right_diagonal, double heading_rad = 0.0,
                                            double half_width_mm = face_from_centre_mm,
                                            double min_lit_counts = 100.0);

/// One sample of a turn in place: the encoders' turn coordinate (right wheel's counts minus the
/// left's, so that it grows turning counter-clockwise) and the four sensors' readings above
/// ambient.
struct TurnSample {
  double turn_counts = 0.0;
  std::array<double, sensor_count> lit_counts{};
};

/// What is known before the turn: the start cell, roughly how the owner put the robot down, and
/// the nominal radians per turn count (from the nominal wheel diameter and wheelbase).
struct TurnSetup {
  std::uint32_t column = 0u;
  std::uint32_t row = 0u;
  double start_heading_rad = 0.0;
  double radians_per_count = 0.0;
  /// Where the robot is thought to stand from the cell's centre, mm (locate_by_turn's start).
  double offset_x_mm = 0.0;
  double offset_y_mm = 0.0;
  /// locate_by_turn: whether the look fits its own angle per count (else radians_per_count holds:
  /// a rate known better from the calibration's three walls than from a corner's two).
  bool fit_rate = true;
};

/// The turn's fit: the sensors learnt, where the robot turned and the angle per turn count.
struct TurnCalibration {
  SensorSet sensors{};
  double centre_x_mm = 0.0;  ///< the centre of the turn, maze frame
  double centre_y_mm = 0.0;
  double start_heading_rad = 0.0;  ///< the heading at turn_counts = 0
  /// (c) The angle turned per turn count, from the walls (no wheelbase in it).
  double radians_per_count = 0.0;
  /// Predicted σ of the four above, from the noise model given to calibrate_from_turn: the fit's
  /// covariance (JᵀJ)⁻¹ JᵀΣJ (JᵀJ)⁻¹ at the solution, Σ each reading's ADC noise and each face's
  /// reflectivity shared by all the readings of that face. The centre's are not yet checked
  /// against the truth (the study found centre_x_sd_mm far too small for some mice).
  double centre_x_sd_mm = 0.0;
  double centre_y_sd_mm = 0.0;
  double start_heading_sd_rad = 0.0;
  double radians_per_count_sd = 0.0;
  double rms_log_residual = 0.0;  ///< of the readings used, ln(measured / model)
  std::size_t readings_used = 0u;
  std::uint32_t iterations = 0u;
};

/// Fits a turn in place (at least one full turn recommended) in the start cell of `maze`: the
/// centre, the start heading, the angle per count, each sensor's a and the shared p, by
/// Levenberg-Marquardt on ln(lit), the model cast into `maze` from the sensors' `mounts`. Uses the
/// readings from 150 counts up to below full scale whose axis meets a face less than 160 mm away.
/// Throws std::invalid_argument when fewer than 20 readings per sensor are usable. `noise` (its
/// sigma_counts and common_relative, a face's reflectivity) gives the predicted σ.
[[nodiscard]] TurnCalibration calibrate_from_turn(
    const sim::Maze& maze, const TurnSetup& setup,
    const std::array<sim::SensorMount, sensor_count>& mounts,
    const std::vector<TurnSample>& samples, const ReadingNoise& noise = {});

/// Where a look found the robot: the centre of its turn and its heading when the look began.
struct TurnLocation {
  double centre_x_mm = 0.0;  ///< maze frame
  double centre_y_mm = 0.0;
  double start_heading_rad = 0.0;  ///< at turn_counts = 0
  double radians_per_count = 0.0;  ///< this turn's own (its slip in it)
  /// Predicted σ from the noise model (as TurnCalibration's).
  double centre_x_sd_mm = 0.0;
  double centre_y_sd_mm = 0.0;
  double start_heading_sd_rad = 0.0;
  double rms_log_residual = 0.0;
  std::size_t readings_used = 0u;
  std::uint32_t iterations = 0u;
};

/// A look: a turn in place (a full turn or more) in any cell whose walls fix a position (two
/// walls at right angles at least), fitted with the sensors already learnt (`sensors`, from
/// calibrate_from_turn): the centre, the heading at its start and its angle per count. `setup`
/// gives the cell, where in it the robot is thought to be, and the heading and angle per count
/// expected. Throws std::invalid_argument when fewer than two sensors see walls the model
/// explains (the robot is not where it was thought to be, or the cell has too few walls).
[[nodiscard]] TurnLocation locate_by_turn(const sim::Maze& maze, const TurnSetup& setup,
                                          const SensorSet& sensors,
                                          const std::vector<TurnSample>& samples,
                                          const ReadingNoise& noise = {});

/// (d) One sample of a straight run along a corridor: the distance run by the encoders at the
/// nominal wheel scale (mm) and the four readings above ambient.
struct RunSample {
  double travel_mm = 0.0;
  std::array<double, sensor_count> lit_counts{};
};

/// (d) Where a diagonal's wall began or ended under the robot.
struct WallEdge {
  double travel_mm = 0.0;  ///< encoder distance at the edge (midway between the two samples)
  bool falling = true;     ///< the wall ended (true) or began
  std::size_t sensor = 0u;
};

/// (d) The edges a diagonal sensor saw: its reading crossing `threshold_counts` between two
/// samples (travel increasing), with a hysteresis of ±20 % of the threshold against noise.
[[nodiscard]] std::vector<WallEdge> find_wall_edges(const std::vector<RunSample>& samples,
                                                    std::size_t sensor, double threshold_counts);

/// How far ahead of the robot's origin, along the corridor, a diagonal's axis meets its side
/// face, for a robot at `offset_mm` and `heading_rad` in a corridor of `half_width_mm` (mm).
[[nodiscard]] double look_ahead_mm(const sim::SensorMount& mount, double offset_mm,
                                   double heading_rad, double half_width_mm = face_from_centre_mm);

/// (b) Whether the axis of `mount`, from the pose `believed` the robot holds of itself (maze
/// frame), meets the face of a wall of `maze` (the robot's map) at least `margin_mm` clear of the
/// posts at its ends. Near a post the axis may meet the post's end face beside a gap (for a
/// diagonal the incidence is then 50° instead of 40°: the reading falls by cos 50° / cos 40° ≈ 0.84
/// at about the same distance, 3 mm of offset) or, through a gap, a face far beyond: the flat-face
/// model of observe_corridor describes neither. `margin_mm` should cover the error of `believed`
/// along the wall (a mouse knows it from the wall edges it has passed).
[[nodiscard]] bool on_wall_face(const sim::Maze& maze, const sim::SensorMount& mount,
                                const sim::MazePose& believed, double margin_mm);

/// (d) The position along a corridor where a wall ends (falling) or begins, mm from the start of
/// the cell boundary `boundary_mm`: the post's far or near face.
[[nodiscard]] double edge_face_mm(double boundary_mm, bool falling);

/// (d) The face edge of the kind `falling` nearest to `predicted_mm` (a position along the
/// corridor, mm from a cell boundary line at 0): how an edge is matched to the maze's plan.
[[nodiscard]] double nearest_edge_face_mm(double predicted_mm, bool falling);

/// (b) over a straight run: the offset from the corridor's centre line as a line in the travel,
/// fitted to observe_corridor's offsets at every sample where both side walls are seen; the
/// heading is the line's slope, and the offsets are solved again with it.
struct CorridorLine {
  double offset_at_zero_mm = 0.0;
  double offset_per_travel = 0.0;  ///< mm per encoder mm (the tangent of the heading)
  double heading_rad = 0.0;        ///< atan(offset_per_travel)
  std::size_t samples_used = 0u;
  [[nodiscard]] double offset_at(double travel_mm) const {
    return offset_at_zero_mm + offset_per_travel * travel_mm;
  }
};

/// (b) Fits the line; throws std::invalid_argument with fewer than two samples seeing both walls.
[[nodiscard]] CorridorLine fit_corridor_line(const SensorSet& sensors,
                                             const std::vector<RunSample>& samples,
                                             double half_width_mm = face_from_centre_mm);

/// (d) Where the robot's origin stands along the corridor (mm, the frame of `edge_face`) when a
/// diagonal's axis passes a wall's end: a wall that ends is left at its face's corner
/// (edge_face_mm(boundary, true), on the face line); a wall that begins is met first at the
/// post's far corner (edge_face_mm(boundary, false), a wall's thickness beyond the face line),
/// where the axis starts to meet the post's end face.
[[nodiscard]] double position_at_edge_mm(const sim::SensorMount& mount, double edge_face,
                                         bool falling, double offset_mm, double heading_rad,
                                         double half_width_mm = face_from_centre_mm);

/// (d) The wheels' scale from edges at known places: travel = start + scale · true position.
struct WheelScale {
  double scale = 1.0;     ///< encoder mm per true mm (the nominal diameter's error, 1 + ε)
  double start_mm = 0.0;  ///< travel at true position 0
  double residual_sd_mm = 0.0;
  std::size_t edges = 0u;
};

/// (d) Least-squares line through (true_position_mm[i], travel_mm[i]) of at least two edges at
/// different places. Throws std::invalid_argument otherwise.
[[nodiscard]] WheelScale fit_wheel_scale(const std::vector<double>& true_position_mm,
                                         const std::vector<double>& travel_mm);

}  // namespace odocal::host::walls
