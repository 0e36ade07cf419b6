#include "run_jury.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "reading_check.hpp"

namespace odocal::host::session {
namespace {

std::string heading_text(double rad) {
  return fmt::format("{:.1f}", plain(std::remainder(rad * deg_per_rad, 360.0)));
}

/// "x 1998.2, y 3.1 mm, heading -18.9 deg (sd 2.3 mm, 2.1 deg)".
std::string predicted_text(const RunJudgement& j, bool heading) {
  const double sd_mm = std::sqrt(0.5 * (j.covariance(0, 0) + j.covariance(1, 1)));
  if (!heading) {
    return fmt::format("x {:.1f}, y {:.1f} mm (sd {:.1f} mm)", plain(j.predicted[0]),
                       plain(j.predicted[1]), sd_mm);
  }
  return fmt::format("x {:.1f}, y {:.1f} mm, heading {} deg (sd {:.1f} mm, {:.1f} deg)",
                     plain(j.predicted[0]), plain(j.predicted[1]), heading_text(j.predicted[2]),
                     sd_mm, std::sqrt(j.covariance(2, 2)) * deg_per_rad);
}

double distance2_of(const RunJudgement& j, const SessionPose& p) {
  return reading_distance2(j, p.x_mm, p.y_mm, p.theta_deg);
}

/// The single slip that best explains `reading` against `j` (none when no slip brings it within
/// `threshold`).
std::optional<SlipCandidate> best_slip(const RunJudgement& j, const SessionPose& reading,
                                       const std::string& typed, const SessionPose& odom,
                                       double threshold) {
  std::optional<SlipCandidate> best;
  double best_d2 = threshold;
  for (const SlipCandidate& s : slip_candidates(reading, typed, odom)) {
    const double d2 = distance2_of(j, s.reading);
    if (d2 <= best_d2) {
      best = s;
      best_d2 = d2;
    }
  }
  return best;
}

nlohmann::json pose_json(const SessionPose& p) {
  return {{"x_mm", p.x_mm},
          {"y_mm", p.y_mm},
          {"theta_deg", p.theta_deg ? nlohmann::json(*p.theta_deg) : nlohmann::json(nullptr)}};
}

/// `out` with `member` left out too.
std::vector<bool> excluding(std::vector<bool> out, std::size_t member) {
  out[member] = true;
  return out;
}

bool turns_in_place(const RunRecord& r) {
  return r.label.rfind("turns", 0) == 0;
}

}  // namespace

RunJury::RunJury(Context& c, const FitNominal& nominal, const FitGeometry& centre)
    : c_(c), nominal_(nominal), centre_(centre), previous_(c.jury) {
  c_.jury = this;
  options_.tape_sigma_mm = 2.0;
}

RunJury::~RunJury() {
  c_.jury = previous_;
}

std::vector<TickLog> RunJury::logs() const {
  std::vector<TickLog> out;
  for (const Member& m : runs_) {
    out.push_back(m.log);
  }
  return out;
}

std::vector<bool> RunJury::left_out() const {
  std::vector<bool> out;
  for (const Member& m : runs_) {
    out.push_back(m.left_out);
  }
  return out;
}

std::vector<TickLog> RunJury::logs_in_use() const {
  std::vector<TickLog> out;
  for (const Member& m : runs_) {
    if (!m.left_out) {
      out.push_back(m.log);
    }
  }
  return out;
}

std::vector<std::size_t> RunJury::runs_in_use() const {
  std::vector<std::size_t> out;
  for (const Member& m : runs_) {
    if (!m.left_out) {
      out.push_back(m.run_index);
    }
  }
  return out;
}

std::size_t RunJury::driven_again() const {
  std::size_t n = 0;
  for (const Member& m : runs_) {
    n += m.again ? 1u : 0u;
  }
  return n;
}

void RunJury::add(std::size_t run_index) {
  Member m;
  m.run_index = run_index;
  const RunRecord& r = c_.runs.at(run_index);
  m.log = tick_log_of(r);
  // A choice the interrupted session recorded for this run holds while its reading is the same.
  const nlohmann::json& before = c_.options.resumed_result;
  if (r.replayed && before.contains("disagreeing_runs") && before["disagreeing_runs"].is_array()) {
    for (const nlohmann::json& e : before["disagreeing_runs"]) {
      if (e.value("run", std::size_t{0}) != run_index + 1 || !e.contains("reading") ||
          !(e["reading"] == pose_json(r.measured))) {
        continue;
      }
      const std::string choice = e.value("choice", std::string());
      m.kept = choice == "kept";
      m.left_out = choice == "driven again" || choice == "left out";
      m.again = choice == "driven again";
      if (m.kept || m.left_out) {
        record_.push_back(e);
      }
    }
  }
  runs_.push_back(std::move(m));
}

ReadingCheck RunJury::check_for(const RunRecord& r, const ReadingCheck& base) const {
  std::size_t predicting = 0;
  for (const Member& m : runs_) {
    predicting += m.left_out ? 0u : 1u;
  }
  if (predicting < 2 || r.ticks.size() < 2) {
    return base;
  }
  const std::vector<TickLog> all = logs();
  const std::vector<bool> out = left_out();
  const TickLog log = tick_log_of(r, false);
  const RunJudgement j = predict_run(all, log, nominal_, centre_, options_, out);
  const FitNominal nominal = nominal_;
  const FitGeometry centre = centre_;
  const AgreementOptions options = options_;
  const SessionPose odom = r.odom;
  return [=](const SessionPose& pose, const std::string& typed) {
    ReadingVerdict v = base ? base(pose, typed) : ReadingVerdict{};
    const double d2 = distance2_of(j, pose);
    if (!v.plausible || d2 <= j.allowed2) {
      return v;
    }
    // One earlier run alone making the difference: the two disagree and the rest cannot tell
    // which is off. This reading is not talked into agreeing with that run; the pair is shown
    // once it is taken (RunJury::settle).
    for (std::size_t m = 0; m < all.size(); ++m) {
      if (out[m] || all[m].rows.empty() || !all[m].rows.back().has_xy) {
        continue;
      }
      std::vector<bool> without = out;
      without[m] = true;
      const RunJudgement alone = predict_run(all, log, nominal, centre, options, without);
      if (distance2_of(alone, pose) <= alone.allowed2) {
        return v;
      }
    }
    v.plausible = false;
    v.decimals = typed.empty() ? decimals_of(pose) : typed_decimals(typed);
    v.problem = fmt::format(
        "the other runs predict {} for this one, and this reading is {:.1f} standard deviations "
        "from that",
        predicted_text(j, pose.theta_deg.has_value()), std::sqrt(d2 / j.dof));
    if (const std::optional<SlipCandidate> s = best_slip(j, pose, typed, odom, j.allowed2)) {
      v.likely = s->what;
      v.suggestion = s->reading;
    }
    return v;
  };
}

RunJury::Shown RunJury::show(const Disagreement& d) {
  const Member& w = runs_[d.judgement.index];
  const RunRecord& r = c_.runs[w.run_index];
  const bool heading = r.measured.theta_deg.has_value();
  Shown shown;
  const std::optional<SlipCandidate> own =
      best_slip(d.judgement, r.measured, "", r.odom, d.judgement.allowed2);
  shown.likely = own ? own->what : std::string();
  // The runs that may be the wrong one instead (their leaving out alone makes this one agree),
  // each with the slip that would make it agree with all the others (this one among them).
  const std::vector<TickLog> all = logs();
  const std::vector<bool> out = left_out();
  std::vector<std::pair<std::size_t, std::optional<SlipCandidate>>> others;
  for (std::size_t i = 0; i < d.partners.size(); ++i) {
    const Member& p = runs_[d.partners[i]];
    const RunRecord& pr = c_.runs[p.run_index];
    // The slip of this run's reading that, undone, lets the run named agree with all the others
    // and agrees with them itself.
    std::optional<SlipCandidate> slip;
    double best = d.judgement.allowed2;
    for (const SlipCandidate& candidate : slip_candidates(pr.measured, "", pr.odom)) {
      std::vector<TickLog> changed = all;
      TickRow& end = changed[d.partners[i]].rows.back();
      end.x_mm = candidate.reading.x_mm;
      end.y_mm = candidate.reading.y_mm;
      end.has_theta = candidate.reading.theta_deg.has_value();
      end.theta_deg = candidate.reading.theta_deg.value_or(0.0);
      const RunJudgement named = predict_run(changed, w.log, nominal_, centre_, options_,
                                             excluding(out, d.judgement.index));
      const RunJudgement itself =
          predict_run(changed, p.log, nominal_, centre_, options_, excluding(out, d.partners[i]));
      const double d2 = distance2_of(named, r.measured);
      if (d2 <= best && distance2_of(itself, candidate.reading) <= itself.allowed2) {
        best = d2;
        slip = candidate;
      }
    }
    if (slip && others.size() < 2) {
      others.emplace_back(d.partners[i], slip);
      shown.partners.push_back(d.partners[i]);
    }
  }
  const auto reads = [this](std::size_t member, const std::optional<SlipCandidate>& slip) {
    const RunRecord& x = c_.runs[runs_[member].run_index];
    return fmt::format(
        "  Run {} ({}) reads {}{}.\n", runs_[member].run_index + 1, x.label,
        pose_text(x.measured, decimals_of(x.measured)),
        slip ? fmt::format("; as {} ({}) it would agree with the others",
                           pose_text(slip->reading, decimals_of(x.measured)), slip->what)
             : std::string());
  };
  if (others.empty()) {
    c_.log << fmt::format(
        "\nCheck run {} ({}): it disagrees with the other runs. They predict {}; it reads {} "
        "({:.1f} standard deviations off).\n",
        w.run_index + 1, r.label, predicted_text(d.judgement, heading),
        pose_text(r.measured, decimals_of(r.measured)),
        std::sqrt(d.judgement.distance2 / d.judgement.dof));
    if (own) {
      c_.log << fmt::format("  Likely {}: did you mean {}?\n", own->what,
                            pose_text(own->reading, decimals_of(r.measured)));
    } else {
      c_.log << "  No single slip (a sign, x and y swapped, metres, a decimal comma) explains it: "
                "check the reading, and whether the run went wrong (a wheel caught, the robot "
                "touched).\n";
    }
    return shown;
  }
  // Two (or three) runs that contradict each other and nothing else: neither is assumed right.
  std::string names = fmt::format("run {}", w.run_index + 1);
  for (const auto& [member, slip] : others) {
    names += fmt::format(" and run {}", runs_[member].run_index + 1);
  }
  c_.log << fmt::format(
      "\nCheck {}: they disagree with each other, and the other runs cannot tell which one is "
      "off.\n",
      names);
  c_.log << reads(d.judgement.index, own);
  for (const auto& [member, slip] : others) {
    c_.log << reads(member, slip);
  }
  // The run just driven can be measured again where it stopped.
  std::size_t latest = d.judgement.index;
  for (const auto& [member, slip] : others) {
    latest = runs_[member].run_index > runs_[latest].run_index ? member : latest;
  }
  if (runs_[latest].run_index + 1 == c_.runs.size() && !c_.runs.back().replayed) {
    c_.log << fmt::format(
        "  The robot is still where run {} stopped: measure it again. If it reads the same, the "
        "other run's reading is the one to check.\n",
        runs_[latest].run_index + 1);
  }
  return shown;
}

void RunJury::note(std::size_t member, const std::string& choice, const Disagreement& d,
                   const std::string& likely) {
  const Member& m = runs_[member];
  const RunRecord& r = c_.runs[m.run_index];
  nlohmann::json partners = nlohmann::json::array();
  for (const std::size_t p : d.partners) {
    partners.push_back(runs_[p].run_index + 1);
  }
  const RunJudgement& j = d.judgement;
  record_.push_back({{"run", m.run_index + 1},
                     {"label", r.label},
                     {"choice", choice},
                     {"reading", pose_json(r.measured)},
                     {"predicted",
                      {{"x_mm", j.predicted[0]},
                       {"y_mm", j.predicted[1]},
                       {"theta_deg", std::remainder(j.predicted[2] * deg_per_rad, 360.0)}}},
                     {"sd",
                      {{"x_mm", std::sqrt(j.covariance(0, 0))},
                       {"y_mm", std::sqrt(j.covariance(1, 1))},
                       {"theta_deg", std::sqrt(j.covariance(2, 2)) * deg_per_rad}}},
                     {"sigmas", std::sqrt(j.distance2 / j.dof)},
                     {"likely", likely},
                     {"partners", partners}});
  c_.partial["disagreeing_runs"] = record_;
}

void RunJury::retype(std::size_t member, std::size_t disagreeing_run) {
  Member& m = runs_[member];
  RunRecord& r = c_.runs[m.run_index];
  // Judged by the others, not by what it read before.
  std::vector<bool> out = left_out();
  out[member] = true;
  const RunJudgement j = predict_run(logs(), m.log, nominal_, centre_, options_, out);
  const double threshold = j.allowed2;
  const SessionPose odom = r.odom;
  const ReadingCheck check = [j, threshold, odom](const SessionPose& pose,
                                                  const std::string& typed) {
    ReadingVerdict v;
    v.decimals = typed_decimals(typed);
    const double d2 = distance2_of(j, pose);
    if (d2 <= threshold) {
      return v;
    }
    v.plausible = false;
    v.problem = fmt::format(
        "the other runs predict {}, and this reading is {:.1f} standard "
        "deviations from that",
        predicted_text(j, pose.theta_deg.has_value()), std::sqrt(d2 / j.dof));
    if (const std::optional<SlipCandidate> s = best_slip(j, pose, typed, odom, threshold)) {
      v.likely = s->what;
      v.suggestion = s->reading;
    }
    return v;
  };
  const std::optional<SessionPose> pose =
      c_.source.retype(r, m.run_index + 1, check, turns_in_place(r));
  if (!pose) {
    return;
  }
  nlohmann::json entry = {{"run", m.run_index + 1},       {"label", r.label},
                          {"choice", "retyped"},          {"reading", pose_json(*pose)},
                          {"was", pose_json(r.measured)}, {"disagreeing_run", disagreeing_run}};
  r.measured = *pose;
  m.log = tick_log_of(r);
  record_.push_back(entry);
  c_.partial["disagreeing_runs"] = record_;
  c_.rewrite_journal();
  c_.log << fmt::format("  Run {}'s reading is now {} (measurements.csv rewritten).\n",
                        m.run_index + 1, pose_text(*pose));
}

nlohmann::json RunJury::checks() const {
  nlohmann::json out = nlohmann::json::array();
  if (runs_.empty()) {
    return out;
  }
  const AgreementResult a = judge_runs(logs(), nominal_, centre_, options_, left_out());
  for (const RunJudgement& j : a.runs) {
    const Member& m = runs_[j.index];
    const RunRecord& r = c_.runs[m.run_index];
    const double predicted_deg = std::remainder(j.predicted[2] * deg_per_rad, 360.0);
    const std::string status = m.again                    ? "driven again"
                               : m.left_out               ? "left out"
                               : m.kept                   ? "kept"
                               : j.distance2 > j.allowed2 ? "disagrees"
                                                          : "agrees";
    out.push_back(
        {{"run", m.run_index + 1},
         {"label", r.label},
         {"measured", pose_json(r.measured)},
         {"predicted",
          {{"x_mm", j.predicted[0]}, {"y_mm", j.predicted[1]}, {"theta_deg", predicted_deg}}},
         {"sd",
          {{"x_mm", std::sqrt(j.covariance(0, 0))},
           {"y_mm", std::sqrt(j.covariance(1, 1))},
           {"theta_deg", std::sqrt(j.covariance(2, 2)) * deg_per_rad}}},
         {"off_mm", std::hypot(r.measured.x_mm - j.predicted[0], r.measured.y_mm - j.predicted[1])},
         {"off_deg", r.measured.theta_deg ? nlohmann::json(std::remainder(
                                                *r.measured.theta_deg - predicted_deg, 360.0))
                                          : nlohmann::json(nullptr)},
         {"sigmas", std::sqrt(j.distance2 / j.dof)},
         {"status", status}});
  }
  return out;
}

std::vector<std::size_t> RunJury::settle() {
  std::vector<std::size_t> again;
  for (int round = 0; round < 64; ++round) {
    std::vector<bool> exempt;
    for (const Member& m : runs_) {
      exempt.push_back(m.kept || m.left_out);  // settled before: never named again
    }
    const AgreementResult a = judge_runs(logs(), nominal_, centre_, options_, left_out(), exempt);
    if (a.disagreements.empty()) {
      break;
    }
    const Disagreement& d = a.disagreements.front();
    const std::size_t member = d.judgement.index;
    const std::size_t number = runs_[member].run_index + 1;
    const Shown shown = show(d);
    const std::string& likely = shown.likely;
    // Only a reading someone typed is typed again (not one the walls took).
    std::string question = "What now?";
    if (c_.source.retypable(number - 1)) {
      question += fmt::format(" r: type run {}'s reading again,", number);
    }
    std::string kept_runs = fmt::format("run {}", number);
    for (const std::size_t p : shown.partners) {
      if (c_.source.retypable(runs_[p].run_index)) {
        question += fmt::format(" r {0}: type run {0}'s again,", runs_[p].run_index + 1);
      }
      kept_runs += fmt::format(" and run {}", runs_[p].run_index + 1);
    }
    question += fmt::format(
        " k: keep {} as read (you checked), d: drive run {} again (this reading is left out): ",
        kept_runs, number);
    bool settled = false;
    while (!settled) {
      const std::optional<std::string> answer = c_.source.ask(question);
      if (!answer) {
        runs_[member].left_out = true;
        note(member, "left out", d, likely);
        c_.log << fmt::format(
            "  Run {} is left out of the fit: its reading disagrees with the other runs and no "
            "one is at the terminal to confirm it (correct it in measurements.csv and --resume, "
            "or type the readings).\n",
            number);
        settled = true;
        continue;
      }
      std::istringstream words(*answer);
      std::string word;
      std::size_t which = 0;
      words >> word;
      const bool with_number = static_cast<bool>(words >> which);
      if (word == "k" && !with_number) {
        runs_[member].kept = true;
        note(member, "kept", d, likely);
        for (const std::size_t p : shown.partners) {
          runs_[p].kept = true;
          note(p, "kept", d, std::string());
        }
        c_.log << fmt::format("  Kept as read: {} (you confirmed it).\n", kept_runs);
        settled = true;
      } else if (word == "d" && !with_number) {
        runs_[member].left_out = true;
        runs_[member].again = true;
        note(member, "driven again", d, likely);
        again.push_back(runs_[member].run_index);
        settled = true;
      } else if (word == "r") {
        const std::size_t target = with_number ? which : number;
        if (target > 0u && !c_.source.retypable(target - 1u)) {
          c_.log << fmt::format("  Run {}'s reading was not typed ({}): answer k or d.\n", target,
                                c_.source.describe());
          continue;
        }
        for (std::size_t i = 0; i < runs_.size() && !settled; ++i) {
          if (runs_[i].run_index + 1 == target) {
            retype(i, number);
            settled = true;
          }
        }
        if (!settled) {
          c_.log << fmt::format("  Run {} is not one of the runs this check judges.\n", target);
        }
      } else {
        c_.log << "  Please answer r, r N, k or d.\n";
      }
    }
  }
  c_.partial["disagreeing_runs"] = record_;
  return again;
}

}  // namespace odocal::host::session
