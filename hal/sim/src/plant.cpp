#include "odocal/sim/plant.hpp"

#include <cmath>
#include <numbers>

namespace odocal::sim {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;
/// Step fraction of the next edge of a wheel that has none left (real fractions are <= 1).
constexpr double no_edge = 2.0;

/// cos, sin and sin(x)/x of an angle: by their series when |x| < 0.05 (error below 1e-11, and
/// exact to double precision for the per-step angles of a driving robot), else libm.
struct Turn {
  double cos;
  double sin;
  double sinc;
};
inline Turn turn_of(double x) {
  if (std::fabs(x) < 0.05) {
    const double x2 = x * x;
    const double sinc = 1.0 - x2 * ((1.0 / 6.0) - x2 * (1.0 / 120.0));
    return Turn{1.0 - x2 * (0.5 - x2 * (1.0 / 24.0)), x * sinc, sinc};
  }
  const double s = std::sin(x);
  return Turn{std::cos(x), s, s / x};
}

/// Quadrature levels for an x4 count: A leads B when counting up (0,0)->(1,0)->(1,1)->(0,1).
void phase_levels(std::int64_t count, bool& a, bool& b) {
  const auto phase = static_cast<std::uint64_t>(count) & 3u;
  a = phase == 1u || phase == 2u;
  b = phase >= 2u;
}

}  // namespace

Plant::Plant(const RobotModel& model, std::uint64_t seed)
    : model_(model),
      ok_(check(model) == ModelError::none),
      random_(seed),
      floor_random_(Random::derive(seed, 1u)) {
  Wheel* wheels[2] = {&left_, &right_};
  const MotorModel motors[2] = {model.left_motor, model.right_motor};
  const double diameters[2] = {model.left_diameter_m, model.right_diameter_m};
  const double h = static_cast<double>(model.physics_step_ns) * 1.0e-9;
  for (int i = 0; i < 2; ++i) {
    Wheel& w = *wheels[i];
    w.motor_ = motors[i];
    if (!ok_) {
      continue;
    }
    const MotorModel& m = w.motor_;
    // J·dω/dt = (k/R)·V − (k²/R + c)·ω − τ_c·sign ω: constants of the exact step solution.
    const double damping =
        m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps;
    w.decay_ = damping / m.inertia_kgm2;
    w.torque_per_volt_ = m.k_v_per_radps / m.resistance_ohm;
    w.speed_per_torque_ = 1.0 / damping;
    w.step_factor_ = std::exp(-w.decay_ * h);
    w.step_lag_s_ = (1.0 - w.step_factor_) / w.decay_;
    w.radius_m_ = 0.5 * diameters[i];
    w.count_rad_ = two_pi / static_cast<double>(model.counts_per_rev);
    w.counts_per_rad_ = static_cast<double>(model.counts_per_rev) / two_pi;
    // Start inside a count, at a random place, so that standing still never chatters.
    w.angle_rad_ = w.count_rad_ * random_.uniform(0.1, 0.9);
    w.count_ = 0;
    bool a = false;
    bool b = false;
    phase_levels(0, a, b);
    w.a_.preset(a);
    w.b_.preset(b);
    w.slip_ratio_ = random_.normal(model.slip_sigma);
    w.slip_left_m_ = model.slip_length_m;
  }
  inverse_wheelbase_ = ok_ ? 1.0 / model.wheelbase_m : 0.0;
  arc_gap_m_ =
      ok_ && model.wheelbase_arc_m != 0.0 ? model.wheelbase_arc_m - model.wheelbase_m : 0.0;
  set_bumps(model.bump_height_m, model.bump_spacing_m);
  place();
}

