// Every run judged by all the others (run_agreement.hpp): a wrong reading is named however early
// it came, a clean session's readings never are, and what the others predict is where the robot
// really ends, within the spread the judgement states.

#include "odocal/host/run_agreement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "synthetic_logs.hpp"

namespace odocal::host {
namespace {

using synthetic::Move;
using synthetic::pi;
using synthetic::Truth;

/// The robot the firmware is told of (the judgement's centre) and the one that drives.
constexpr FitNominal kNominal{60.0, 150.0, 1440.0};
const Truth kTruth{59.85, 60.1, 152.0, 1440.0};
/// The runs are driven by the odometry of the robot told: its wheels roll what that one's would.
const Truth kTold{60.0, 60.0, 150.0, 1440.0};

FitGeometry centre() {
  FitGeometry g;
  g.wheel_diameter_left_mm = kNominal.wheel_diameter_mm;
  g.wheel_diameter_right_mm = kNominal.wheel_diameter_mm;
  g.wheelbase_mm = kNominal.wheelbase_mm;
  return g;
}

enum class Leg { line, spin_ccw, spin_cw, arc_left, arc_right };

std::vector<Move> moves_of(Leg run, const Truth& t) {
  switch (run) {
    case Leg::line:
      return {synthetic::line(2000.0)};
    case Leg::spin_ccw:
      return {synthetic::turn(10.0 * pi, t)};
    case Leg::spin_cw:
      return {synthetic::turn(-10.0 * pi, t)};
    case Leg::arc_left:
      return {synthetic::arc(400.0 * 1.5 * pi, 400.0, t)};
    case Leg::arc_right:
      return {synthetic::arc(400.0 * 1.5 * pi, -400.0, t)};
  }
  return {};
}

/// A session's runs on a robot that slips: each run's wheels `slip` (relative sd) off their size
/// for the whole run (slip that holds, as on a floor), the tape reading 1.5 mm and 0.3 deg off
/// (sd). The last row holds the reading.
std::vector<TickLog> session(const std::vector<Leg>& runs, std::mt19937& rng, double slip) {
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<TickLog> logs;
  for (const Leg run : runs) {
    Truth t = kTruth;
    t.left_mm *= 1.0 + slip * unit(rng);
    t.right_mm *= 1.0 + slip * unit(rng);
    TickLog log = synthetic::make_log(t, moves_of(run, kTold), synthetic::Truthing::end_only);
    // The counts are those of the true robot (make_log counts with t's wheel sizes): the slipping
    // run is kept as counted, its end where the slipping wheels took it.
    TickRow& end = log.rows.back();
    end.x_mm += 1.5 * unit(rng);
    end.y_mm += 1.5 * unit(rng);
    end.theta_deg = std::remainder(end.theta_deg + 0.3 * unit(rng), 360.0);
    logs.push_back(log);
  }
  return logs;
}

const std::vector<Leg> kFirstRound = {Leg::line, Leg::spin_ccw, Leg::arc_left,
                                      Leg::line, Leg::spin_cw,  Leg::arc_right};

bool names(const AgreementResult& r, std::size_t run) {
  for (const Disagreement& d : r.disagreements) {
    if (d.judgement.index == run) {
      return true;
    }
    for (const std::size_t p : d.partners) {
      if (p == run) {
        return true;
      }
    }
  }
  return false;
}

TEST(RunAgreement, CleanSessionsOnASlippingRobotNameNoRun) {
  // 40 sessions of 14 runs each, slip 0.2 % per wheel per run: no reading is wrong, so none may
  // be named (a false alarm would ask an owner to doubt a right reading).
  std::mt19937 rng(7);
  std::vector<Leg> runs = kFirstRound;
  for (const Leg r : {Leg::spin_ccw, Leg::line, Leg::arc_left, Leg::spin_cw, Leg::arc_right,
                      Leg::line, Leg::spin_ccw, Leg::arc_right}) {
    runs.push_back(r);
  }
  int named = 0;
  for (int s = 0; s < 40; ++s) {
    const AgreementResult r =
        judge_runs(session(runs, rng, 0.002), kNominal, centre(), AgreementOptions{});
    named += static_cast<int>(r.disagreements.size());
    EXPECT_EQ(r.runs.size(), runs.size());
  }
  EXPECT_EQ(named, 0);
}

TEST(RunAgreement, PredictionsCoverWhereTheRobotEnds) {
  // What the others predict for a run, against where the run really ended: the standardised
  // errors of the position, pooled over many runs, have a variance near 1 or below (the judgement
  // is never overconfident) and are not wildly conservative (a check that allows everything
  // catches nothing).
  std::mt19937 rng(11);
  double sum2 = 0.0;
  int n = 0;
  for (int s = 0; s < 20; ++s) {
    const std::vector<TickLog> logs = session(kFirstRound, rng, 0.001);
    const AgreementResult r = judge_runs(logs, kNominal, centre(), AgreementOptions{});
    for (const RunJudgement& j : r.runs) {
      const TickRow& end = logs[j.index].rows.back();
      sum2 += std::pow(end.x_mm - j.predicted[0], 2) / j.covariance(0, 0) +
              std::pow(end.y_mm - j.predicted[1], 2) / j.covariance(1, 1);
      n += 2;
    }
  }
  const double variance = sum2 / n;
  EXPECT_LT(variance, 1.5);
  EXPECT_GT(variance, 0.02);
}

TEST(RunAgreement, AWrongSignHeadingAtTheFirstTurnInPlaceIsNamed) {
  // The first turn in place's heading typed with the wrong sign: the turn the other way already
  // tells the wheelbase, so the two disagree; with one more turn each way the others tell which.
  std::mt19937 rng(3);
  std::vector<TickLog> logs = session(kFirstRound, rng, 0.0005);
  TickRow& wrong = logs[1].rows.back();
  ASSERT_GT(std::fabs(wrong.theta_deg), 3.0);  // the 152 mm robot told 150 mm under-turns
  wrong.theta_deg = -wrong.theta_deg;
  const AgreementResult first = judge_runs(logs, kNominal, centre(), AgreementOptions{});
  ASSERT_FALSE(first.disagreements.empty());
  EXPECT_TRUE(names(first, 1));
  // The reading as it should have been agrees with the others' prediction.
  const Disagreement& d = first.disagreements.front();
  if (d.judgement.index == 1) {
    EXPECT_LT(reading_distance2(d.judgement, wrong.x_mm, wrong.y_mm, -wrong.theta_deg), 16.0);
  }
  // Two more turns in place: run 1 alone disagrees, and no partner can take the blame.
  for (const Leg r : {Leg::spin_ccw, Leg::spin_cw}) {
    logs.push_back(session({r}, rng, 0.0005).front());
  }
  const AgreementResult later = judge_runs(logs, kNominal, centre(), AgreementOptions{});
  ASSERT_EQ(later.disagreements.size(), 1u);
  EXPECT_EQ(later.disagreements.front().judgement.index, 1u);
  EXPECT_TRUE(later.disagreements.front().partners.empty());
}

TEST(RunAgreement, ReadingSlipsOnLinesAndArcsAreNamed) {
  // x and y swapped on a line, the sign of y on an arc, centimetres on a line: each named alone.
  std::mt19937 rng(5);
  const std::vector<Leg> runs = {Leg::line,    Leg::spin_ccw,  Leg::arc_left, Leg::line,
                                 Leg::spin_cw, Leg::arc_right, Leg::line,     Leg::arc_left};
  for (int slip = 0; slip < 3; ++slip) {
    std::vector<TickLog> logs = session(runs, rng, 0.0005);
    const std::size_t bad = slip == 1 ? 7 : 3;
    TickRow& end = logs[bad].rows.back();
    if (slip == 0) {
      std::swap(end.x_mm, end.y_mm);
    } else if (slip == 1) {
      end.y_mm = -end.y_mm;
    } else {
      end.x_mm /= 10.0;
      end.y_mm /= 10.0;
    }
    const AgreementResult r = judge_runs(logs, kNominal, centre(), AgreementOptions{});
    ASSERT_FALSE(r.disagreements.empty()) << "slip " << slip;
    EXPECT_EQ(r.disagreements.front().judgement.index, bad) << "slip " << slip;
  }
}

TEST(RunAgreement, AKeptRunIsNotNamedAndALeftOutRunPredictsNothing) {
  std::mt19937 rng(9);
  std::vector<TickLog> logs = session(kFirstRound, rng, 0.0005);
  logs[0].rows.back().y_mm += 300.0;  // a line 300 mm off to the side
  const AgreementResult plain = judge_runs(logs, kNominal, centre(), AgreementOptions{});
  ASSERT_FALSE(plain.disagreements.empty());
  EXPECT_EQ(plain.disagreements.front().judgement.index, 0u);
  std::vector<bool> flag(logs.size(), false);
  flag[0] = true;
  EXPECT_TRUE(
      judge_runs(logs, kNominal, centre(), AgreementOptions{}, {}, flag).disagreements.empty() ||
      !names(judge_runs(logs, kNominal, centre(), AgreementOptions{}, {}, flag), 0));
  // Left out, run 0 no longer bends the others: each of them agrees.
  const AgreementResult out = judge_runs(logs, kNominal, centre(), AgreementOptions{}, flag);
  for (const Disagreement& d : out.disagreements) {
    EXPECT_EQ(d.judgement.index, 0u);
  }
}

}  // namespace
}  // namespace odocal::host
