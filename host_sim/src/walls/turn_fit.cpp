// (c) and the sensors' calibration: a turn in place in the start cell fitted to the maze's known
// walls. Levenberg-Marquardt on ln(lit) with numerical derivatives, grown from the start of the
// turn to its end so that the angle per count, still poorly known at first, is pinned by the
// first walls before the later ones are used.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "dense_solve.hpp"
#include "odocal/host/walls.hpp"

namespace odocal::host::walls {

namespace {

// Parameters: centre x, centre y, start heading, rad per count, p, ln a of each sensor.
constexpr std::size_t turn_parameters = 5u + sensor_count;
using TurnParameters = std::array<double, turn_parameters>;

constexpr double min_turn_lit_counts = 150.0;
constexpr double max_turn_lit_counts = 3800.0;
constexpr double max_turn_distance_mm = 160.0;
// A reading this far from the model (in ln) is taken for a ray near a corner or an edge.
constexpr double max_log_residual = 0.35;
constexpr std::size_t min_readings_per_sensor = 20u;
// A look's reading's ln error (ADC noise and the model's misfit: the looks' residual, about 0.02),
// against which a face's reflectivity prior is weighed (TurnProblem::face_weight).
constexpr double look_reading_sigma = 0.02;

struct TurnReading {
  std::size_t sample = 0u;
  std::size_t sensor = 0u;
  double log_lit = 0.0;
};

struct TurnProblem {
  const sim::Maze& maze;
  const std::array<sim::SensorMount, sensor_count>& mounts;
  const std::vector<TurnSample>& samples;
  /// The parameters the fit moves (the others stay as given: a look with the sensors known).
  std::array<bool, turn_parameters> free{true, true, true, true, true, true, true, true, true};
  /// A look: each face's or post's reflectivity (ln, one per surface the readings meet) fitted
  /// with the pose, drawn towards 0 by its prior: face_weight = (σ of a reading / σ of a face)²,
  /// 0 for none (the calibration: the start cell's faces are in the strengths).
  double face_weight = 0.0;
};

// The model's ln(lit) for one reading, false when the axis meets nothing close.
bool model_log_lit(const TurnProblem& problem, const TurnParameters& q, const TurnReading& reading,
                   double& log_lit, std::uint32_t* surface = nullptr) {
  const double heading = q[2] + q[3] * problem.samples[reading.sample].turn_counts;
  const sim::SensorMount& mount = problem.mounts[reading.sensor];
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  const double x = q[0] + c * mount.x_mm - s * mount.y_mm;
  const double y = q[1] + s * mount.x_mm + c * mount.y_mm;
  const sim::RayHit hit = problem.maze.cast(x, y, heading + mount.yaw_rad, max_turn_distance_mm);
  if (hit.kind == sim::SurfaceKind::none || !(hit.distance_mm > 1.0)) {
    return false;
  }
  const double cos_incidence = std::cos(hit.incidence_rad);
  if (!(cos_incidence > 0.2)) {
    return false;
  }
  if (surface != nullptr) {
    *surface = hit.surface;
  }
  log_lit =
      q[5u + reading.sensor] + q[4] * std::log(cos_incidence) - 2.0 * std::log(hit.distance_mm);
  return true;
}

// The readings the fit uses at `q`, among the samples up to `last_sample`.
std::vector<TurnReading> select_readings(const TurnProblem& problem, const TurnParameters& q,
                                         std::size_t last_sample, bool check_residual) {
  std::vector<TurnReading> readings;
  for (std::size_t j = 0u; j <= last_sample; ++j) {
    for (std::size_t i = 0u; i < sensor_count; ++i) {
      const double lit = problem.samples[j].lit_counts[i];
      if (!(lit >= min_turn_lit_counts && lit < max_turn_lit_counts)) {
        continue;
      }
      const TurnReading reading{j, i, std::log(lit)};
      double model = 0.0;
      if (!model_log_lit(problem, q, reading, model)) {
        continue;
      }
      if (check_residual && std::fabs(reading.log_lit - model) > max_log_residual) {
        continue;
      }
      readings.push_back(reading);
    }
  }
  return readings;
}

// Residuals (measured − model); a reading the model no longer sees weighs as the cut-off. With
// face offsets (TurnProblem::face_weight), each surface's ln reflectivity is solved for at `q`
// (the mean of its readings' residuals shrunk by the prior: variable projection) and taken out;
// the second half of the vector is the prior's share of each reading, so that the sum of squares
// is the readings' plus face_weight times the offsets'.
std::vector<double> residuals(const TurnProblem& problem, const TurnParameters& q,
                              const std::vector<TurnReading>& readings) {
  const bool faces = problem.face_weight > 0.0;
  std::vector<double> out(faces ? 2u * readings.size() : readings.size(), 0.0);
  std::vector<std::uint32_t> surface_of(readings.size(), UINT32_MAX);
  for (std::size_t k = 0u; k < readings.size(); ++k) {
    double model = 0.0;
    std::uint32_t surface = UINT32_MAX;
    const bool seen = model_log_lit(problem, q, readings[k], model, &surface);
    out[k] = seen ? readings[k].log_lit - model : max_log_residual;
    surface_of[k] = seen ? surface : UINT32_MAX;
  }
  if (!faces) {
    return out;
  }
  std::vector<std::pair<std::uint32_t, std::pair<double, double>>> sums;  // surface: Σr, n
  for (std::size_t k = 0u; k < readings.size(); ++k) {
    if (surface_of[k] == UINT32_MAX) {
      continue;
    }
    auto it = std::find_if(sums.begin(), sums.end(),
                           [&](const auto& entry) { return entry.first == surface_of[k]; });
    if (it == sums.end()) {
      sums.push_back({surface_of[k], {0.0, 0.0}});
      it = sums.end() - 1;
    }
    it->second.first += out[k];
    it->second.second += 1.0;
  }
  for (std::size_t k = 0u; k < readings.size(); ++k) {
    if (surface_of[k] == UINT32_MAX) {
      continue;
    }
    const auto it = std::find_if(sums.begin(), sums.end(),
                                 [&](const auto& entry) { return entry.first == surface_of[k]; });
    const double n = it->second.second;
    const double offset = it->second.first / (n + problem.face_weight);
    out[k] -= offset;
    out[readings.size() + k] = std::sqrt(problem.face_weight / n) * offset;
  }
  return out;
}

double sum_of_squares(const std::vector<double>& r) {
  double sum = 0.0;
  for (const double value : r) {
    sum += value * value;
  }
  return sum;
}

// Numerical derivative steps, per parameter.
TurnParameters derivative_steps(const TurnParameters& q) {
  TurnParameters steps{};
  steps[0] = 1e-3;
  steps[1] = 1e-3;
  steps[2] = 1e-6;
  steps[3] = 1e-6 * std::fabs(q[3]) + 1e-12;
  steps[4] = 1e-5;
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    steps[5u + i] = 1e-5;
  }
  return steps;
}

// d(model)/dq for every reading, by parameter (numerical, forward differences).
using TurnJacobian = std::array<std::vector<double>, turn_parameters>;

TurnJacobian turn_jacobian(const TurnProblem& problem, const TurnParameters& q,
                           const std::vector<TurnReading>& readings, const std::vector<double>& r) {
  const TurnParameters steps = derivative_steps(q);
  TurnJacobian jacobian;
  for (std::size_t p = 0u; p < turn_parameters; ++p) {
    jacobian[p].assign(r.size(), 0.0);
    if (!problem.free[p]) {
      continue;
    }
    TurnParameters moved = q;
    moved[p] += steps[p];
    const std::vector<double> r_moved = residuals(problem, moved, readings);
    for (std::size_t k = 0u; k < r.size(); ++k) {
      jacobian[p][k] = -(r_moved[k] - r[k]) / steps[p];
    }
  }
  return jacobian;
}

using TurnMatrix = std::array<std::array<double, turn_parameters>, turn_parameters>;

// The fit's covariance from the noise model (the sandwich of least squares, ln lit unweighted):
// C = A⁻¹ B A⁻¹, A = JᵀJ, B = Σ_k σ_k² j_k j_kᵀ (each reading's ADC noise, σ_k = σ / lit_k) +
// σ_face² Σ_s g_s g_sᵀ (one reflectivity per face or post s shared by its readings, g_s the sum of
// their rows). A look, which fits each face's reflectivity (TurnProblem::face_weight), has no
// face term: its prior's rows join A, and B with the reading σ they were weighed against. Empty
// (all zero) when A is singular.
TurnMatrix turn_covariance(const TurnProblem& problem, const TurnParameters& q,
                           const std::vector<TurnReading>& readings, const ReadingNoise& noise) {
  const std::vector<double> r = residuals(problem, q, readings);
  const TurnJacobian jacobian = turn_jacobian(problem, q, readings, r);
  TurnMatrix a{};
  TurnMatrix b{};
  std::vector<std::pair<std::uint32_t, TurnParameters>> faces;
  // With face offsets (a look) the residuals' second half is their prior: rows of A, and of B
  // with the reading σ the prior was weighed against; the faces are then in the fit, not in B.
  const bool fitted_faces = problem.face_weight > 0.0;
  for (std::size_t k = readings.size(); k < r.size(); ++k) {
    const double sigma2 = look_reading_sigma * look_reading_sigma;
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      for (std::size_t m = 0u; m < turn_parameters; ++m) {
        a[p][m] += jacobian[p][k] * jacobian[m][k];
        b[p][m] += sigma2 * jacobian[p][k] * jacobian[m][k];
      }
    }
  }
  for (std::size_t k = 0u; k < readings.size(); ++k) {
    TurnParameters row{};
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      row[p] = jacobian[p][k];
    }
    const double sigma = noise.sigma_counts / std::exp(readings[k].log_lit);
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      for (std::size_t m = 0u; m < turn_parameters; ++m) {
        a[p][m] += row[p] * row[m];
        b[p][m] += sigma * sigma * row[p] * row[m];
      }
    }
    double model = 0.0;
    std::uint32_t surface = 0u;
    static_cast<void>(model_log_lit(problem, q, readings[k], model, &surface));
    auto face = std::find_if(faces.begin(), faces.end(),
                             [&](const auto& entry) { return entry.first == surface; });
    if (face == faces.end()) {
      faces.push_back({surface, TurnParameters{}});
      face = faces.end() - 1;
    }
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      face->second[p] += row[p];
    }
  }
  for (std::size_t p = 0u; p < turn_parameters; ++p) {
    a[p][p] += problem.free[p] ? 0.0 : 1.0;  // a fixed parameter: no variance of its own
  }
  const double face_variance = fitted_faces ? 0.0 : noise.common_relative * noise.common_relative;
  for (const auto& [surface, g] : faces) {
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      for (std::size_t m = 0u; m < turn_parameters; ++m) {
        b[p][m] += face_variance * g[p] * g[m];
      }
    }
  }
  // A⁻¹ column by column, then A⁻¹ B A⁻¹.
  TurnMatrix inverse{};
  for (std::size_t col = 0u; col < turn_parameters; ++col) {
    TurnParameters unit{};
    unit[col] = 1.0;
    if (!solve_dense(a, unit)) {
      return TurnMatrix{};
    }
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      inverse[p][col] = unit[p];
    }
  }
  TurnMatrix product{};
  for (std::size_t p = 0u; p < turn_parameters; ++p) {
    for (std::size_t m = 0u; m < turn_parameters; ++m) {
      for (std::size_t k = 0u; k < turn_parameters; ++k) {
        product[p][m] += inverse[p][k] * b[k][m];
      }
    }
  }
  TurnMatrix covariance{};
  for (std::size_t p = 0u; p < turn_parameters; ++p) {
    for (std::size_t m = 0u; m < turn_parameters; ++m) {
      for (std::size_t k = 0u; k < turn_parameters; ++k) {
        covariance[p][m] += product[p][k] * inverse[k][m];
      }
    }
  }
  return covariance;
}