void Plant::set_bumps(double height_m, double spacing_m) {
  model_.bump_height_m = height_m > 0.0 ? height_m : 0.0;
  if (spacing_m > 0.0) {
    model_.bump_spacing_m = spacing_m;
  }
  Wheel* const wheels[2] = {&left_, &right_};
  for (Wheel* w : wheels) {
    w->laid_count_ = 0u;
    w->bump_arc_m_ = 0.0;
    w->bump_chord_m_ = 0.0;
    w->bump_ratio_ = 1.0;
    if (model_.bump_height_m > 0.0 && ok_) {
      // A wheel of radius r rolling over a cable of radius c (height 2c): its centre follows an
      // arc of radius r + c over ±ψ0, cos ψ0 = (r − c)/(r + c), while the floor distance covered
      // is only the chord 4·sqrt(r·c). The wheel turns by the arc: extra rotation, less progress.
      const double r = w->radius_m_;
      const double c = 0.5 * model_.bump_height_m;
      const double psi0 = std::acos((r - c) / (r + c));
      w->bump_arc_m_ = 2.0 * (r + c) * psi0;
      w->bump_chord_m_ = 4.0 * std::sqrt(r * c);
      w->bump_ratio_ = w->bump_chord_m_ / w->bump_arc_m_;
    }
  }
  place_cables();
}

void Plant::lay_cables(bool right_wheel, double height_m, double first_m, double spacing_m,
                       std::uint32_t count) {
  set_bumps(height_m, spacing_m);
  if (model_.bump_height_m <= 0.0 || count == 0u) {
    return;
  }
  // The other wheel: one cable at a floor distance no run reaches.
  Wheel& laid = right_wheel ? right_ : left_;
  Wheel& clear = right_wheel ? left_ : right_;
  laid.laid_first_m_ = first_m > 0.0 ? first_m : 0.0;
  laid.laid_count_ = count;
  clear.laid_first_m_ = 1.0e300;
  clear.laid_count_ = 1u;
  place_cables();
}

void Plant::place_cables() {
  Wheel* const wheels[2] = {&left_, &right_};
  for (Wheel* w : wheels) {
    w->bump_left_m_ = 0.0;
    w->cables_ahead_ = w->laid_count_;
    w->bump_next_m_ = w->laid_count_ > 0u          ? w->laid_first_m_
                      : model_.bump_height_m > 0.0 ? model_.bump_spacing_m * floor_random_.uniform()
                                                   : 0.0;
  }
}

void Plant::place(const WorldPose& pose) {
  pose_ = pose;
  cos_ = std::cos(pose.theta_rad);
  sin_ = std::sin(pose.theta_rad);
  left_.speed_radps_ = 0.0;
  right_.speed_radps_ = 0.0;
  place_cables();
}

bool Plant::at_rest(double radps) const {
  return std::fabs(left_.speed_radps_) < radps && std::fabs(right_.speed_radps_) < radps;
}

WorldPose Plant::measure() {
  WorldPose m = pose_;
  m.x_m += random_.normal(model_.measure_sigma_m);
  m.y_m += random_.normal(model_.measure_sigma_m);
  m.theta_rad += random_.normal(model_.measure_heading_sigma_rad);
  return m;
}

void Plant::advance_to_ns(std::uint64_t t_ns) {
  if (!ok_) {
    if (t_ns > clock_.ns()) {
      clock_.set_ns(t_ns);
    }
    return;
  }
  while (clock_.ns() < t_ns) {
    const std::uint64_t remaining = t_ns - clock_.ns();
    const std::uint32_t dt = remaining < model_.physics_step_ns
                                 ? static_cast<std::uint32_t>(remaining)
                                 : model_.physics_step_ns;
    step(dt);
  }
}

