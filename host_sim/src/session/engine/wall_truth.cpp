// `--truth walls`: the walls of the maze as the session's measurement source (wall_truth.hpp).

#include "wall_truth.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace odocal::host {
namespace session {
namespace {

constexpr double kWallPi = std::numbers::pi;
constexpr double kWallDeg = kWallPi / 180.0;
/// A look's step: about 5° at the turn rate below (the robot brakes to rest after each).
constexpr double kStepRadps = 1.5;
constexpr int kStepMs = 60;
/// The calibration turns a turn and a quarter (each sensor sees the three walls at least once
/// from both sides); a look half a turn and a bit there and back (its turn coordinate ends where
/// it began, so the heading at its end is known as well as at its start, whatever the rate).
constexpr double kCalibrationTurnRad = 2.5 * kWallPi;
constexpr double kLookTurnRad = 2.0 * kWallPi + 10.0 * kWallDeg;
/// A look stops after this many steps whatever the odometry says (a wheel that does not turn).
constexpr std::size_t kMaxSteps = 400u;
/// Square-up: a heading further than this from a quarter of the maze is turned back.
constexpr double kSquareRad = 0.4 * kWallDeg;

double wrap_rad(double rad) {
  return std::remainder(rad, 2.0 * kWallPi);
}

double lit(const Reply& reply, const char* key) {
  const auto it = reply.pairs.find(key);
  return it == reply.pairs.end() ? 0.0 : reply.number(key);
}

int side_of(double heading_rad) {
  // 0 east, 1 north, 2 west, 3 south.
  const long quarter = std::lround(heading_rad / (0.5 * kWallPi));
  return static_cast<int>(((quarter % 4) + 4) % 4);
}

sim::Side maze_side(int quarter) {
  constexpr sim::Side sides[] = {sim::Side::east, sim::Side::north, sim::Side::west,
                                 sim::Side::south};
  return sides[quarter];
}

}  // namespace

Corridor corridor_from(const sim::Maze& maze, std::uint32_t column, std::uint32_t row,
                       double heading_rad) {
  const int quarter = side_of(heading_rad);
  constexpr int dx[] = {1, 0, -1, 0};
  constexpr int dy[] = {0, 1, 0, -1};
  Corridor out{0u, false, column, row};
  while (!maze.has_wall(out.end_column, out.end_row, maze_side(quarter)) &&
         out.cells < maze.width() + maze.height()) {
    out.end_column = static_cast<std::uint32_t>(static_cast<int>(out.end_column) + dx[quarter]);
    out.end_row = static_cast<std::uint32_t>(static_cast<int>(out.end_row) + dy[quarter]);
    ++out.cells;
  }
  out.end_has_side_wall =
      maze.has_wall(out.end_column, out.end_row, maze_side((quarter + 1) % 4)) ||
      maze.has_wall(out.end_column, out.end_row, maze_side((quarter + 3) % 4));
  return out;
}

WallTruth::WallTruth(RobotClient& robot, const MazeKnowledge& maze, std::ostream& log)
    : robot_(robot), maze_(maze), log_(log) {
  const sim::MazePose start = sim::Maze::cell_centre(maze.start_column, maze.start_row);
  pose_ = {start.x_mm, start.y_mm, maze.start_heading_rad};
}

double WallTruth::trial_turn_counts() {
  const Reply trial = robot_.query("trial");
  return trial.number("count_r") - trial.number("count_l");
}

double WallTruth::nominal_radians_per_count() {
  const auto get = [this](const char* name) {
    return robot_.query(std::string("get ") + name).number(name);
  };
  return kWallPi * get("wheel_diameter_mm") / get("counts_per_rev") / get("wheelbase_mm");
}

void WallTruth::wait_done(double expected_s) {
  static_cast<void>(robot_.wait_done(static_cast<int>(1000.0 * expected_s) + 5000));
}

std::vector<walls::TurnSample> WallTruth::turn_and_read(double turn_rad, bool and_back) {
  std::vector<walls::TurnSample> samples;
  // The turn coordinate: the right wheel's counts minus the left's, summed over the steps (each a
  // trial, over when the wheels stand still): raw counts, whatever the factors in force.
  double turned = 0.0;
  const double step_counts = kStepRadps * kStepMs / 1000.0 / rate_;
  // Out to turn_rad, then (and_back) back to where it began: the turn coordinate ends near 0.
  for (int leg = 0; leg < (and_back ? 2 : 1); ++leg) {
    const double goal = leg == 0 ? turn_rad / rate_ : 0.0;
    const double sign = goal - turned < 0.0 ? -1.0 : 1.0;
    const std::string step = fmt::format("drive 0 {:.4f} {}", sign * kStepRadps, kStepMs);
    bool there = false;
    for (std::size_t k = 0u; !there; ++k) {
      if (k > kMaxSteps) {
        throw std::runtime_error(fmt::format(
            "--truth walls: the robot turned only {:.0f} degrees in {} steps of a look (a wheel "
            "that does not turn? a stall?)",
            turned * rate_ / kWallDeg, kMaxSteps));
      }
      if (k > 0u || leg > 0) {
        robot_.expect_ok(step);
        wait_done(kStepMs / 1000.0);
        turned += trial_turn_counts();
      }
      const Reply walls = robot_.command("walls");
      if (!walls.ok) {
        throw std::runtime_error(
            "--truth walls: the robot's `walls` answered `" + walls.line +
            "`: it has no wall sensors (docs/maze.md); calibrate it with a tape (no --truth)");
      }
      samples.push_back({turned,
                         {lit(walls, "left_front"), lit(walls, "left_diagonal"),
                          lit(walls, "right_diagonal"), lit(walls, "right_front")}});
      // Within half a step of the goal, or past it.
      there = sign * (turned - goal) >= -0.5 * step_counts;
    }
  }
  return samples;
}

void WallTruth::calibrate() {
  log_ << "The walls: the robot learns its sensors from the start cell (" << maze_.name
       << ", cell (" << maze_.start_column << ", " << maze_.start_row
       << ")): a turn and a quarter in place, reading its four sensors every few degrees.\n";
  rate_ = nominal_radians_per_count();
  nominal_rate_ = rate_;
  const double nominal_rate = rate_;
  const std::vector<walls::TurnSample> samples = turn_and_read(kCalibrationTurnRad, false);
  const walls::TurnSetup setup{maze_.start_column, maze_.start_row, maze_.start_heading_rad, rate_};
  try {
    calibration_ = walls::calibrate_from_turn(maze_.maze, setup, maze_.mounts, samples);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("--truth walls: the start cell's walls do not explain "
                                         "what the sensors read (") +
                             e.what() +
                             "): is the robot in the start cell, facing out of it, in the maze "
                             "the session was told?");
  }
  const walls::TurnCalibration& cal = *calibration_;
  rate_ = cal.radians_per_count;
  pose_ = {cal.centre_x_mm, cal.centre_y_mm,
           wrap_rad(cal.start_heading_rad + rate_ * samples.back().turn_counts)};
  const sim::MazePose centre = sim::Maze::cell_centre(maze_.start_column, maze_.start_row);
  log_ << fmt::format(
      "  Sensors learnt from {} readings: strengths {:.2f}, {:.2f}, {:.2f}, {:.2f} x 10^6 "
      "counts mm^2 (left front, left diagonal, right diagonal, right front), incidence power "
      "{:.2f}. The robot stood {:.1f} mm east and {:.1f} mm north of the cell's centre, facing "
      "{:.2f} deg; it turns {:.4f} times what its nominal wheelbase says (seen by the walls).\n",
      cal.readings_used, cal.sensors.responses[0].a_counts_mm2 / 1e6,
      cal.sensors.responses[1].a_counts_mm2 / 1e6, cal.sensors.responses[2].a_counts_mm2 / 1e6,
      cal.sensors.responses[3].a_counts_mm2 / 1e6, cal.sensors.responses[0].incidence_power,
      cal.centre_x_mm - centre.x_mm, cal.centre_y_mm - centre.y_mm,
      cal.start_heading_rad / kWallDeg, cal.radians_per_count / nominal_rate);
  turn_by(wrap_rad(maze_.start_heading_rad - pose_.theta_rad));
  square_up();
  // Where the robot stands: a look with the sensors now known. The calibration's own centre
  // trades off against the strengths it learns at the same time (off by up to 14 mm along the
  // corridor on some mice, against the simulator); a look with them fixed is not (about 1 mm).
  static_cast<void>(look(pose_, "the calibration turn"));
}

