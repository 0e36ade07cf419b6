// UMBmark (Borenstein & Feng 1994, section 6): formulas against hand-computed values, the exact
// square model against the paper's first-order expressions, the robot's float solve against the
// host's double one, round trips through the drive
// stack's odometry, the exact solve, composition of passes and the 3·SEM rule.
#include "odocal/calib/umbmark.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "odocal/drive/odometry.hpp"

namespace odocal::calib {
namespace {

constexpr double pi = 3.14159265358979323846;

UmbmarkStatus solve(const std::vector<ReturnError>& cw, const std::vector<ReturnError>& ccw,
                    double side, double b, bool exact, UmbmarkResult& r) {
  UmbmarkInput in;
  in.cw = cw.data();
  in.cw_count = cw.size();
  in.ccw = ccw.data();
  in.ccw_count = ccw.size();
  in.side_mm = side;
  in.wheelbase_mm = b;
  in.exact = exact;
  return solve_umbmark(in, r);
}

// Centres cw (−30, −50), ccw (20, −20); L = 4000 mm, b = 340 mm. By hand (rad):
// β_x = (−30 − 20)/(−16000) = 0.003125, β_y = (−50 − 20)/(−16000) = 0.004375, β = 0.00375;
// α_x = (−30 + 20)/(−16000) = 0.000625, α_y = (−50 + 20)/(−16000) = 0.001875, α = 0.00125.
// R = 2000/sin(0.001875) = 1066667.29 mm; E_d = (R + 170)/(R − 170) = 1.000318800;
// E_b = 90/(90 − 0.0716197°) = 1.000796408; c_L = 2/(E_d + 1) = 0.999840625,
// c_R = 2/(1/E_d + 1) = 1.000159375; b_new = 340.270779 mm.
// Scatter: each run is (±10, ±10) from its centre: σ = sqrt(4·200/(4 − 2)) = 20 mm,
// SEM = 20/√2 = 14.1421 mm; r_cg = 58.3095 and 28.2843 mm; 58.31 >= 3·14.14 → second pass.
TEST(Umbmark, FormulasMatchHandComputedValues) {
  const std::vector<ReturnError> cw{{-40.0, -60.0}, {-20.0, -40.0}};
  const std::vector<ReturnError> ccw{{10.0, -30.0}, {30.0, -10.0}};
  UmbmarkResult r;
  ASSERT_EQ(solve(cw, ccw, 4000.0, 340.0, false, r), UmbmarkStatus::ok);
  EXPECT_DOUBLE_EQ(r.x_cg_cw, -30.0);
  EXPECT_DOUBLE_EQ(r.y_cg_cw, -50.0);
  EXPECT_DOUBLE_EQ(r.x_cg_ccw, 20.0);
  EXPECT_DOUBLE_EQ(r.y_cg_ccw, -20.0);
  EXPECT_NEAR(r.r_cg_cw, 58.309519, 1e-6);
  EXPECT_NEAR(r.r_cg_ccw, 28.284271, 1e-6);
  EXPECT_NEAR(r.e_max_syst_mm, 58.309519, 1e-6);
  EXPECT_NEAR(r.beta_deg, 0.00375 * 180.0 / pi, 1e-12);
  EXPECT_NEAR(r.alpha_deg, 0.00125 * 180.0 / pi, 1e-12);
  EXPECT_NEAR(r.radius_mm, 1066667.29, 0.01);
  EXPECT_NEAR(r.e_d, 1.000318800, 1e-9);
  EXPECT_NEAR(r.e_b, 1.000796408, 1e-9);
  EXPECT_NEAR(r.c_l, 0.999840625, 1e-9);
  EXPECT_NEAR(r.c_r, 1.000159375, 1e-9);
  EXPECT_NEAR((r.c_l + r.c_r) / 2.0, 1.0, 1e-15);  // average diameter kept (eq. 6.30)
  EXPECT_NEAR(r.wheelbase_new_mm, 340.270779, 1e-6);
  EXPECT_NEAR(r.sigma_mm, 20.0, 1e-12);
  EXPECT_NEAR(r.sem_mm, 14.142136, 1e-6);
  EXPECT_TRUE(r.second_pass_recommended);
  EXPECT_FALSE(r.exact);
}

// The paper's example (section 6.3): σ = 25 mm over n = 5 runs gives SEM = 11.2 mm, and E_max,syst
// of 66 mm > 3·SEM = 33.6 mm asks for a second pass, while 21 mm does not.
TEST(Umbmark, ThreeSemRuleFollowsThePaper) {
  // Five runs per direction at (c ± 25·(1,0)·k): deviations whose pooled radial σ is 25 mm.
  // Deviations {+a, −a, +a, −a, 0} along x with a chosen so that 4a²·2/(10 − 2) = 625.
  const double a = std::sqrt(625.0 * 8.0 / 8.0);
  const auto runs = [a](double cx, double cy) {
    return std::vector<ReturnError>{
        {cx + a, cy}, {cx - a, cy}, {cx + a, cy}, {cx - a, cy}, {cx, cy}};
  };
  UmbmarkResult r;
  ASSERT_EQ(solve(runs(-46.67, -46.67), runs(10.0, 10.0), 4000.0, 340.0, false, r),
            UmbmarkStatus::ok);
  EXPECT_NEAR(r.sigma_mm, 25.0, 1e-9);
  EXPECT_NEAR(r.sem_mm, 11.18, 0.01);
  EXPECT_NEAR(r.e_max_syst_mm, 66.0, 0.01);
  EXPECT_TRUE(r.second_pass_recommended);
  ASSERT_EQ(solve(runs(-14.85, -14.85), runs(10.0, 10.0), 4000.0, 340.0, false, r),
            UmbmarkStatus::ok);
  EXPECT_NEAR(r.e_max_syst_mm, 21.0, 0.01);
  EXPECT_FALSE(r.second_pass_recommended);
}

TEST(Umbmark, NoErrorMeansNoCorrection) {
  const std::vector<ReturnError> zero{{0.0, 0.0}, {0.0, 0.0}};
  for (const bool exact : {false, true}) {
    UmbmarkResult r;
    ASSERT_EQ(solve(zero, zero, 4000.0, 340.0, exact, r), UmbmarkStatus::ok);
    EXPECT_NEAR(r.e_d, 1.0, 1e-12);
    EXPECT_NEAR(r.e_b, 1.0, 1e-12);
    // Straight legs: the curvature radius is infinite (odocal prints JSON null), and the
    // angles are +0, never −0 (β = 0/(−4L) would be −0).
    EXPECT_TRUE(std::isinf(r.radius_mm));
    EXPECT_GT(r.radius_mm, 0.0);
    EXPECT_EQ(r.beta_deg, 0.0);
    EXPECT_EQ(r.alpha_deg, 0.0);
    EXPECT_FALSE(std::signbit(r.beta_deg));
    EXPECT_FALSE(std::signbit(r.alpha_deg));
    EXPECT_FALSE(std::signbit(r.x_cg_cw));
    EXPECT_FALSE(std::signbit(r.y_cg_ccw));
    EXPECT_NEAR(r.wheelbase_new_mm, 340.0, 1e-9);
    EXPECT_FALSE(r.second_pass_recommended);
  }
}

// The exact model must agree with the paper's first-order expressions (eq. 6.6, 6.10, 6.14,
// 6.18) to second order in the angles: x, y = −2Lα ± ... within ~4L·(angle)².
TEST(Umbmark, ExactModelMatchesPaperToFirstOrder) {
  const double side = 4000.0, b = 340.0;
  {  // Type A only: α = 90° − 90°/E_b.
    const double e_b = 1.001;
    const double alpha = pi / 2.0 - pi / 2.0 / e_b;
    const double tol = 4.0 * side * alpha * alpha + 1e-9;
    const ReturnError ccw = square_return_error(side, b, 1.0, e_b, false);
    const ReturnError cw = square_return_error(side, b, 1.0, e_b, true);
    EXPECT_NEAR(ccw.x_mm, -2.0 * side * alpha, tol);  // eq. 6.6a
    EXPECT_NEAR(ccw.y_mm, 2.0 * side * alpha, tol);   // eq. 6.6b
    EXPECT_NEAR(cw.x_mm, -2.0 * side * alpha, tol);   // eq. 6.10a
    EXPECT_NEAR(cw.y_mm, -2.0 * side * alpha, tol);   // eq. 6.10b
  }
  {  // Type B only: a leg turns β = 2L(E_d − 1)/((E_d + 1)·b).
    const double e_d = 1.0002;
    const double beta = 2.0 * side * (e_d - 1.0) / ((e_d + 1.0) * b);
    // Second-order terms, plus the small drift of the unequal wheels in each turn in place.
    const double tol = 8.0 * side * beta * beta + pi * b * (e_d - 1.0);
    const ReturnError ccw = square_return_error(side, b, e_d, 1.0, false);
    const ReturnError cw = square_return_error(side, b, e_d, 1.0, true);
    EXPECT_NEAR(ccw.x_mm, 2.0 * side * beta, tol);   // eq. 6.14a
    EXPECT_NEAR(ccw.y_mm, -2.0 * side * beta, tol);  // eq. 6.14b
    EXPECT_NEAR(cw.x_mm, -2.0 * side * beta, tol);   // eq. 6.18a
    EXPECT_NEAR(cw.y_mm, -2.0 * side * beta, tol);   // eq. 6.18b
  }
}

/// An independent square run through the drive stack's odometry: the real wheels travel what the
/// perceived (nominal) wheels travelled, scaled by their true size, in many small ticks; the
/// odometry integrates them with the true wheelbase to give the true end point. The perceived
/// run (nominal wheels, nominal wheelbase) closes at the start.
ReturnError drive_square(double side_mm, double b_mm, double e_d, double e_b, bool clockwise,
                         double& perceived_end_mm) {
  const double k_l = 2.0 / (e_d + 1.0);
  const double k_r = 2.0 * e_d / (e_d + 1.0);
  drive::Odometry truth;
  drive::Odometry belief;
  const auto segment = [&](double left_mm, double right_mm) {
    constexpr int ticks = 2000;
    for (int i = 0; i < ticks; ++i) {
      const double l = left_mm / ticks * 1e-3, r = right_mm / ticks * 1e-3;
      truth.update(static_cast<float>(k_l * l), static_cast<float>(k_r * r),
                   static_cast<float>(e_b * b_mm * 1e-3));
      belief.update(static_cast<float>(l), static_cast<float>(r), static_cast<float>(b_mm * 1e-3));
    }
  };
  const double turn = pi / 2.0 * b_mm / 2.0;
  for (int corner = 0; corner < 4; ++corner) {
    segment(side_mm, side_mm);
    segment(clockwise ? turn : -turn, clockwise ? -turn : turn);
  }
  perceived_end_mm = 1e3 * std::hypot(belief.pose().x_m, belief.pose().y_m);
  return ReturnError{1e3 * (truth.pose().x_m - belief.pose().x_m),
                     1e3 * (truth.pose().y_m - belief.pose().y_m)};
}

struct Robot {
  double side_mm, b_mm, e_d, e_b;
};

UmbmarkResult solve_drive_square(const Robot& robot, bool exact) {
  double perceived = 0.0;
  const ReturnError cw =
      drive_square(robot.side_mm, robot.b_mm, robot.e_d, robot.e_b, true, perceived);
  EXPECT_LT(perceived, 0.05);  // the odometry believes it closed the square
  const ReturnError ccw =
      drive_square(robot.side_mm, robot.b_mm, robot.e_d, robot.e_b, false, perceived);
  EXPECT_LT(perceived, 0.05);
  UmbmarkResult r;
  EXPECT_EQ(solve({cw, cw}, {ccw, ccw}, robot.side_mm, robot.b_mm, exact, r), UmbmarkStatus::ok);
  return r;
}

TEST(Umbmark, RoundTripThroughDriveOdometryRecoversEdEb) {
  // A LabMate-like robot (the paper's E-1 after-values: b 340 → 336.17, D_R/D_L 1.00084).
  const Robot robot{4000.0, 340.0, 1.00084, 336.17 / 340.0};
  const UmbmarkResult exact = solve_drive_square(robot, true);
  // Single-precision odometry over ~16 m and 8000 ticks/side: ~0.1 mm of end-point noise, which
  // maps to ~0.1/(2L) ≈ 1e-5 in the factors.
  EXPECT_NEAR(exact.e_d, robot.e_d, 2e-5);
  EXPECT_NEAR(exact.e_b, robot.e_b, 2e-5);
  EXPECT_TRUE(exact.exact);
  EXPECT_GT(exact.iterations, 0);
  // The small-angle formulas are close here too: the leftover is second order in α ≈ 0.01 rad.
  const UmbmarkResult approx = solve_drive_square(robot, false);
  EXPECT_NEAR(approx.e_d, robot.e_d, 1e-4);
  EXPECT_NEAR(approx.e_b, robot.e_b, 2e-4);
}

/// E_max,syst of the robot after applying `factors` (what the robot believes, relative to the
/// truth: D_R/D_L relative to c_R/c_L, true wheelbase relative to the new one).
double e_max_after(const Robot& robot, const WheelFactors& factors) {
  const double e_d = robot.e_d * factors.c_l / factors.c_r;
  const double e_b = robot.e_b * robot.b_mm / factors.wheelbase_mm;
  const ReturnError cw = square_return_error(robot.side_mm, factors.wheelbase_mm, e_d, e_b, true);
  const ReturnError ccw = square_return_error(robot.side_mm, factors.wheelbase_mm, e_d, e_b, false);
  return std::fmax(std::hypot(cw.x_mm, cw.y_mm), std::hypot(ccw.x_mm, ccw.y_mm));
}

UmbmarkResult solve_model(const Robot& robot, const WheelFactors& current, bool exact) {
  const double e_d = robot.e_d * current.c_l / current.c_r;
  const double e_b = robot.e_b * robot.b_mm / current.wheelbase_mm;
  const ReturnError cw = square_return_error(robot.side_mm, current.wheelbase_mm, e_d, e_b, true);
  const ReturnError ccw = square_return_error(robot.side_mm, current.wheelbase_mm, e_d, e_b, false);
  UmbmarkResult r;
  EXPECT_EQ(solve({cw, cw}, {ccw, ccw}, robot.side_mm, current.wheelbase_mm, exact, r),
            UmbmarkStatus::ok);
  return r;
}

// A small robot with large errors: 8 % wheelbase error (each corner turns 6.7° short) and 2 %
// diameter difference on a 1 m square. The formulas' leftover is second order in α ≈ 0.116 rad:
// α' ~ α²/… gives an E_max,syst of order 2L·α² ≈ 27 mm; the exact solve leaves rounding only.
TEST(Umbmark, ExactSolveRemovesWhatSmallAnglesLeave) {
  const Robot robot{1000.0, 150.0, 1.02, 1.08};
  const WheelFactors nominal{1.0, 1.0, robot.b_mm};
  const double before = e_max_after(robot, nominal);
  EXPECT_GT(before, 300.0);
  const WheelFactors approx = compose(nominal, solve_model(robot, nominal, false));
  const WheelFactors exact = compose(nominal, solve_model(robot, nominal, true));
  EXPECT_GT(e_max_after(robot, approx), 5.0);
  EXPECT_LT(e_max_after(robot, exact), 1e-6);
  EXPECT_NEAR(exact.c_r / exact.c_l, robot.e_d, 1e-10);
  EXPECT_NEAR(exact.wheelbase_mm, robot.e_b * robot.b_mm, 1e-8);
}

TEST(Umbmark, SecondPassRefinesAndDoesNotReset) {
  const Robot robot{1000.0, 150.0, 1.02, 1.08};
  WheelFactors factors{1.0, 1.0, robot.b_mm};
  double previous = e_max_after(robot, factors);
  // Approximate passes on top of each other converge to the truth (the paper's second pass).
  for (int pass = 0; pass < 3; ++pass) {
    factors = compose(factors, solve_model(robot, factors, false));
    const double now = e_max_after(robot, factors);
    EXPECT_LT(now, previous / 10.0) << "pass " << pass;
    previous = now;
  }
  EXPECT_NEAR(factors.c_r / factors.c_l, robot.e_d, 1e-6);
  EXPECT_NEAR(factors.wheelbase_mm, robot.e_b * robot.b_mm, 1e-4);
  EXPECT_NEAR((factors.c_l + factors.c_r) / 2.0, 1.0, 1e-15);
  // On a perfectly calibrated robot a further pass changes nothing.
  const WheelFactors exact = compose(factors, solve_model(robot, factors, true));
  const WheelFactors again = compose(exact, solve_model(robot, exact, true));
  EXPECT_NEAR(again.c_l, exact.c_l, 1e-12);
  EXPECT_NEAR(again.c_r, exact.c_r, 1e-12);
  EXPECT_NEAR(again.wheelbase_mm, exact.wheelbase_mm, 1e-9);
}

// compose by hand: (0.99·0.995, 1.01·1.005) = (0.98505, 1.01505), mean 1.00005 →
// (0.98500075, 1.01499925); the wheelbase is the result's.
TEST(Umbmark, ComposeMultipliesAndRenormalises) {
  UmbmarkResult second;
  second.c_l = 0.995;
  second.c_r = 1.005;
  second.wheelbase_new_mm = 151.0;
  const WheelFactors out = compose({0.99, 1.01, 150.0}, second);
  EXPECT_NEAR(out.c_l, 0.98500075, 1e-8);
  EXPECT_NEAR(out.c_r, 1.01499925, 1e-8);
  EXPECT_DOUBLE_EQ(out.wheelbase_mm, 151.0);
}

TEST(Umbmark, RefusesBadInputAndWritesNothing) {
  const std::vector<ReturnError> two{{1.0, 2.0}, {3.0, 4.0}};
  const std::vector<ReturnError> one{{1.0, 2.0}};
  UmbmarkResult r;
  r.e_d = 42.0;
  EXPECT_EQ(solve(one, two, 4000.0, 340.0, false, r), UmbmarkStatus::too_few_runs);
  EXPECT_EQ(solve(two, {}, 4000.0, 340.0, false, r), UmbmarkStatus::too_few_runs);
  EXPECT_EQ(solve(two, two, 0.0, 340.0, false, r), UmbmarkStatus::bad_side);
  EXPECT_EQ(solve(two, two, NAN, 340.0, false, r), UmbmarkStatus::bad_side);
  EXPECT_EQ(solve(two, two, 4000.0, -1.0, false, r), UmbmarkStatus::bad_wheelbase);
  EXPECT_EQ(solve({{NAN, 0.0}, {0.0, 0.0}}, two, 4000.0, 340.0, false, r),
            UmbmarkStatus::non_finite);
  EXPECT_EQ(solve(two, {{0.0, INFINITY}, {0.0, 0.0}}, 4000.0, 340.0, false, r),
            UmbmarkStatus::non_finite);
  EXPECT_EQ(solve({{16001.0, 0.0}, {0.0, 0.0}}, two, 4000.0, 340.0, false, r),
            UmbmarkStatus::error_too_large);
  // β = 1 rad on a 100 mm square with b = 340 mm: R = 50/sin(0.5) = 104 mm < b/2.
  const std::vector<ReturnError> cw{{-200.0, -200.0}, {-200.0, -200.0}};
  const std::vector<ReturnError> ccw{{200.0, -200.0}, {200.0, -200.0}};
  EXPECT_EQ(solve(cw, ccw, 100.0, 340.0, false, r), UmbmarkStatus::degenerate);
  EXPECT_EQ(solve(cw, ccw, 100.0, 340.0, true, r), UmbmarkStatus::degenerate);
  EXPECT_EQ(r.e_d, 42.0);
  std::vector<ReturnError> many(umbmark_max_runs + 1);
  EXPECT_EQ(solve(many, two, 4000.0, 340.0, false, r), UmbmarkStatus::too_few_runs);
  EXPECT_STREQ(to_string(UmbmarkStatus::ok), "ok");
  EXPECT_NE(std::string(to_string(UmbmarkStatus::degenerate)).find("degenerate"),
            std::string::npos);
}

TEST(Umbmark, SolveAllocatesNothing) {
  const std::vector<ReturnError> cw{{-40.0, -60.0}, {-20.0, -40.0}};
  const std::vector<ReturnError> ccw{{10.0, -30.0}, {30.0, -10.0}};
  UmbmarkInput in;
  in.cw = cw.data();
  in.cw_count = cw.size();
  in.ccw = ccw.data();
  in.ccw_count = ccw.size();
  in.wheelbase_mm = 340.0;
  UmbmarkResult r;
  const test::AllocationWatch watch;
  in.exact = false;
  EXPECT_EQ(solve_umbmark(in, r), UmbmarkStatus::ok);
  in.exact = true;
  EXPECT_EQ(solve_umbmark(in, r), UmbmarkStatus::ok);
  (void)compose({}, r);
  (void)square_return_error(4000.0, 340.0, 1.001, 1.01, true);
  EXPECT_EQ(watch.allocations(), 0u);
}

}  // namespace
}  // namespace odocal::calib