inline void Plant::integrate_motor(Wheel& w, double dt_s, bool standard_step, double& delta_rad) {
  const MotorModel& m = w.motor_;
  const double duty = static_cast<double>(w.pwm_.duty());
  w.voltage_v_ = (w.direction_.forward() ? duty : -duty) * m.supply_v;
  const double drive_nm = w.torque_per_volt_ * w.voltage_v_;
  const double w0 = w.speed_radps_;
  double sign = 0.0;
  if (w0 == 0.0) {
    // Stuck: dry friction holds the wheel until the motor torque breaks it away.
    if (std::fabs(drive_nm) <= m.coulomb_nm) {
      delta_rad = 0.0;
      return;
    }
    sign = drive_nm > 0.0 ? 1.0 : -1.0;
  } else {
    sign = w0 > 0.0 ? 1.0 : -1.0;
  }
  // Linear between sign changes: dω/dt = a·(w_ss − ω), solved exactly over the step (constant V).
  const double a = w.decay_;
  const double w_ss = (drive_nm - m.coulomb_nm * sign) * w.speed_per_torque_;
  double e = w.step_factor_;
  double lag_s = w.step_lag_s_;
  if (!standard_step) {
    e = std::exp(-a * dt_s);
    lag_s = (1.0 - e) / a;
  }
  double w1 = w_ss + (w0 - w_ss) * e;
  delta_rad = w_ss * dt_s + (w0 - w_ss) * lag_s;
  if (w0 != 0.0 && w1 * sign < 0.0) {
    // Friction brought it to rest at t0 inside the step. It stays there unless the motor torque
    // breaks it away in the other direction for the rest of the step.
    const double t0 = -std::log(-w_ss / (w0 - w_ss)) / a;
    delta_rad = w_ss * t0 + w0 / a;
    w1 = 0.0;
    const double rest_s = dt_s - t0;
    if (rest_s > 0.0 && std::fabs(drive_nm) > m.coulomb_nm) {
      const double back = drive_nm > 0.0 ? 1.0 : -1.0;
      const double w_back = (drive_nm - m.coulomb_nm * back) * w.speed_per_torque_;
      const double e_back = std::exp(-a * rest_s);
      w1 = w_back * (1.0 - e_back);
      delta_rad += w_back * rest_s - w_back * (1.0 - e_back) / a;
    }
  }
  w.speed_radps_ = w1;
}

/// The edges one wheel owes inside a step, at evenly spaced fractions of it (the shaft angle is
/// interpolated linearly inside the step).
struct Plant::Sweep {
  Wheel* wheel;
  std::int64_t remaining;  ///< edges not yet delivered
  std::int64_t direction;  ///< +1 counting up, −1 down
  std::int64_t a_parity;   ///< count parity at which the next edge is on line A
  double next;             ///< fraction of the step at which the next edge happens
  double spacing;          ///< fraction of the step between two edges
};

bool Plant::leaves_count(const Wheel& w) {
  // floor(angle / count_rad) != count, without floor(): the shaft is inside count c exactly when
  // c <= angle·counts_per_rad < c + 1 (c + 1 is exact in a double).
  const double counts = w.angle_rad_ * w.counts_per_rad_;
  const auto count = static_cast<double>(w.count_);
  return counts < count || counts >= count + 1.0;
}

Plant::Sweep Plant::sweep_of(Wheel& w, double from) {
  Sweep s{&w, 0, 1, 0, no_edge, 0.0};
  // floor() without the libm call: truncation, one less for negative non-integers.
  const double counts = w.angle_rad_ * w.counts_per_rad_;
  auto target = static_cast<std::int64_t>(counts);
  if (static_cast<double>(target) > counts) {
    --target;
  }
  if (target == w.count_) {
    return s;
  }
  const double per_rad = 1.0 / (w.angle_rad_ - from);
  s.direction = target > w.count_ ? 1 : -1;
  s.remaining = (target - w.count_) * s.direction;
  // Gray code (see phase_levels): line A changes between an even count and the next one, B
  // between an odd one and the next. Counting down from c, the edge is the one below c.
  s.a_parity = s.direction > 0 ? 0 : 1;
  const std::int64_t boundary = s.direction > 0 ? w.count_ + 1 : w.count_;
  s.next = (static_cast<double>(boundary) * w.count_rad_ - from) * per_rad;
  s.spacing = w.count_rad_ * per_rad * static_cast<double>(s.direction);
  return s;
}