bool WallTruth::in_start_cell() const {
  return std::floor(pose_.x_mm / sim::cell_pitch_mm) == static_cast<double>(maze_.start_column) &&
         std::floor(pose_.y_mm / sim::cell_pitch_mm) == static_cast<double>(maze_.start_row);
}

void WallTruth::turn_by(double turn_rad) {
  if (std::fabs(turn_rad) < 0.05 * kWallDeg) {
    return;
  }
  const double w = turn_rad < 0.0 ? -kStepRadps : kStepRadps;
  const int ms =
      std::max(10, static_cast<int>(std::lround(1000.0 * std::fabs(turn_rad) / kStepRadps)));
  robot_.expect_ok(fmt::format("drive 0 {:.4f} {}", w, ms));
  wait_done(ms / 1000.0);
  pose_.theta_rad = wrap_rad(pose_.theta_rad + rate_ * trial_turn_counts());
}

void WallTruth::face(double heading_rad) {
  turn_by(wrap_rad(heading_rad - pose_.theta_rad));
  square_up();
}

Motion WallTruth::turn_in_place(double turn_rad, double w_radps) {
  // The firmware turns by time at what its geometry believes: rate_ (the walls') over its
  // believed rate is how much the robot really turns per radian asked.
  const double real_per_asked = rate_ / nominal_radians_per_count();
  const double w = turn_rad < 0.0 ? -std::fabs(w_radps) : std::fabs(w_radps);
  return Motion::timed(
      0.0, w, std::round(1000.0 * std::fabs(turn_rad) / std::fabs(w_radps) / real_per_asked));
}

