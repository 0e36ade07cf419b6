#include "odocal/sim/plant.hpp"

#include <cmath>

namespace odocal::sim {
namespace {

constexpr double two_pi = 6.283185307179586476925;

/// cos and sin of a small angle by their series (|x| < 0.05: error below 1e-11), else libm.
void cos_sin(double x, double& c, double& s) {
  if (std::fabs(x) < 0.05) {
    const double x2 = x * x;
    c = 1.0 - x2 * (0.5 - x2 * (1.0 / 24.0));
    s = x * (1.0 - x2 * ((1.0 / 6.0) - x2 * (1.0 / 120.0)));
  } else {
    c = std::cos(x);
    s = std::sin(x);
  }
}

/// Quadrature levels for an x4 count: A leads B when counting up (0,0)->(1,0)->(1,1)->(0,1).
void phase_levels(std::int64_t count, bool& a, bool& b) {
  const auto phase = static_cast<std::uint64_t>(count) & 3u;
  a = phase == 1u || phase == 2u;
  b = phase >= 2u;
}

}  // namespace

Plant::Plant(const RobotModel& model, std::uint64_t seed)
    : model_(model), ok_(check(model) == ModelError::none), random_(seed) {
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
    w.decay_ = (m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps) /
               m.inertia_kgm2;
    w.step_factor_ = std::exp(-w.decay_ * h);
    w.radius_m_ = 0.5 * diameters[i];
    w.count_rad_ = two_pi / static_cast<double>(model.counts_per_rev);
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
  set_bumps(model.bump_height_m, model.bump_spacing_m);
  place();
}

void Plant::set_bumps(double height_m, double spacing_m) {
  model_.bump_height_m = height_m > 0.0 ? height_m : 0.0;
  if (spacing_m > 0.0) {
    model_.bump_spacing_m = spacing_m;
  }
  bump_ratio_ = 1.0;
  bump_arc_m_ = 0.0;
  if (model_.bump_height_m > 0.0) {
    // A wheel of radius r rolling over a cable of radius c (height 2c): its centre follows an arc
    // of radius r + c over ±ψ0, cos ψ0 = (r − c)/(r + c), while the floor distance covered is
    // only the chord 4·sqrt(r·c). The wheel turns by the arc: extra rotation, shorter progress.
    const double r = 0.25 * (model_.left_diameter_m + model_.right_diameter_m);
    const double c = 0.5 * model_.bump_height_m;
    const double psi0 = std::acos((r - c) / (r + c));
    bump_arc_m_ = 2.0 * (r + c) * psi0;
    bump_ratio_ = 4.0 * std::sqrt(r * c) / bump_arc_m_;
  }
  bump_next_m_ = model_.bump_spacing_m * random_.uniform();
}

void Plant::place(const WorldPose& pose) {
  pose_ = pose;
  cos_ = std::cos(pose.theta_rad);
  sin_ = std::sin(pose.theta_rad);
  left_.speed_radps_ = 0.0;
  right_.speed_radps_ = 0.0;
  left_.bump_left_m_ = 0.0;
  right_.bump_left_m_ = 0.0;
  bump_next_m_ = model_.bump_spacing_m * random_.uniform();
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

void Plant::integrate_motor(Wheel& w, double dt_s, bool standard_step, double& delta_rad) {
  const MotorModel& m = w.motor_;
  const double duty = static_cast<double>(w.pwm_.duty());
  w.voltage_v_ = (w.direction_.forward() ? 1.0 : -1.0) * duty * m.supply_v;
  const double drive_nm = m.k_v_per_radps * w.voltage_v_ / m.resistance_ohm;
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
  // Linear between sign changes: dω/dt = u − a·ω, solved exactly over the step (constant V).
  const double a = w.decay_;
  const double u = (drive_nm - m.coulomb_nm * sign) / m.inertia_kgm2;
  const double w_ss = u / a;
  const double e = standard_step ? w.step_factor_ : std::exp(-a * dt_s);
  double w1 = w_ss + (w0 - w_ss) * e;
  delta_rad = w_ss * dt_s + (w0 - w_ss) * (1.0 - e) / a;
  if (w0 != 0.0 && w1 * sign < 0.0) {
    // Friction brought it to rest at t0 inside the step. It stays there unless the motor torque
    // breaks it away in the other direction for the rest of the step.
    const double t0 = -std::log(-w_ss / (w0 - w_ss)) / a;
    delta_rad = w_ss * t0 + w0 / a;
    w1 = 0.0;
    const double rest_s = dt_s - t0;
    if (rest_s > 0.0 && std::fabs(drive_nm) > m.coulomb_nm) {
      const double back = drive_nm > 0.0 ? 1.0 : -1.0;
      const double w_back = (drive_nm - m.coulomb_nm * back) / m.inertia_kgm2 / a;
      const double e_back = std::exp(-a * rest_s);
      w1 = w_back * (1.0 - e_back);
      delta_rad += w_back * rest_s - w_back * (1.0 - e_back) / a;
    }
  }
  w.speed_radps_ = w1;
}

void Plant::deliver_edges(double left_from, double right_from, std::uint64_t t0_ns,
                          std::uint32_t dt_ns) {
  struct Pending {
    Wheel* wheel;
    double from;
    double span;
    std::int64_t target;
    std::int64_t direction;
    double fraction;  // of the step at which the next edge happens; > 1: none
  };
  Pending pending[2] = {{&left_, left_from, 0.0, 0, 0, 2.0}, {&right_, right_from, 0.0, 0, 0, 2.0}};
  auto next_fraction = [](Pending& p) {
    if (p.wheel->count_ == p.target) {
      p.fraction = 2.0;
      return;
    }
    const std::int64_t boundary = p.direction > 0 ? p.wheel->count_ + 1 : p.wheel->count_;
    // Linear interpolation of the shaft angle inside the step.
    p.fraction = (static_cast<double>(boundary) * p.wheel->count_rad_ - p.from) / p.span;
  };
  for (Pending& p : pending) {
    Wheel& w = *p.wheel;
    p.span = w.angle_rad_ - p.from;
    // floor() without the libm call: truncation, one less for negative non-integers.
    const double counts = w.angle_rad_ / w.count_rad_;
    p.target = static_cast<std::int64_t>(counts);
    if (static_cast<double>(p.target) > counts) {
      --p.target;
    }
    p.direction = p.target > w.count_ ? 1 : -1;
    next_fraction(p);
  }
  std::uint64_t last_ns = t0_ns;
  while (pending[0].fraction <= 1.5 || pending[1].fraction <= 1.5) {
    Pending& p = pending[1].fraction < pending[0].fraction ? pending[1] : pending[0];
    double f = p.fraction;
    f = f < 0.0 ? 0.0 : (f > 1.0 ? 1.0 : f);
    std::uint64_t t = t0_ns + static_cast<std::uint64_t>(f * dt_ns + 0.5);
    if (t < last_ns) {
      t = last_ns;  // the clock never runs backwards, even by a rounding
    }
    last_ns = t;
    clock_.set_ns(t);
    Wheel& w = *p.wheel;
    w.count_ += p.direction;
    bool a = false;
    bool b = false;
    phase_levels(w.count_, a, b);
    // Exactly one of the two lines changes per count; only that one runs its handler.
    w.a_.drive(a);
    w.b_.drive(b);
    next_fraction(p);
  }
}

double Plant::ground_travel(Wheel& w, double rolled_m) {
  const double magnitude = std::fabs(rolled_m);
  if (magnitude == 0.0) {
    return 0.0;
  }
  double ground = magnitude * (1.0 + w.slip_ratio_);
  if (w.bump_left_m_ > 0.0) {
    const double on_bump = magnitude < w.bump_left_m_ ? magnitude : w.bump_left_m_;
    ground -= on_bump * (1.0 - bump_ratio_) * (1.0 + w.slip_ratio_);
    w.bump_left_m_ -= on_bump;
  }
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

void Plant::start_bump() {
  ++bumps_;
  // Both wheels roll over the cable (laid across the path).
  left_.bump_left_m_ = bump_arc_m_;
  right_.bump_left_m_ = bump_arc_m_;
  // The jolt skids the heading a little, more for a higher bump.
  const double kick = random_.normal(model_.bump_yaw_sigma_rad * model_.bump_height_m / 0.01);
  double c = 1.0;
  double s = 0.0;
  cos_sin(kick, c, s);
  const double c2 = cos_ * c - sin_ * s;
  sin_ = sin_ * c + cos_ * s;
  cos_ = c2;
  pose_.theta_rad += kick;
  const double jitter = model_.bump_spacing_jitter * random_.uniform(-1.0, 1.0);
  bump_next_m_ += model_.bump_spacing_m * (1.0 + jitter);
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
    deliver_edges(left_from, right_from, t0, dt_ns);

    const double rolled_left = left_.radius_m_ * left_delta;
    const double rolled_right = right_.radius_m_ * right_delta;
    if (model_.bump_height_m > 0.0) {
      bump_next_m_ -= std::fabs(0.5 * (rolled_left + rolled_right));
      if (bump_next_m_ <= 0.0) {
        start_bump();
      }
    }
    const double s_left = ground_travel(left_, rolled_left);
    const double s_right = ground_travel(right_, rolled_right);
    left_.ground_m_ += s_left;
    right_.ground_m_ += s_right;

    // Rigid body, no lateral slip: the centre moves on the arc the two contact points define.
    const double ds = 0.5 * (s_left + s_right);
    const double dtheta = (s_right - s_left) / model_.wheelbase_m;
    const double half = 0.5 * dtheta;
    double ch = 1.0;
    double sh = 0.0;
    cos_sin(half, ch, sh);
    const double sinc = std::fabs(half) < 1.0e-4 ? 1.0 - half * half / 6.0 : sh / half;
    const double cm = cos_ * ch - sin_ * sh;
    const double sm = sin_ * ch + cos_ * sh;
    pose_.x_m += ds * sinc * cm;
    pose_.y_m += ds * sinc * sm;
    double c = cm * ch - sm * sh;
    double s = sm * ch + cm * sh;
    const double renorm = 1.5 - 0.5 * (c * c + s * s);  // one Newton step keeps |(c, s)| = 1
    cos_ = c * renorm;
    sin_ = s * renorm;
    pose_.theta_rad += dtheta;
    distance_m_ += ds;
  }
  clock_.set_ns(t0 + dt_ns);
}

}  // namespace odocal::sim