inline void Plant::fire(Sweep& s, std::uint64_t t0_ns, double dt_ns, std::int64_t last_ns,
                        std::int64_t& previous_ns) {
  // The edge's instant, rounded to the ns, inside the step and never before the previous one.
  auto offset = static_cast<std::int64_t>(s.next * dt_ns + 0.5);
  offset = offset < previous_ns ? previous_ns : (offset > last_ns ? last_ns : offset);
  previous_ns = offset;
  clock_.set_ns(t0_ns + static_cast<std::uint64_t>(offset));
  Wheel& w = *s.wheel;
  const bool line_a = (w.count_ & 1) == s.a_parity;
  w.count_ += s.direction;
  if (line_a) {  // exactly one line changes per count; only that one runs its handler
    w.a_.toggle();
  } else {
    w.b_.toggle();
  }
  s.next = --s.remaining > 0 ? s.next + s.spacing : no_edge;
}

void Plant::deliver_edges(double left_from, double right_from, std::uint64_t t0_ns,
                          std::uint32_t dt_ns) {
  Sweep sweeps[2] = {sweep_of(left_, left_from), sweep_of(right_, right_from)};
  const auto dt = static_cast<double>(dt_ns);
  const auto last = static_cast<std::int64_t>(dt_ns);
  std::int64_t previous = 0;
  for (;;) {
    // The earlier of the two wheels' next edges (the left one on a tie).
    Sweep& s = sweeps[1].next < sweeps[0].next ? sweeps[1] : sweeps[0];
    if (s.next > 1.5) {
      break;
    }
    fire(s, t0_ns, dt, last, previous);
  }
}

void Plant::deliver_wheel_edges(Wheel& wheel, double from, std::uint64_t t0_ns,
                                std::uint32_t dt_ns) {
  Sweep s = sweep_of(wheel, from);
  const auto dt = static_cast<double>(dt_ns);
  const auto last = static_cast<std::int64_t>(dt_ns);
  std::int64_t previous = 0;
  while (s.next <= 1.5) {
    fire(s, t0_ns, dt, last, previous);
  }
}

inline double Plant::ground_travel(Wheel& w, double rolled_m) {
  const double magnitude = std::fabs(rolled_m);
  if (magnitude == 0.0) {
    return 0.0;
  }
  const double floor_m = model_.bump_height_m > 0.0 ? over_cables(w, magnitude) : magnitude;
  const double ground = floor_m * (1.0 + w.slip_ratio_);
  w.slip_left_m_ -= magnitude;
  if (w.slip_left_m_ <= 0.0) {
    w.slip_ratio_ = random_.normal(model_.slip_sigma);
    w.slip_left_m_ += model_.slip_length_m;
    if (w.slip_left_m_ <= 0.0) {
      w.slip_left_m_ = model_.slip_length_m;
    }
  }
  return rolled_m < 0.0 ? -ground : ground;
}

double Plant::over_cables(Wheel& w, double rolled_m) {
  // Floor progress of the contact point (before slip, which moves the cables by ~1e-3 of their
  // spacing at most) for `rolled_m` > 0 of wheel travel, forwards or backwards alike.
  double floor_m = 0.0;
  double rolled_left = rolled_m;
  for (;;) {
    if (w.bump_left_m_ > 0.0) {
      // On a cable: the wheel turns through the arc while its contact covers only the chord.
      const double on = rolled_left < w.bump_left_m_ ? rolled_left : w.bump_left_m_;
      floor_m += on * w.bump_ratio_;
      w.bump_left_m_ -= on;
      rolled_left -= on;
      if (rolled_left <= 0.0) {
        return floor_m;
      }
    }
    if (rolled_left < w.bump_next_m_) {  // flat floor all the way
      w.bump_next_m_ -= rolled_left;
      return floor_m + rolled_left;
    }
    floor_m += w.bump_next_m_;
    rolled_left -= w.bump_next_m_;
    start_bump(w);
  }
}