std::optional<Corridor> WallTruth::second_corridor(double& turn_rad) const {
  const Corridor first = calibration_corridor();
  std::optional<Corridor> best;
  for (const double side : {-0.5 * kWallPi, 0.5 * kWallPi}) {
    const Corridor k =
        corridor_from(maze_.maze, first.end_column, first.end_row, maze_.start_heading_rad + side);
    if (k.cells >= 2u && k.end_has_side_wall && (!best || k.cells > best->cells)) {
      best = k;
      turn_rad = side;
    }
  }
  return best;
}

Motion WallTruth::route_run(double cruise_mps, double spin_radps, std::vector<Motion>& then,
                            double& expected_s, std::string& what) {
  double side = 0.0;
  const Corridor first = calibration_corridor();
  const Corridor second = *second_corridor(side);
  const sim::MazePose start = sim::Maze::cell_centre(maze_.start_column, maze_.start_row);
  const sim::MazePose corner = sim::Maze::cell_centre(first.end_column, first.end_row);
  const sim::MazePose end = sim::Maze::cell_centre(second.end_column, second.end_row);
  const bool out = in_start_cell();
  // First leg aimed at the corner's centre from where the robot stands; the second leg's
  // direction from the corner to where the run ends.
  const double first_m = aim_at(first.end_column, first.end_row);
  const sim::MazePose& to = out ? end : start;
  const double second_heading = std::atan2(to.y_mm - corner.y_mm, to.x_mm - corner.x_mm);
  const double second_m = std::hypot(to.y_mm - corner.y_mm, to.x_mm - corner.x_mm) * 1e-3;
  // Slowly: a timed turn goes on a little after its time is up (the wheels' loop catching up),
  // which grows with the square of the rate: at a third of the turns' rate it is a degree or so.
  const Motion turn = turn_in_place(wrap_rad(second_heading - pose_.theta_rad), spin_radps / 3.0);
  then = {turn, Motion::line(second_m)};
  expected_s = (first_m + second_m) / cruise_mps + turn.ms / 1000.0 + 4.0;
  what = fmt::format(
      "{} the route: {:.3f} m to cell ({}, {}), a quarter turn, {:.3f} m to cell "
      "({}, {})",
      out ? "out along" : "back along", first_m, first.end_column, first.end_row, second_m,
      out ? second.end_column : maze_.start_column, out ? second.end_row : maze_.start_row);
  return Motion::line(first_m);
}

