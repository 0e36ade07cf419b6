#include "odocal/drive/motion_executor.hpp"

#include <cmath>
#include <numbers>

#include "odocal/name_list.hpp"

namespace odocal::drive {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kMaxPathLength_m = 20.0f;

// Out of line: two paths check it.
[[gnu::noinline]] bool valid_length(float length_m) {
  return std::isfinite(length_m) && length_m > 0.0f && length_m <= kMaxPathLength_m;
}

float sign_of(float value) {
  return value < 0.0f ? -1.0f : 1.0f;
}

// The least speed a segment runs at before its end: 2 % of cruise, but never so slow that a wheel
// sees fewer than one encoder edge per `kCreepEdgePeriod_s` (the wheel loop would have no speed
// feedback and hunt against dry friction with a coarse encoder); at most half the cruise speed.
constexpr float kCreepEdgePeriod_s = 0.02f;

// Distance over which a line or an arc steers a heading error away, m.
constexpr float kSteerDistance_m = 0.2f;

float creep_speed(const DriveConfig& limits, bool by_distance, float cruise) {
  const float wheel_radps = 2.0f * kPi / (limits.counts_per_rev * kCreepEdgePeriod_s);
  const float diameter_m = limits.wheel_diameter_mm * 1e-3f;
  // Line: v = ω_wheel·D/2. Turn in place: each wheel moves ω·b/2, so ω = ω_wheel·D/b.
  const float edge_limited = by_distance ? wheel_radps * 0.5f * diameter_m
                                         : wheel_radps * diameter_m / (limits.wheelbase_mm * 1e-3f);
  const float creep = edge_limited > 0.02f * cruise ? edge_limited : 0.02f * cruise;
  return creep < 0.5f * cruise ? creep : 0.5f * cruise;
}

// Appends `sides` legs of `side_m`, each followed by a turn in place of `turn_rad` (a regular
// polygon when the turns add up to a full turn). Out of line: three paths share one copy.
[[gnu::noinline]] void push_polygon(Path& path, int sides, float side_m, float turn_rad) {
  for (int side = 0; side < sides; ++side) {
    path.push(Segment{side_m, 0.0f});
    path.push(Segment{0.0f, turn_rad});
  }
}

}  // namespace

const char* path_name(PathId id) {
  // In PathId's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char names[] = "none\0umbmark-cw\0umbmark-ccw\0line\0unseen\0drive";
  static_assert(nul_count(names) == static_cast<std::size_t>(PathId::drive) + 1u,
                "one name per PathId, in its order");
  const auto n = static_cast<unsigned>(id);
  return name_at(names, n <= static_cast<unsigned>(PathId::drive) ? n : 0u);
}

bool Path::push(const Segment& segment) {
  if (count >= capacity) {
    return false;
  }
  segments[count] = segment;
  ++count;
  return true;
}

Path make_umbmark_square(bool clockwise, float side_m) {
  Path path;
  if (!valid_length(side_m)) {
    return path;
  }
  path.id = clockwise ? PathId::umbmark_cw : PathId::umbmark_ccw;
  push_polygon(path, 4, side_m, clockwise ? -0.5f * kPi : 0.5f * kPi);
  return path;
}

Path make_line(float length_m) {
  Path path;
  if (!valid_length(length_m)) {
    return path;
  }
  path.id = PathId::line;
  path.push(Segment{length_m, 0.0f});
  return path;
}

Path make_unseen_path() {
  Path path;
  path.id = PathId::unseen;
  push_polygon(path, 4, 1.0f, 0.5f * kPi);         // 100 cm square, left turns
  push_polygon(path, 3, 1.0f, 2.0f * kPi / 3.0f);  // 100 cm equilateral triangle, left turns
  path.push(Segment{0.8f * kPi, kPi});             // 80 cm-radius left semicircle
  return path;
}

void MotionExecutor::start(const Path& path, const Odometry& odometry) {
  load(path);
  start_loaded(odometry);
}

void MotionExecutor::load(const Path& path) {
  cancel();
  path_ = path;
}

void MotionExecutor::start_loaded(const Odometry& odometry) {
  index_ = 0u;
  busy_ = path_.count > 0u;
  settling_ = false;
  speed_ = 0.0f;
  heading_goal_rad_ = odometry.rotation_rad();
  if (busy_) {
    begin_segment(odometry);
  }
}

void MotionExecutor::cancel() {
  busy_ = false;
  settling_ = false;
  speed_ = 0.0f;
}

void MotionExecutor::begin_segment(const Odometry& odometry) {
  start_distance_m_ = odometry.distance_m();
  // Headings are planned from the path's start, not from where the last segment ended: what a
  // turn over- or undershot is made good by the segments after it instead of adding up.
  start_rotation_rad_ = heading_goal_rad_;
  heading_goal_rad_ += path_.segments[index_].angle_rad;
  speed_ = 0.0f;
  settling_ = false;
  settle_s_ = 0.0f;
}

Twist MotionExecutor::update(const Odometry& odometry, const DriveConfig& limits, float dt_s) {
  if (!busy_) {
    return Twist{};
  }
  if (settling_) {
    settle_s_ += dt_s;
    if (settle_s_ * 1000.0f >= limits.settle_ms) {
      ++index_;
      if (index_ >= path_.count) {
        busy_ = false;
        return Twist{};
      }
      begin_segment(odometry);
    } else {
      return Twist{};
    }
  }

  const Segment& segment = path_.segments[index_];
  const bool by_distance = segment.distance_m != 0.0f;
  const float target = by_distance ? std::fabs(segment.distance_m) : std::fabs(segment.angle_rad);
  const float direction = by_distance ? sign_of(segment.distance_m) : sign_of(segment.angle_rad);
  const float progress = direction * (by_distance ? odometry.distance_m() - start_distance_m_
                                                  : odometry.rotation_rad() - start_rotation_rad_);
  const float remaining = target - progress;
  if (remaining <= 0.0f) {
    // Odometry says the segment is covered: command standstill and settle.
    settling_ = true;
    settle_s_ = 0.0f;
    speed_ = 0.0f;
    return Twist{};
  }

  const float cruise = by_distance ? limits.v_max_mps : limits.w_max_radps;
  const float accel = by_distance ? limits.accel_mps2 : limits.alpha_radps2;
  // Trapezoidal profile on what remains: accelerate, cruise, and brake so the speed reaches
  // zero at the end (v² = 2·a·remaining); a small creep speed guarantees the end is reached.
  float speed = speed_ + accel * dt_s;
  const float braking = std::sqrt(2.0f * accel * remaining);
  if (speed > braking) {
    speed = braking;
  }
  if (speed > cruise) {
    speed = cruise;
  }
  const float creep = creep_speed(limits, by_distance, cruise);
  if (speed < creep) {
    speed = creep;
  }
  speed_ = speed;

  if (!by_distance) {
    return Twist{0.0f, direction * speed};
  }
  // Lines and arcs steer toward the heading the path has at this point (the plan's heading where
  // the segment began plus its share of the arc's angle): the steering gain is the speed over a
  // fixed distance, so a heading error decays over kSteerDistance_m of travel at any speed.
  const float v = direction * speed;
  const float planned = start_rotation_rad_ + segment.angle_rad * (progress / target);
  const float steer = (planned - odometry.rotation_rad()) * speed * (1.0f / kSteerDistance_m);
  return Twist{v, v * segment.angle_rad / segment.distance_m + steer};
}

}  // namespace odocal::drive