void Plant::start_bump(Wheel& w) {
  ++w.bumps_;
  w.bump_left_m_ = w.bump_arc_m_;
  // The next cable lies `spacing` (± jitter) of floor after this one's start; the crossing
  // itself covers the chord. Cables closer than a chord follow each other directly.
  // Laid cables (lay_cables) are evenly spaced, and there are no more after the last one.
  const double jitter =
      (w.laid_count_ > 0u ? 0.0 : model_.bump_spacing_jitter) * floor_random_.uniform(-1.0, 1.0);
  const double next = model_.bump_spacing_m * (1.0 + jitter) - w.bump_chord_m_;
  w.bump_next_m_ = next > 0.0 ? next : 0.0;
  if (w.cables_ahead_ > 0u && --w.cables_ahead_ == 0u) {
    w.bump_next_m_ = 1.0e300;
  }
  // Besides the yaw that follows from this wheel's lost ground travel, the jolt skids the heading
  // a little (zero mean, more for a higher cable).
  const double skid = floor_random_.normal(model_.bump_yaw_sigma_rad * model_.bump_height_m / 0.01);
  if (skid != 0.0) {
    const Turn t = turn_of(skid);
    const double c2 = cos_ * t.cos - sin_ * t.sin;
    sin_ = sin_ * t.cos + cos_ * t.sin;
    cos_ = c2;
    pose_.theta_rad += skid;
  }
}

void Plant::step(std::uint32_t dt_ns) {
  const std::uint64_t t0 = clock_.ns();
  const double dt_s = static_cast<double>(dt_ns) * 1.0e-9;
  const bool standard = dt_ns == model_.physics_step_ns;
  const double left_from = left_.angle_rad_;
  const double right_from = right_.angle_rad_;
  double left_delta = 0.0;
  double right_delta = 0.0;
  integrate_motor(left_, dt_s, standard, left_delta);
  integrate_motor(right_, dt_s, standard, right_delta);
  if (left_delta != 0.0 || right_delta != 0.0) {
    left_.angle_rad_ += left_delta;
    right_.angle_rad_ += right_delta;
    // Edges by event: most steps cross no count boundary on one wheel or both, and only a wheel
    // whose shaft left its count computes the instants of its edges.
    const bool left_edges = leaves_count(left_);
    const bool right_edges = leaves_count(right_);
    if (left_edges && right_edges) {
      deliver_edges(left_from, right_from, t0, dt_ns);
    } else if (left_edges) {
      deliver_wheel_edges(left_, left_from, t0, dt_ns);
    } else if (right_edges) {
      deliver_wheel_edges(right_, right_from, t0, dt_ns);
    }

    const double rolled_left = left_.radius_m_ * left_delta;
    const double rolled_right = right_.radius_m_ * right_delta;
    const double s_left = ground_travel(left_, rolled_left);
    const double s_right = ground_travel(right_, rolled_right);
    left_.ground_m_ += s_left;
    right_.ground_m_ += s_right;

    // Rigid body, no lateral slip: the centre moves on the arc the two contact points define.
    const double ds = 0.5 * (s_left + s_right);
    double dtheta = (s_right - s_left) * inverse_wheelbase_;
    if (arc_gap_m_ != 0.0) {
      // The wheelbase in force this step: the blend by the forward share of the wheels' rotation.
      const double forward = std::fabs(left_delta + right_delta);
      const double sum = forward + std::fabs(right_delta - left_delta);
      dtheta = (s_right - s_left) / (model_.wheelbase_m + arc_gap_m_ * (forward / sum));
    }
    const Turn half = turn_of(0.5 * dtheta);
    const double cm = cos_ * half.cos - sin_ * half.sin;
    const double sm = sin_ * half.cos + cos_ * half.sin;
    const double chord = ds * half.sinc;
    pose_.x_m += chord * cm;
    pose_.y_m += chord * sm;
    const double c = cm * half.cos - sm * half.sin;
    const double s = sm * half.cos + cm * half.sin;
    const double renorm = 1.5 - 0.5 * (c * c + s * s);  // one Newton step keeps |(c, s)| = 1
    cos_ = c * renorm;
    sin_ = s * renorm;
    pose_.theta_rad += dtheta;
    distance_m_ += ds;
  }
  clock_.set_ns(t0 + dt_ns);
}

}  // namespace odocal::sim