Motion WallTruth::corridor_line(std::size_t n, double cruise_mps, double& expected_s,
                                std::string& what) {
  const Corridor corridor = calibration_corridor();
  const bool up = in_start_cell();
  const bool backwards = n % 4u == 1u || n % 4u == 2u;
  const std::uint32_t column = up ? corridor.end_column : maze_.start_column;
  const std::uint32_t row = up ? corridor.end_row : maze_.start_row;
  const double length_m = aim_at(column, row, backwards);
  what = fmt::format("{} the corridor {}, {:.3f} m to the centre of cell ({}, {})",
                     up ? "up" : "back down", backwards ? "in reverse" : "forwards", length_m,
                     column, row);
  if (!backwards) {
    expected_s = length_m / cruise_mps + 2.0;
    return Motion::line(length_m);
  }
  // No `run line` in reverse: a timed drive, which brakes once its time is up (about the distance
  // its start-up took: it ends near v·t).
  const double ms = std::round(length_m / cruise_mps * 1000.0);
  expected_s = ms / 1000.0 + 2.0;
  return Motion::timed(-cruise_mps, 0.0, ms);
}

double WallTruth::aim_at(std::uint32_t column, std::uint32_t row, bool backwards) {
  const sim::MazePose target = sim::Maze::cell_centre(column, row);
  const double heading =
      std::atan2(target.y_mm - pose_.y_mm, target.x_mm - pose_.x_mm) + (backwards ? kWallPi : 0.0);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double off = wrap_rad(heading - pose_.theta_rad);
    if (std::fabs(off) < 0.5 * kSquareRad) {
      break;
    }
    turn_by(off);
  }
  return std::hypot(target.y_mm - pose_.y_mm, target.x_mm - pose_.x_mm) * 1e-3;
}

void WallTruth::square_up() {
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double quarter = 0.5 * kWallPi * std::round(pose_.theta_rad / (0.5 * kWallPi));
    const double off = quarter - pose_.theta_rad;
    if (std::fabs(off) < kSquareRad) {
      return;
    }
    // Short turns overshoot less than they undershoot: the rest is turned again.
    turn_by(off);
  }
}

sim::MazePose WallTruth::look(const sim::MazePose& guess, const std::string& why) {
  const auto column =
      static_cast<std::uint32_t>(std::clamp(std::floor(guess.x_mm / sim::cell_pitch_mm), 0.0,
                                            static_cast<double>(maze_.maze.width() - 1u)));
  const auto row =
      static_cast<std::uint32_t>(std::clamp(std::floor(guess.y_mm / sim::cell_pitch_mm), 0.0,
                                            static_cast<double>(maze_.maze.height() - 1u)));
  const sim::MazePose centre = sim::Maze::cell_centre(column, row);
  const std::vector<walls::TurnSample> samples = turn_and_read(kLookTurnRad, true);
  walls::TurnSetup setup{column, row, guess.theta_rad, rate_};
  setup.offset_x_mm = guess.x_mm - centre.x_mm;
  setup.offset_y_mm = guess.y_mm - centre.y_mm;
  // The rate the calibration's three walls gave (a look's half turn there and back pins its
  // own less well, and its end heading does not depend on it).
  setup.fit_rate = false;
  walls::TurnLocation found;
  try {
    found = walls::locate_by_turn(maze_.maze, setup, calibration_->sensors, samples);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format(
        "--truth walls: the look after {} in cell ({}, {}) does not find the walls the maze "
        "has there ({}): the robot is not where its odometry says, or the maze is not the one "
        "the session was told",
        why, column, row, e.what()));
  }
  const sim::MazePose at_start{found.centre_x_mm, found.centre_y_mm,
                               wrap_rad(found.start_heading_rad)};
  pose_ = {
      found.centre_x_mm, found.centre_y_mm,
      wrap_rad(found.start_heading_rad + found.radians_per_count * samples.back().turn_counts)};
  looks_.push_back({{"after", why},
                    {"cell", {column, row}},
                    {"x_mm", found.centre_x_mm},
                    {"y_mm", found.centre_y_mm},
                    {"theta_deg", at_start.theta_rad / kWallDeg},
                    {"x_sd_mm", found.centre_x_sd_mm},
                    {"y_sd_mm", found.centre_y_sd_mm},
                    {"theta_sd_deg", found.start_heading_sd_rad / kWallDeg},
                    {"readings", found.readings_used},
                    {"rms_log_residual", found.rms_log_residual}});
  square_up();
  return at_start;
}