// Levenberg-Marquardt on the readings chosen; returns the iterations taken.
std::uint32_t levenberg_marquardt(const TurnProblem& problem,
                                  const std::vector<TurnReading>& readings, TurnParameters& q) {
  double lambda = 1e-3;
  std::vector<double> r = residuals(problem, q, readings);
  double cost = sum_of_squares(r);
  std::uint32_t iteration = 0u;
  for (; iteration < 40u; ++iteration) {
    const TurnJacobian jacobian = turn_jacobian(problem, q, readings, r);
    std::array<std::array<double, turn_parameters>, turn_parameters> normal{};
    TurnParameters gradient{};
    for (std::size_t p = 0u; p < turn_parameters; ++p) {
      for (std::size_t k = 0u; k < r.size(); ++k) {
        gradient[p] += jacobian[p][k] * r[k];
      }
      for (std::size_t m = 0u; m <= p; ++m) {
        double sum = 0.0;
        for (std::size_t k = 0u; k < r.size(); ++k) {
          sum += jacobian[p][k] * jacobian[m][k];
        }
        normal[p][m] = sum;
        normal[m][p] = sum;
      }
    }
    bool improved = false;
    while (!improved && lambda < 1e8) {
      auto damped = normal;
      TurnParameters step = gradient;
      for (std::size_t p = 0u; p < turn_parameters; ++p) {
        damped[p][p] += problem.free[p] ? lambda * (normal[p][p] + 1e-12) : 1.0;
      }
      if (!solve_dense(damped, step)) {
        lambda *= 10.0;
        continue;
      }
      TurnParameters trial = q;
      for (std::size_t p = 0u; p < turn_parameters; ++p) {
        trial[p] += step[p];
      }
      const std::vector<double> r_trial = residuals(problem, trial, readings);
      const double trial_cost = sum_of_squares(r_trial);
      if (trial_cost < cost) {
        const double drop = cost - trial_cost;
        q = trial;
        r = r_trial;
        cost = trial_cost;
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
        if (drop < 1e-10 * (1.0 + cost)) {
          return iteration + 1u;
        }
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) {
      break;
    }
  }
  return iteration;
}

// Each sensor's ln a given the rest: the median of ln(lit) − (model without a).
void initial_strengths(const TurnProblem& problem, TurnParameters& q, std::size_t last_sample,
                       std::size_t min_readings) {
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    q[5u + i] = 0.0;
  }
  const std::vector<TurnReading> readings = select_readings(problem, q, last_sample, false);
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    std::vector<double> offsets;
    for (const TurnReading& reading : readings) {
      double model = 0.0;
      if (reading.sensor == i && model_log_lit(problem, q, reading, model)) {
        offsets.push_back(reading.log_lit - model);
      }
    }
    if (offsets.size() < min_readings) {
      throw std::invalid_argument("calibrate_from_turn: sensor " + std::to_string(i) +
                                  " sees too few walls in the start cell");
    }
    std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2u, offsets.end());
    q[5u + i] = offsets[offsets.size() / 2u];
  }
}

