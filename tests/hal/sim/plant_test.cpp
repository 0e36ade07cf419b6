// The simulated plant alone, driven open-loop through its HAL endpoints.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/plant.hpp"

namespace odocal::sim {
namespace {

constexpr double pi = 3.14159265358979323846;

/// A robot with no random terms, so geometry can be checked exactly.
RobotModel quiet_robot() {
  RobotModel m;
  m.slip_sigma = 0.0;
  m.bump_height_m = 0.0;
  m.measure_sigma_m = 0.0;
  m.measure_heading_sigma_rad = 0.0;
  return m;
}

void set_wheel(Wheel& wheel, float duty) {
  wheel.forward().set(duty >= 0.0f);
  wheel.pwm().set_duty(std::fabs(duty));
}

/// Steady no-load speed of the motor model at a duty: (k·V/R − τ_c) / (k²/R + c).
double steady_speed(const MotorModel& m, double duty) {
  const double v = duty * m.supply_v;
  return (m.k_v_per_radps * v / m.resistance_ohm - m.coulomb_nm) /
         (m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps);
}

TEST(Plant, FullDutyReachesTheNoLoadSpeedTheFirmwareFeedForwardAssumes) {
  Plant plant(quiet_robot(), 1u);
  set_wheel(plant.left(), 1.0f);
  set_wheel(plant.right(), 1.0f);
  plant.advance_to_ns(2'000'000'000u);  // 20 time constants
  const double expected = steady_speed(plant.model().left_motor, 1.0);
  EXPECT_NEAR(plant.left().speed_radps(), expected, 1e-6 * expected);
  // kff = 0.033 duty per rad/s means full duty ~ 30 rad/s: the model agrees within 5 %.
  EXPECT_NEAR(expected, 1.0 / 0.033, 0.05 / 0.033);
}

TEST(Plant, WheelAtRestStaysThereBelowBreakawayTorque) {
  Plant plant(quiet_robot(), 1u);
  const MotorModel& m = plant.model().left_motor;
  const double breakaway_duty = m.coulomb_nm * m.resistance_ohm / m.k_v_per_radps / m.supply_v;
  set_wheel(plant.left(), static_cast<float>(0.9 * breakaway_duty));
  plant.advance_to_ns(1'000'000'000u);
  EXPECT_EQ(plant.left().speed_radps(), 0.0);
  EXPECT_EQ(plant.left().encoder_count(), 0);
}

TEST(Plant, StraightRunOfUnequalWheelsBendsWithTheUmbmarkRadius) {
  RobotModel m = quiet_robot();
  m.left_diameter_m = 0.0597;
  m.right_diameter_m = 0.0603;
  Plant plant(m, 7u);
  const double left0 = plant.left().angle_rad();
  const double right0 = plant.right().angle_rad();
  set_wheel(plant.left(), 0.2f);  // identical motors and duties: identical shaft rotation
  set_wheel(plant.right(), 0.2f);
  plant.advance_to_ns(10'000'000'000u);
  ASSERT_NEAR(plant.left().angle_rad() - left0, plant.right().angle_rad() - right0, 1e-9);

  // UMBmark eq. 6.24 solved for R: E_d = (R + b/2)/(R − b/2)  =>  R = (b/2)(E_d + 1)/(E_d − 1).
  const double e_d = m.right_diameter_m / m.left_diameter_m;
  const double radius = 0.5 * m.wheelbase_m * (e_d + 1.0) / (e_d - 1.0);
  const WorldPose& p = plant.pose();
  ASSERT_GT(plant.distance_m(), 1.0);
  // Arc of radius R turning left: heading = s/R, position on the circle centred at (0, R).
  EXPECT_NEAR(p.theta_rad, plant.distance_m() / radius, 1e-9);
  EXPECT_NEAR(std::hypot(p.x_m, p.y_m - radius), radius, 1e-9 * radius);
  EXPECT_GT(p.y_m, 0.0);  // D_R > D_L curves to the left
}

TEST(Plant, TurnInPlaceUnderRotatesByTheWheelbaseRatio) {
  RobotModel m = quiet_robot();
  m.left_diameter_m = 0.06;
  m.right_diameter_m = 0.06;
  m.wheelbase_m = 0.153;  // the firmware believes 0.150
  const double nominal_wheelbase_m = 0.150;
  Plant plant(m, 3u);
  set_wheel(plant.left(), -0.2f);
  set_wheel(plant.right(), 0.2f);
  plant.advance_to_ns(3'000'000'000u);
  set_wheel(plant.left(), 0.0f);
  set_wheel(plant.right(), 0.0f);
  plant.advance_to_ns(5'000'000'000u);
  ASSERT_TRUE(plant.at_rest());
  ASSERT_NEAR(plant.distance_m(), 0.0, 1e-12);

  // What odometry with the nominal wheelbase believes, from the encoder counts.
  const double count_m = pi * 0.06 / m.counts_per_rev;
  const double believed =
      static_cast<double>(plant.right().encoder_count() - plant.left().encoder_count()) * count_m /
      nominal_wheelbase_m;
  ASSERT_GT(believed, pi);
  // True rotation / believed rotation = b_nominal / b_true, within one count of quantisation
  // per wheel.
  const double tolerance = 2.0 * count_m / nominal_wheelbase_m / believed;
  EXPECT_NEAR(plant.pose().theta_rad / believed, nominal_wheelbase_m / m.wheelbase_m, tolerance);
}

// The arc wheelbase (robot file `true_wheelbase_arc_mm`): the robot turns with b + w·(b_arc − b),
// w = |φ_L + φ_R| / (|φ_L + φ_R| + |φ_R − φ_L|) of the wheel rotation: b in place, the blend on an
// arc. Steady wheel speeds (20 motor time constants) make the turn rate exact.
TEST(Plant, AnArcWheelbaseTurnsWithTheBlend) {
  RobotModel m = quiet_robot();
  m.left_diameter_m = 0.06;
  m.right_diameter_m = 0.06;
  m.wheelbase_m = 0.150;
  m.wheelbase_arc_m = 0.153;
  ASSERT_EQ(check(m), ModelError::none);
  for (const float left_duty : {-0.3f, 0.15f}) {
    Plant plant(m, 5u);
    set_wheel(plant.left(), left_duty);
    set_wheel(plant.right(), 0.3f);
    plant.advance_to_ns(2'000'000'000u);
    const double left = plant.left().speed_radps();
    const double right = plant.right().speed_radps();
    const double theta0 = plant.pose().theta_rad;
    plant.advance_to_ns(3'000'000'000u);
    const double forward = std::fabs(left + right);
    const double w = forward / (forward + std::fabs(right - left));
    const double expected = 0.03 * (right - left) / (0.150 + w * 0.003);  // rad in 1 s
    EXPECT_NEAR(plant.pose().theta_rad - theta0, expected, 1e-6 * std::fabs(expected)) << w;
    if (left_duty < 0.0f) {
      EXPECT_NEAR(w, 0.0, 1e-9);  // turning in place: the turn wheelbase
    } else {
      EXPECT_GT(w, 0.5);
    }
  }
  m.wheelbase_arc_m = 0.05;  // not above a wheel's diameter
  EXPECT_EQ(check(m), ModelError::wheelbase_arc);
}

/// Records every edge seen on one wheel's lines.
struct EdgeLog {
  Wheel* wheel = nullptr;
  SimClock* clock = nullptr;
  std::vector<std::uint8_t> states;
  std::vector<std::uint64_t> times_ns;
  static void on_edge(void* context) {
    auto* log = static_cast<EdgeLog*>(context);
    const bool a = log->wheel->channel_a().read();
    const bool b = log->wheel->channel_b().read();
    log->states.push_back(static_cast<std::uint8_t>((a ? 2u : 0u) | (b ? 1u : 0u)));
    log->times_ns.push_back(log->clock->ns());
  }
};

TEST(Plant, EdgesComeInQuadratureOrderAtTheInstantTheShaftCrossesThem) {
  Plant plant(quiet_robot(), 11u);
  EdgeLog log;
  log.wheel = &plant.left();
  log.clock = &plant.clock();
  plant.left().channel_a().on_edge(&EdgeLog::on_edge, &log);
  plant.left().channel_b().on_edge(&EdgeLog::on_edge, &log);
  set_wheel(plant.left(), 0.3f);
  plant.advance_to_ns(1'500'000'000u);
  set_wheel(plant.left(), -0.3f);  // reverse through zero
  plant.advance_to_ns(3'000'000'000u);
  ASSERT_GT(log.states.size(), 1000u);

  // Gray code: each edge changes exactly one line; time never runs backwards.
  std::uint8_t previous = 0u;  // the plant starts at count 0: A = B = low
  for (std::size_t i = 0; i < log.states.size(); ++i) {
    const std::uint8_t changed = static_cast<std::uint8_t>(previous ^ log.states[i]);
    ASSERT_TRUE(changed == 1u || changed == 2u) << "edge " << i;
    previous = log.states[i];
    if (i > 0) {
      ASSERT_GE(log.times_ns[i], log.times_ns[i - 1]);
    }
  }

  // At steady speed the edges are one count apart in angle: interval = (2π/N)/ω, to within the
  // 1 ns rounding of the edge instant (the speed is constant to 1e-9 after 14 time constants).
  Plant steady(quiet_robot(), 11u);
  EdgeLog s;
  s.wheel = &steady.left();
  s.clock = &steady.clock();
  steady.left().channel_a().on_edge(&EdgeLog::on_edge, &s);
  steady.left().channel_b().on_edge(&EdgeLog::on_edge, &s);
  set_wheel(steady.left(), 0.5f);
  steady.advance_to_ns(1'500'000'000u);
  const std::size_t first = s.times_ns.size();
  steady.advance_to_ns(1'600'000'000u);
  const double omega = steady.left().speed_radps();
  const double interval_ns = 2.0 * pi / steady.model().counts_per_rev / omega * 1e9;
  for (std::size_t i = first + 1; i < s.times_ns.size(); ++i) {
    EXPECT_NEAR(static_cast<double>(s.times_ns[i] - s.times_ns[i - 1]), interval_ns, 2.0);
  }
}

TEST(Plant, DecoderWiredThroughTheHalCountsEveryEdgeAndNoIllegalOne) {
  Plant plant(quiet_robot(), 5u);
  drive::QuadratureDecoder decoder;
  EncoderWiring wiring(plant.right().channel_a(), plant.right().channel_b(), plant.clock(),
                       drive::edge_sink(decoder));
  wiring.attach();
  set_wheel(plant.right(), 1.0f);
  plant.advance_to_ns(1'000'000'000u);
  set_wheel(plant.right(), -1.0f);
  plant.advance_to_ns(1'300'000'000u);
  const auto snap = decoder.snapshot();
  EXPECT_EQ(static_cast<std::int32_t>(snap.count),
            static_cast<std::int32_t>(plant.right().encoder_count()));
  EXPECT_EQ(snap.illegal, 0u);
  EXPECT_GT(snap.edges, 5000u);
}

/// A quiet robot with equal 60 mm wheels on a floor of 10 mm cables every 200 mm (±10 %), no
/// random skid: every heading change comes from the wheels' ground travel.
RobotModel cable_robot() {
  RobotModel m = quiet_robot();
  m.left_diameter_m = 0.06;
  m.right_diameter_m = 0.06;
  m.bump_height_m = 0.010;
  m.bump_spacing_m = 0.2;
  m.bump_spacing_jitter = 0.1;
  m.bump_yaw_sigma_rad = 0.0;
  return m;
}

/// Wheel travel lost on one cable: over a cable of radius c a wheel of radius r turns through the
/// arc 2(r+c)·acos((r−c)/(r+c)) while covering the chord 4·sqrt(r·c).
double loss_per_cable(const RobotModel& m) {
  const double r = 0.5 * m.left_diameter_m;
  const double c = 0.5 * m.bump_height_m;
  return 2.0 * (r + c) * std::acos((r - c) / (r + c)) - 4.0 * std::sqrt(r * c);
}

/// How far a wheel's crossing count may stray from floor distance / spacing: the first cable is
/// anywhere in the first spacing (±1), and the sum of n uniform ±jitter spacings has a standard
/// deviation of spacing·jitter·sqrt(n/3) (4 of them).
double crossing_tolerance(const RobotModel& m, double crossings) {
  return 1.0 + 4.0 * m.bump_spacing_jitter * std::sqrt(crossings / 3.0);
}

TEST(Plant, EachWheelLosesTheCableGeometryOnEveryCableItsOwnContactCrosses) {
  const RobotModel m = cable_robot();
  const double lost = loss_per_cable(m);
  // 10 mm cable, 30 mm wheel: an arc of 54.27 mm against a chord of 48.99 mm.
  ASSERT_NEAR(lost, 0.00528, 0.00001);
  Plant plant(m, 9u);
  const double left0 = plant.left().angle_rad();
  const double right0 = plant.right().angle_rad();
  set_wheel(plant.left(), 0.3f);
  set_wheel(plant.right(), 0.3f);
  plant.advance_to_ns(40'000'000'000u);
  set_wheel(plant.left(), 0.0f);
  set_wheel(plant.right(), 0.0f);
  plant.advance_to_ns(42'000'000'000u);
  ASSERT_TRUE(plant.at_rest());

  const double rolled[2] = {0.03 * (plant.left().angle_rad() - left0),
                            0.03 * (plant.right().angle_rad() - right0)};
  const Wheel* wheels[2] = {&plant.left(), &plant.right()};
  for (int i = 0; i < 2; ++i) {
    const double ground = wheels[i]->ground_m();
    const double crossings = wheels[i]->bumps_crossed();
    ASSERT_GT(ground, 9.0);
    // Every cable but possibly the last one is fully crossed.
    const double loss = rolled[i] - ground;
    EXPECT_GE(loss, (crossings - 1.0) * lost - 1e-9) << "wheel " << i;
    EXPECT_LE(loss, crossings * lost + 1e-9) << "wheel " << i;
    // One cable per spacing of floor: loss per metre = crossings per metre x loss per crossing.
    const double expected_crossings = ground / m.bump_spacing_m;
    const double tolerance = crossing_tolerance(m, expected_crossings);
    EXPECT_NEAR(crossings, expected_crossings, tolerance) << "wheel " << i;
    EXPECT_NEAR(loss / ground, lost / m.bump_spacing_m, tolerance * lost / ground) << "wheel " << i;
  }
  EXPECT_EQ(plant.bumps_crossed(), plant.left().bumps_crossed() + plant.right().bumps_crossed());
  // No skid: the heading is exactly what the two wheels' ground travel makes of a rigid body.
  const double heading =
      (plant.right().ground_m() - plant.left().ground_m()) / plant.model().wheelbase_m;
  EXPECT_NEAR(plant.pose().theta_rad, heading, 1e-9);
  EXPECT_NE(plant.left().ground_m(), plant.right().ground_m());  // the wheels' own phases
}

TEST(Plant, TurnInPlaceOverCablesUnderRotatesByTheGroundLossOfAStraightRun) {
  const RobotModel m = cable_robot();
  const double lost = loss_per_cable(m);
  Plant plant(m, 4u);
  const double left0 = plant.left().angle_rad();
  const double right0 = plant.right().angle_rad();
  set_wheel(plant.left(), -0.3f);
  set_wheel(plant.right(), 0.3f);
  plant.advance_to_ns(40'000'000'000u);
  set_wheel(plant.left(), 0.0f);
  set_wheel(plant.right(), 0.0f);
  plant.advance_to_ns(42'000'000'000u);
  ASSERT_TRUE(plant.at_rest());

  const double rolled_left = 0.03 * (left0 - plant.left().angle_rad());
  const double rolled_right = 0.03 * (plant.right().angle_rad() - right0);
  // The rotation the rolled travel gives on a smooth floor (true wheelbase).
  const double smooth = (rolled_left + rolled_right) / m.wheelbase_m;
  ASSERT_GT(smooth, 100.0);  // about 20 turns: 10 m of floor per wheel
  // Every spacing of floor costs spacing + lost of wheel travel, turning or not: on average the
  // turn achieves spacing/(spacing + lost) of the smooth-floor rotation (2.6 % short here).
  const double expected = m.bump_spacing_m / (m.bump_spacing_m + lost);
  const double crossings = 0.5 * plant.bumps_crossed();  // per wheel
  const double tolerance = crossing_tolerance(m, crossings) * lost /
                           (0.5 * (rolled_left + rolled_right));  // as a fraction of the travel
  EXPECT_NEAR(plant.pose().theta_rad / smooth, expected, tolerance);
  EXPECT_LT(plant.pose().theta_rad / smooth, 1.0 - 0.5 * (1.0 - expected));
  // The under-rotation is each wheel's own lost ground travel, cable by cable.
  EXPECT_NEAR(plant.pose().theta_rad,
              (plant.right().ground_m() - plant.left().ground_m()) / m.wheelbase_m, 1e-9);
}

TEST(Plant, LaidCablesAreCrossedByOneWheelOnlyExactlyAsManyTimesAsLaid) {
  // The extended UMBmark's floor: ten cables under the right wheel, 0.2 m from the start, every
  // 0.4 m. Driving 10 m straight, the right wheel crosses each once and loses each one's geometry;
  // the left wheel rolls on a smooth floor; the heading turns right by the lost travel / wheelbase.
  RobotModel m = cable_robot();
  m.bump_height_m = 0.0;
  const double lost = loss_per_cable(cable_robot());
  Plant plant(m, 5u);
  plant.lay_cables(true, 0.010, 0.2, 0.4, 10u);
  const double left0 = plant.left().angle_rad();
  const double right0 = plant.right().angle_rad();
  set_wheel(plant.left(), 0.3f);
  set_wheel(plant.right(), 0.3f);
  plant.advance_to_ns(40'000'000'000u);
  set_wheel(plant.left(), 0.0f);
  set_wheel(plant.right(), 0.0f);
  plant.advance_to_ns(42'000'000'000u);
  ASSERT_TRUE(plant.at_rest());
  ASSERT_GT(plant.right().ground_m(), 5.0);  // far past the last cable (3.8 m)
  EXPECT_EQ(plant.right().bumps_crossed(), 10u);
  EXPECT_EQ(plant.left().bumps_crossed(), 0u);
  const double rolled_left = 0.03 * (plant.left().angle_rad() - left0);
  const double rolled_right = 0.03 * (plant.right().angle_rad() - right0);
  EXPECT_NEAR(rolled_left - plant.left().ground_m(), 0.0, 1e-9);
  EXPECT_NEAR(rolled_right - plant.right().ground_m(), 10.0 * lost, 1e-9);
  EXPECT_NEAR(plant.pose().theta_rad,
              (plant.right().ground_m() - plant.left().ground_m()) / m.wheelbase_m, 1e-9);

  // A new run (place) lays the same row again; set_bumps returns to the random floor.
  plant.place();
  set_wheel(plant.left(), 0.3f);
  set_wheel(plant.right(), 0.3f);
  plant.advance_to_ns(60'000'000'000u);
  EXPECT_EQ(plant.right().bumps_crossed(), 20u);
  EXPECT_EQ(plant.left().bumps_crossed(), 0u);
  plant.set_bumps(0.010, 0.2);
  plant.advance_to_ns(70'000'000'000u);
  EXPECT_GT(plant.left().bumps_crossed(), 0u);
}

TEST(Plant, SmoothFloorRunDoesNotDependOnTheCableSettings) {
  // The cables draw from their own random stream: a smooth floor is the same whatever their
  // spacing, jitter or skid.
  RobotModel a;
  RobotModel b;
  b.bump_spacing_m = 0.37;
  b.bump_spacing_jitter = 0.5;
  b.bump_yaw_sigma_rad = 0.1;
  Plant pa(a, 8u);
  Plant pb(b, 8u);
  for (Plant* p : {&pa, &pb}) {
    set_wheel(p->left(), 0.3f);
    set_wheel(p->right(), 0.31f);
    p->advance_to_ns(3'000'000'000u);
  }
  EXPECT_EQ(pa.pose().x_m, pb.pose().x_m);
  EXPECT_EQ(pa.pose().theta_rad, pb.pose().theta_rad);
  EXPECT_EQ(pa.bumps_crossed(), 0u);
}

TEST(Plant, PhysicsStepDoesNotChangeTheMotion) {
  RobotModel coarse = quiet_robot();
  RobotModel fine = quiet_robot();
  fine.physics_step_ns = 50'000u;
  Plant a(coarse, 2u);
  Plant b(fine, 2u);
  for (Plant* p : {&a, &b}) {
    set_wheel(p->left(), 0.25f);
    set_wheel(p->right(), 0.3f);
    p->advance_to_ns(1'000'000'000u);
    set_wheel(p->left(), -0.1f);
    p->advance_to_ns(2'000'000'000u);
  }
  // Exact exponential integration: only the stiction handling depends on the step.
  EXPECT_NEAR(a.pose().x_m, b.pose().x_m, 1e-6);
  EXPECT_NEAR(a.pose().y_m, b.pose().y_m, 1e-6);
  EXPECT_NEAR(a.pose().theta_rad, b.pose().theta_rad, 1e-5);
}

// The plant keeps its own physics (motors, edges, the floor) but moves the body as the one
// model of the robot says (drive::model): integrating the wheels' rotation sampled every
// millisecond with model::advance and the robot's true geometry lands where the plant's body is.
// Between samples the wheel speeds change by at most 1 % (motor time constant ~0.1 s), so taking
// each millisecond as one arc errs by far less than a micrometre per sample: 1e-6 m over ~1 m of
// lines, arcs and turns in place.
TEST(Plant, BodyMovesAsTheOneRobotModelSays) {
  RobotModel m = quiet_robot();
  m.left_diameter_m = 0.0597;
  m.right_diameter_m = 0.0604;
  m.wheelbase_m = 0.152;
  m.wheelbase_arc_m = 0.1535;
  ASSERT_EQ(check(m), ModelError::none);
  Plant plant(m, 9u);
  drive::model::PoseOf<double> pose;
  double left0 = plant.left().angle_rad();
  double right0 = plant.right().angle_rad();
  const float duties[][2] = {{0.3f, 0.3f}, {-0.25f, 0.25f}, {0.1f, 0.35f}, {0.3f, 0.2f}};
  std::uint64_t t_ns = 0;
  for (const auto& duty : duties) {
    set_wheel(plant.left(), duty[0]);
    set_wheel(plant.right(), duty[1]);
    for (int ms = 0; ms < 1500; ++ms) {
      t_ns += 1'000'000u;
      plant.advance_to_ns(t_ns);
      const double left_rad = plant.left().angle_rad() - left0;
      const double right_rad = plant.right().angle_rad() - right0;
      left0 = plant.left().angle_rad();
      right0 = plant.right().angle_rad();
      drive::model::advance(
          pose, 0.5 * m.left_diameter_m * left_rad, 0.5 * m.right_diameter_m * right_rad,
          drive::model::wheelbase_for(m.wheelbase_m, m.wheelbase_arc_m, left_rad, right_rad));
    }
  }
  ASSERT_GT(plant.distance_m(), 0.5);
  EXPECT_NEAR(plant.pose().x_m, pose.x, 1e-6);
  EXPECT_NEAR(plant.pose().y_m, pose.y, 1e-6);
  EXPECT_NEAR(plant.pose().theta_rad, pose.theta, 1e-6);
}

std::vector<double> noisy_run(std::uint64_t seed) {
  RobotModel m;
  m.bump_height_m = 0.01;
  m.slip_sigma = 0.01;
  Plant plant(m, seed);
  set_wheel(plant.left(), 0.3f);
  set_wheel(plant.right(), 0.31f);
  plant.advance_to_ns(3'000'000'000u);
  const WorldPose measured = plant.measure();
  return {plant.pose().x_m,
          plant.pose().y_m,
          plant.pose().theta_rad,
          measured.x_m,
          measured.y_m,
          measured.theta_rad,
          static_cast<double>(plant.left().encoder_count())};
}

TEST(Plant, SameSeedSameRunBitForBitAndAnotherSeedDiffers) {
  EXPECT_EQ(noisy_run(42u), noisy_run(42u));
  EXPECT_NE(noisy_run(42u), noisy_run(43u));
}

TEST(RobotModel, RefusesImpossibleRobots) {
  RobotModel m;
  EXPECT_EQ(check(m), ModelError::none);
  m.left_diameter_m = 0.0;
  EXPECT_EQ(check(m), ModelError::left_diameter);
  m = RobotModel{};
  m.right_diameter_m = -1.0;
  EXPECT_EQ(check(m), ModelError::right_diameter);
  m = RobotModel{};
  m.wheelbase_m = 0.05;  // smaller than a wheel
  EXPECT_EQ(check(m), ModelError::wheelbase);
  m = RobotModel{};
  m.counts_per_rev = 1442u;
  EXPECT_EQ(check(m), ModelError::counts_per_rev);
  m = RobotModel{};
  m.bump_height_m = 0.05;  // higher than the wheel's axle
  EXPECT_EQ(check(m), ModelError::bump);
  Plant refused(m, 1u);
  EXPECT_FALSE(refused.ok());
}

}  // namespace
}  // namespace odocal::sim