SessionPose WallTruth::take(const RunRecord& run, std::size_t index, std::size_t planned) {
  if (on_floor_) {
    const SessionPose taken = tape_->take(run, index, planned);
    taped_.push_back(index);
    return taken;
  }
  if (!calibration_) {
    calibrate();  // a run before the calibration (the self-test's measured run)
  }
  const sim::MazePose start = pose_;
  const double c = std::cos(start.theta_rad);
  const double s = std::sin(start.theta_rad);
  // The heading from the run's counts (raw, unwrapped) at the rate the walls saw.
  const sim::MazePose guess{
      start.x_mm + c * run.odom.x_mm - s * run.odom.y_mm,
      start.y_mm + s * run.odom.x_mm + c * run.odom.y_mm,
      start.theta_rad + rate_ * static_cast<double>(run.count_r - run.count_l)};
  std::optional<SessionPose> tape;
  if (maze_.simulator) {
    const Reply reply = robot_.query("measure");
    if (reply.ok) {
      tape = SessionPose{reply.number("x_mm"), reply.number("y_mm"), reply.number("theta_deg")};
    }
  }
  const sim::MazePose end = look(guess, fmt::format("run {}", index + 1));
  const double dx = end.x_mm - start.x_mm;
  const double dy = end.y_mm - start.y_mm;
  SessionPose measured;
  measured.x_mm = c * dx + s * dy;
  measured.y_mm = -s * dx + c * dy;
  measured.theta_deg = wrap_rad(end.theta_rad - start.theta_rad) / kWallDeg;
  looks_.back()["run"] = index + 1;
  if (tape) {
    const std::array<double, 3> error{
        measured.x_mm - tape->x_mm, measured.y_mm - tape->y_mm,
        wrap_rad((*measured.theta_deg - *tape->theta_deg) * kWallDeg) / kWallDeg};
    errors_.push_back(error);
    looks_.back()["simulator"] = {
        {"x_mm", tape->x_mm},     {"y_mm", tape->y_mm},     {"theta_deg", *tape->theta_deg},
        {"error_x_mm", error[0]}, {"error_y_mm", error[1]}, {"error_theta_deg", error[2]}};
  }
  log_ << fmt::format(
      "  The walls: it stopped at x {:.1f} mm, y {:.1f} mm, heading {:.2f} deg "
      "(a look in cell ({}, {})).\n",
      measured.x_mm, measured.y_mm, *measured.theta_deg,
      looks_.back()["cell"][0].get<std::uint32_t>(), looks_.back()["cell"][1].get<std::uint32_t>());
  return measured;
}