// What a turn's fit (TurnCalibration or TurnLocation) says of its solution `q`: the readings
// used and their residual, the centre, heading and rate, and their σ; returns the covariance.
template <class Fit>
TurnMatrix describe_fit(const TurnProblem& problem, const TurnParameters& q,
                        const std::vector<TurnReading>& readings, const ReadingNoise& noise,
                        Fit& out) {
  const std::vector<double> r = residuals(problem, q, readings);
  out.readings_used = readings.size();
  // The readings' own residuals (a look's second half is the faces' prior).
  double sum = 0.0;
  for (std::size_t k = 0u; k < readings.size(); ++k) {
    sum += r[k] * r[k];
  }
  out.rms_log_residual = std::sqrt(sum / static_cast<double>(readings.size()));
  out.centre_x_mm = q[0];
  out.centre_y_mm = q[1];
  out.start_heading_rad = q[2];
  out.radians_per_count = q[3];
  const TurnMatrix covariance = turn_covariance(problem, q, readings, noise);
  out.centre_x_sd_mm = std::sqrt(covariance[0][0]);
  out.centre_y_sd_mm = std::sqrt(covariance[1][1]);
  out.start_heading_sd_rad = std::sqrt(covariance[2][2]);
  return covariance;
}

}  // namespace

TurnCalibration calibrate_from_turn(const sim::Maze& maze, const TurnSetup& setup,
                                    const std::array<sim::SensorMount, sensor_count>& mounts,
                                    const std::vector<TurnSample>& samples,
                                    const ReadingNoise& noise) {
  if (samples.size() < min_readings_per_sensor || !(std::fabs(setup.radians_per_count) > 0.0)) {
    throw std::invalid_argument("calibrate_from_turn: too few samples or no nominal turn rate");
  }
  const TurnProblem problem{maze, mounts, samples};
  const sim::MazePose centre = sim::Maze::cell_centre(setup.column, setup.row);
  TurnParameters q{};
  q[0] = centre.x_mm;
  q[1] = centre.y_mm;
  q[2] = setup.start_heading_rad;
  q[3] = setup.radians_per_count;
  q[4] = 1.0;
  TurnCalibration out;
  // Grown in stages: a quarter, half, then all of the turn.
  for (const double fraction : {0.25, 0.5, 1.0}) {
    const auto last = static_cast<std::size_t>(fraction * static_cast<double>(samples.size() - 1u));
    // The early stages (part of the turn) start from fewer readings: a coarse turn (a robot
    // that stops every few degrees) has few in its first quarter.
    initial_strengths(problem, q, last,
                      fraction < 1.0 ? min_readings_per_sensor / 4u : min_readings_per_sensor);
    const std::vector<TurnReading> readings = select_readings(problem, q, last, true);
    out.iterations += levenberg_marquardt(problem, readings, q);
  }
  const std::vector<TurnReading> readings = select_readings(problem, q, samples.size() - 1u, true);
  out.iterations += levenberg_marquardt(problem, readings, q);
  const TurnMatrix covariance = describe_fit(problem, q, readings, noise, out);
  out.radians_per_count_sd = std::sqrt(covariance[3][3]);
  out.sensors.mounts = mounts;
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    out.sensors.responses[i] = SensorResponse{std::exp(q[5u + i]), q[4]};
  }
  return out;
}