namespace odocal::calib {
namespace {

// The robot's console solves in float. Over random robots and noisy runs, the float solve must
// agree with the double one far inside what the measurement itself resolves: a tenth of the
// change that moving every cw stop point by 1 mm (a careful tape measurement) makes.
TEST(Umbmark, FloatSolveAgreesWithDoubleWithinATenthOfOneMillimetreOfMeasurement) {
  std::uint64_t state = 12345u;
  auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int robot = 0; robot < 200; ++robot) {
    const double side = uniform(1000.0, 4000.0);
    const double b = uniform(100.0, 400.0);
    const double e_d = uniform(0.99, 1.01);
    const double e_b = uniform(0.97, 1.03);
    std::vector<ReturnError> cw;
    std::vector<ReturnError> ccw;
    std::vector<ReturnErrorOf<float>> cw_f;
    std::vector<ReturnErrorOf<float>> ccw_f;
    for (int run = 0; run < 5; ++run) {
      for (const bool clockwise : {true, false}) {
        ReturnError e = square_return_error(side, b, e_d, e_b, clockwise);
        e.x_mm += uniform(-5.0, 5.0);
        e.y_mm += uniform(-5.0, 5.0);
        (clockwise ? cw : ccw).push_back(e);
        (clockwise ? cw_f : ccw_f)
            .push_back({static_cast<float>(e.x_mm), static_cast<float>(e.y_mm)});
      }
    }
    for (const bool exact : {false, true}) {
      UmbmarkResult ref;
      ASSERT_EQ(solve(cw, ccw, side, b, exact, ref), UmbmarkStatus::ok);
      std::vector<ReturnError> moved = cw;
      for (ReturnError& e : moved) {
        e.x_mm += 1.0;
        e.y_mm += 1.0;
      }
      UmbmarkResult shifted;
      ASSERT_EQ(solve(moved, ccw, side, b, exact, shifted), UmbmarkStatus::ok);
      // Plus two units of float's last bit: a float result cannot be closer than half of one.
      constexpr double ulp = 1.1920928955078125e-7;
      const double tol_d = 0.1 * std::fabs(shifted.e_d - ref.e_d) + 2.0 * ulp * ref.e_d;
      const double tol_b = 0.1 * std::fabs(shifted.e_b - ref.e_b) + 2.0 * ulp * ref.e_b;
      UmbmarkInputOf<float> in;
      in.cw = cw_f.data();
      in.cw_count = cw_f.size();
      in.ccw = ccw_f.data();
      in.ccw_count = ccw_f.size();
      in.side_mm = static_cast<float>(side);
      in.wheelbase_mm = static_cast<float>(b);
      in.exact = exact;
      UmbmarkResultOf<float> r;
      ASSERT_EQ(solve_umbmark(in, r), UmbmarkStatus::ok);
      EXPECT_NEAR(r.e_d, ref.e_d, tol_d) << "robot " << robot << " exact " << exact;
      EXPECT_NEAR(r.e_b, ref.e_b, tol_b) << "robot " << robot << " exact " << exact;
      EXPECT_NEAR(r.c_l, ref.c_l, tol_d);
      EXPECT_NEAR(r.wheelbase_new_mm, ref.wheelbase_new_mm, tol_b * b);
      EXPECT_EQ(r.second_pass_recommended, ref.second_pass_recommended);
    }
  }
}

}  // namespace
}  // namespace odocal::calib