void WallTruth::move_and_look(const std::string& command, double expected_s) {
  robot_.expect_ok("odom reset");
  const sim::MazePose start = pose_;
  robot_.expect_ok(command);
  wait_done(expected_s);
  const Reply odom = robot_.query("odom");
  const double c = std::cos(start.theta_rad);
  const double s = std::sin(start.theta_rad);
  const double x = odom.number("x_mm");
  const double y = odom.number("y_mm");
  const sim::MazePose guess{start.x_mm + c * x - s * y, start.y_mm + s * x + c * y,
                            start.theta_rad + rate_ * trial_turn_counts()};
  static_cast<void>(look(guess, "`" + command + "`"));
}

nlohmann::json WallTruth::wall_segments() const {
  // Each wall once: a cell's south and west sides, and the maze's north and east borders.
  nlohmann::json out = nlohmann::json::array();
  const sim::Maze& m = maze_.maze;
  const double p = sim::cell_pitch_mm;
  for (std::uint32_t c = 0; c < m.width(); ++c) {
    for (std::uint32_t r = 0; r < m.height(); ++r) {
      if (m.has_wall(c, r, sim::Side::south)) {
        out.push_back({c * p, r * p, (c + 1) * p, r * p});
      }
      if (m.has_wall(c, r, sim::Side::west)) {
        out.push_back({c * p, r * p, c * p, (r + 1) * p});
      }
      if (r + 1 == m.height() && m.has_wall(c, r, sim::Side::north)) {
        out.push_back({c * p, (r + 1) * p, (c + 1) * p, (r + 1) * p});
      }
      if (c + 1 == m.width() && m.has_wall(c, r, sim::Side::east)) {
        out.push_back({(c + 1) * p, r * p, (c + 1) * p, (r + 1) * p});
      }
    }
  }
  return out;
}

nlohmann::json WallTruth::json() const {
  nlohmann::json out = {{"maze", maze_.name},
                        {"start_cell", {maze_.start_column, maze_.start_row}},
                        {"walls_mm", wall_segments()},
                        {"looks", looks_}};
  if (!errors_.empty()) {
    // What the walls' stops got wrong against the simulator's tape, per reading kind.
    const char* kinds[] = {"x_mm", "y_mm", "theta_deg"};
    nlohmann::json against = nlohmann::json::object();
    for (std::size_t k = 0; k < 3; ++k) {
      double sum = 0.0;
      double sum2 = 0.0;
      double worst = 0.0;
      for (const auto& e : errors_) {
        sum += e[k];
        sum2 += e[k] * e[k];
        worst = std::max(worst, std::fabs(e[k]));
      }
      const double n = static_cast<double>(errors_.size());
      const double mean = sum / n;
      against[kinds[k]] = {
          {"runs", errors_.size()},
          {"mean", mean},
          {"rms", std::sqrt(sum2 / n)},
          {"sd", n > 1.0 ? std::sqrt(std::max(sum2 - n * mean * mean, 0.0) / (n - 1.0)) : 0.0},
          {"max_abs", worst}};
    }
    out["against_simulator"] = against;
  }
  if (calibration_) {
    const walls::TurnCalibration& cal = *calibration_;
    nlohmann::json sensors = nlohmann::json::array();
    for (const walls::SensorResponse& r : cal.sensors.responses) {
      sensors.push_back({{"a_counts_mm2", r.a_counts_mm2}, {"incidence_power", r.incidence_power}});
    }
    out["calibration"] = {
        {"sensors", sensors},
        {"centre_x_mm", cal.centre_x_mm},
        {"centre_y_mm", cal.centre_y_mm},
        {"start_heading_deg", cal.start_heading_rad / kWallDeg},
        {"start_heading_sd_deg", cal.start_heading_sd_rad / kWallDeg},
        // The turn per raw count over the nominal geometry's (a ratio),
        // and the turn per count itself.
        {"true_rad_per_odometry_rad", cal.radians_per_count / nominal_rate_},
        {"true_rad_per_odometry_rad_sd", cal.radians_per_count_sd / nominal_rate_},
        {"radians_per_count", cal.radians_per_count},
        {"readings", cal.readings_used},
        {"rms_log_residual", cal.rms_log_residual}};
  }
  return out;
}

}  // namespace session

}  // namespace odocal::host