TurnLocation locate_by_turn(const sim::Maze& maze, const TurnSetup& setup, const SensorSet& sensors,
                            const std::vector<TurnSample>& samples, const ReadingNoise& noise) {
  if (samples.size() < min_readings_per_sensor || !(std::fabs(setup.radians_per_count) > 0.0)) {
    throw std::invalid_argument("locate_by_turn: too few samples or no nominal turn rate");
  }
  TurnProblem problem{maze, sensors.mounts, samples};
  for (std::size_t p = 4u; p < turn_parameters; ++p) {
    problem.free[p] = false;
  }
  problem.free[3] = setup.fit_rate;
  // No spread between the faces (common_relative 0): one reflectivity for all, none fitted.
  problem.face_weight =
      noise.common_relative > 0.0 ? std::pow(look_reading_sigma / noise.common_relative, 2.0) : 0.0;
  const sim::MazePose centre = sim::Maze::cell_centre(setup.column, setup.row);
  TurnParameters q{};
  q[0] = centre.x_mm + setup.offset_x_mm;
  q[1] = centre.y_mm + setup.offset_y_mm;
  q[2] = setup.start_heading_rad;
  q[3] = setup.radians_per_count;
  q[4] = sensors.responses[0].incidence_power;
  for (std::size_t i = 0u; i < sensor_count; ++i) {
    q[5u + i] = std::log(sensors.responses[i].a_counts_mm2);
  }
  TurnLocation out;
  // Grown as the calibration's, the first stage on every reading the walls can explain.
  for (const double fraction : {0.25, 0.5, 1.0}) {
    const auto last = static_cast<std::size_t>(fraction * static_cast<double>(samples.size() - 1u));
    const std::vector<TurnReading> readings = select_readings(problem, q, last, fraction > 0.3);
    out.iterations += levenberg_marquardt(problem, readings, q);
  }
  const std::vector<TurnReading> readings = select_readings(problem, q, samples.size() - 1u, true);
  std::array<std::size_t, sensor_count> per_sensor{};
  for (const TurnReading& reading : readings) {
    ++per_sensor[reading.sensor];
  }
  std::size_t seeing = 0u;
  for (const std::size_t n : per_sensor) {
    seeing += n >= min_readings_per_sensor / 2u ? 1u : 0u;
  }
  if (seeing < 2u) {
    throw std::invalid_argument(
        "locate_by_turn: the walls around the robot explain too few "
        "readings (is it in the cell it was thought to be in?)");
  }
  out.iterations += levenberg_marquardt(problem, readings, q);
  static_cast<void>(describe_fit(problem, q, readings, noise, out));
  return out;
}

}  // namespace odocal::host::walls
