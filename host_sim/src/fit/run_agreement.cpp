#include "odocal/host/run_agreement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fit_model.hpp"
#include "odocal/host/fit_noise.hpp"

namespace odocal::host {
namespace {

using fit_detail::ModelSpec;
using fit_detail::ModelState;
using fit_detail::Params;
using fit_detail::Unit;
using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;
using Mat34 = Eigen::Matrix<double, 3, 4>;
constexpr double pi = 3.14159265358979323846;

/// One run seen through the model at a parameter point.
struct Seen {
  bool measured = false;  ///< its last row holds x and y
  bool has_theta = false;
  Eigen::Vector3d reading = Eigen::Vector3d::Zero();  ///< mm, mm, rad
  Eigen::Vector3d end = Eigen::Vector3d::Zero();      ///< the model's end (mm, mm, rad)
  Mat34 jacobian = Mat34::Zero();                     ///< of the end, per ln-parameter
  Eigen::Matrix3d drift = Eigen::Matrix3d::Zero();    ///< end covariance per unit of k
  Eigen::Matrix3d slip = Eigen::Matrix3d::Zero();     ///< per unit of a held slip's variance
  Eigen::Matrix3d floor = Eigen::Matrix3d::Zero();    ///< the tape and the run's own scatter
};

Params params_of(const Vec4& p) {
  Params q(4);
  q << p[0], p[1], p[2], p[3];
  return q;
}

/// The run `log` through the model at `p` (D_L, D_R, b, b_arc; mm).
Seen see(const TickLog& log, const Vec4& p, const FitNominal& nominal, const AgreementOptions& o) {
  Seen s;
  if (log.rows.size() < 2) {
    return s;
  }
  const TickRow& last = log.rows.back();
  s.measured = last.has_xy;
  s.has_theta = last.has_xy && last.has_theta;
  s.reading = {last.x_mm, last.y_mm, last.theta_deg * pi / 180.0};
  // The end of the run whatever its rows hold: integrate a copy whose last row counts as
  // measured, and no other row (only the end is judged).
  TickLog whole = log;
  for (TickRow& row : whole.rows) {
    row.has_xy = row.has_theta = false;
  }
  whole.rows.front() = log.rows.front();
  whole.rows.front().has_xy = whole.rows.front().has_theta = false;
  whole.rows.back().has_xy = true;
  ModelSpec spec;
  spec.kind = FitModelKind::arc_wheelbase;
  spec.k = pi / nominal.counts_per_rev;
  const Unit unit{&whole, 0, whole.rows.size()};
  fit_detail::integrate(unit, params_of(p), spec, true, [&](const TickRow&, const ModelState& m) {
    s.end = {m.x, m.y, m.theta};
    for (int j = 0; j < 4; ++j) {
      // Per ln-parameter: d/d(ln p) = p · d/dp.
      s.jacobian(0, j) = m.dx[j] * p[j];
      s.jacobian(1, j) = m.dy[j] * p[j];
      s.jacobian(2, j) = m.dtheta[j] * p[j];
    }
  });
  FitGeometry g;
  g.wheel_diameter_left_mm = p[0];
  g.wheel_diameter_right_mm = p[1];
  g.wheelbase_mm = p[2];
  g.second_wheelbase_mm = p[3];
  g.model = FitModelKind::arc_wheelbase;
  const EndSensitivity e = end_sensitivity(whole, 0, whole.rows.size() - 1, nominal, g);
  s.drift = e.left + e.right;
  // Slip held over the run: each wheel's size off by a share that stays for the whole run.
  s.slip = s.jacobian.col(0) * s.jacobian.col(0).transpose() +
           s.jacobian.col(1) * s.jacobian.col(1).transpose();
  // The run's size: the length its middle rolled and the angle it turned.
  double length_mm = 0.0, turned_rad = 0.0;
  for (std::size_t i = 1; i < log.rows.size(); ++i) {
    const double dl = spec.k * p[0] * (log.rows[i].count_l - log.rows[i - 1].count_l);
    const double dr = spec.k * p[1] * (log.rows[i].count_r - log.rows[i - 1].count_r);
    length_mm += 0.5 * std::fabs(dl + dr);
    turned_rad += std::fabs(dr - dl) / p[2];
  }
  const double position = std::hypot(o.tape_sigma_mm, o.relative_scatter * length_mm);
  const double heading =
      std::hypot(o.tape_sigma_deg * pi / 180.0, o.relative_turn_scatter * turned_rad);
  s.floor =
      Eigen::Vector3d(position * position, position * position, heading * heading).asDiagonal();
  return s;
}

/// reading − model end, the heading wrapped to the nearest turn.
Eigen::Vector3d residual_of(const Eigen::Vector3d& reading, const Eigen::Vector3d& end) {
  return {reading[0] - end[0], reading[1] - end[1], std::remainder(reading[2] - end[2], 2.0 * pi)};
}

/// The information (inverse covariance) of a reading with covariance `c`; a reading without a
/// heading informs x and y only.
Eigen::Matrix3d information(const Eigen::Matrix3d& c, bool has_theta) {
  if (has_theta) {
    return c.inverse();
  }
  Eigen::Matrix3d w = Eigen::Matrix3d::Zero();
  w.topLeftCorner<2, 2>() = c.topLeftCorner<2, 2>().inverse();
  return w;
}

double log_det(const Eigen::Matrix3d& c, bool has_theta) {
  return has_theta ? std::log(c.determinant()) : std::log(c.topLeftCorner<2, 2>().determinant());
}

/// The prior of the ln-parameters about the centre: scale, ratio, wheelbase, arc share.
Mat4 prior_information(const AgreementOptions& o) {
  Mat4 t;  // (scale, ratio, ln b, arc share) -> (ln D_L, ln D_R, ln b, ln b_arc)
  t << 1.0, -0.5, 0.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0;
  const Vec4 sd(o.prior_scale, o.prior_ratio, o.prior_wheelbase, o.prior_arc_share);
  const Mat4 cov = t * sd.cwiseProduct(sd).asDiagonal() * t.transpose();
  return cov.inverse();
}

/// The runs `use` of `seen` (linearised at a point `delta` away from the centre, ln) combined
/// with the prior, for a drift `k`: the step from that point, its covariance, and the log
/// evidence (the parameters integrated out).
struct Solved {
  Vec4 step = Vec4::Zero();
  Mat4 covariance = Mat4::Identity();
  double evidence = -std::numeric_limits<double>::infinity();
};

/// The noise of the runs beyond the tape: a random walk (k, mm²/mm) and a slip held over a run
/// (its relative sd).
struct Noise {
  double k = 0.0;
  double slip = 0.0;
};

Eigen::Matrix3d covariance_of(const Seen& s, const Noise& n) {
  return s.floor + n.k * s.drift + n.slip * n.slip * s.slip;
}

Solved solve(const std::vector<Seen>& seen, const std::vector<std::size_t>& use, const Vec4& delta,
             const Mat4& prior, const Noise& noise) {
  Mat4 h = prior;
  Vec4 g = -prior * delta;
  double fixed = 0.0;
  std::vector<Eigen::Matrix3d> w(use.size());
  std::vector<Eigen::Vector3d> r(use.size());
  for (std::size_t u = 0; u < use.size(); ++u) {
    const Seen& s = seen[use[u]];
    const Eigen::Matrix3d c = covariance_of(s, noise);
    w[u] = information(c, s.has_theta);
    r[u] = residual_of(s.reading, s.end);
    h += s.jacobian.transpose() * w[u] * s.jacobian;
    g += s.jacobian.transpose() * w[u] * r[u];
    fixed += log_det(c, s.has_theta);
  }
  Solved out;
  const Eigen::LDLT<Mat4> ldlt(h);
  out.step = ldlt.solve(g);
  out.covariance = ldlt.solve(Mat4::Identity());
  double misfit = (delta + out.step).dot(prior * (delta + out.step));
  for (std::size_t u = 0; u < use.size(); ++u) {
    const Eigen::Vector3d e = r[u] - seen[use[u]].jacobian * out.step;
    misfit += e.dot(w[u] * e);
  }
  out.evidence =
      -0.5 * (fixed + misfit + std::log(h.determinant()) - std::log(prior.determinant()));
  return out;
}

/// The noise that the runs `use` make most likely (type-II maximum likelihood on a grid: k in
/// factors of 2 from its floor, the held slip from none to 1 % in factors of 2).
std::pair<Noise, Solved> best_noise(const std::vector<Seen>& seen,
                                    const std::vector<std::size_t>& use, const Vec4& delta,
                                    const Mat4& prior, const AgreementOptions& o) {
  Noise best_noise{o.min_k_mm, 0.0};
  Solved best = solve(seen, use, delta, prior, best_noise);
  for (int i = 0; i <= 24; ++i) {
    for (int j = 0; j <= 7; ++j) {
      const Noise n{o.min_k_mm * std::pow(2.0, i), j == 0 ? 0.0 : 1.25e-4 * std::pow(2.0, j - 1)};
      Solved s = solve(seen, use, delta, prior, n);
      if (s.evidence > best.evidence) {
        best = s;
        best_noise = n;
      }
    }
  }
  return {best_noise, best};
}

/// The geometry point every run is linearised at: the runs `use` with the prior, by Gauss-Newton
/// from the centre (a few steps: the prior keeps it within a few per cent).
Vec4 common_point(const std::vector<TickLog>& logs, const std::vector<std::size_t>& use,
                  const Vec4& centre, const FitNominal& nominal, const Mat4& prior,
                  const AgreementOptions& o) {
  Vec4 delta = Vec4::Zero();
  for (int iteration = 0; iteration < 3; ++iteration) {
    const Vec4 p = centre.cwiseProduct(delta.array().exp().matrix());
    std::vector<Seen> seen(logs.size());
    for (const std::size_t i : use) {
      seen[i] = see(logs[i], p, nominal, o);
    }
    delta += best_noise(seen, use, delta, prior, o).second.step;
  }
  return delta;
}

struct Judge {
  const std::vector<TickLog>& logs;
  const FitNominal& nominal;
  const AgreementOptions& o;
  Vec4 centre;
  Mat4 prior;
  Vec4 delta;  ///< the common point, ln, from the centre
  Vec4 point;  ///< the same, mm
  std::vector<Seen> seen;

  /// What the runs `use` predict for `log` (whose reading, if any, is judged).
  RunJudgement predict(const TickLog& log, const Seen& own, const std::vector<std::size_t>& use) {
    const auto [noise, solved] = best_noise(seen, use, delta, prior, o);
    const Vec4 p = point.cwiseProduct(solved.step.array().exp().matrix());
    const Seen there = see(log, p, nominal, o);
    RunJudgement j;
    j.k_mm = noise.k;
    j.slip = noise.slip;
    j.predicted = there.end;
    j.covariance =
        own.jacobian * solved.covariance * own.jacobian.transpose() + covariance_of(own, noise);
    j.dof = own.has_theta ? 3 : 2;
    // The noise is estimated from the other runs' few readings: the bound widens as they are
    // fewer (as Student's t widens the normal's), by 1 + 4/v, v their readings' numbers less the
    // four parameters.
    double readings = 0.0;
    for (const std::size_t i : use) {
      readings += seen[i].has_theta ? 3.0 : 2.0;
    }
    j.allowed2 = o.threshold * (1.0 + 4.0 / std::max(1.0, readings - 4.0));
    if (own.measured) {
      const Eigen::Vector3d r = residual_of(own.reading, there.end);
      j.distance2 = r.dot(information(j.covariance, own.has_theta) * r);
    }
    return j;
  }
};

std::vector<std::size_t> without(const std::vector<std::size_t>& use, std::size_t a,
                                 std::size_t b = std::numeric_limits<std::size_t>::max()) {
  std::vector<std::size_t> out;
  for (const std::size_t i : use) {
    if (i != a && i != b) {
      out.push_back(i);
    }
  }
  return out;
}

Vec4 centre_of(const FitGeometry& g) {
  return {g.wheel_diameter_left_mm, g.wheel_diameter_right_mm, g.wheelbase_mm,
          g.second_wheelbase_mm > 0.0 ? g.second_wheelbase_mm : g.wheelbase_mm};
}

std::vector<std::size_t> predicting(const std::vector<TickLog>& logs,
                                    const std::vector<bool>& left_out) {
  std::vector<std::size_t> use;
  for (std::size_t i = 0; i < logs.size(); ++i) {
    const bool out = i < left_out.size() && left_out[i];
    if (!out && logs[i].rows.size() >= 2 && logs[i].rows.back().has_xy) {
      use.push_back(i);
    }
  }
  return use;
}

Judge make_judge(const std::vector<TickLog>& logs, const std::vector<std::size_t>& use,
                 const FitNominal& nominal, const FitGeometry& centre, const AgreementOptions& o) {
  Judge j{logs,         nominal,      o, centre_of(centre), prior_information(o),
          Vec4::Zero(), Vec4::Zero(), {}};
  j.delta = common_point(logs, use, j.centre, nominal, j.prior, o);
  j.point = j.centre.cwiseProduct(j.delta.array().exp().matrix());
  j.seen.resize(logs.size());
  for (std::size_t i = 0; i < logs.size(); ++i) {
    j.seen[i] = see(logs[i], j.point, nominal, o);
  }
  return j;
}

}  // namespace

double reading_distance2(const RunJudgement& j, double x_mm, double y_mm,
                         std::optional<double> theta_deg) {
  const Eigen::Vector3d reading(x_mm, y_mm, theta_deg.value_or(0.0) * pi / 180.0);
  const Eigen::Vector3d r = residual_of(reading, j.predicted);
  return r.dot(information(j.covariance, theta_deg.has_value()) * r);
}

RunJudgement predict_run(const std::vector<TickLog>& logs, const TickLog& log,
                         const FitNominal& nominal, const FitGeometry& centre,
                         const AgreementOptions& options, const std::vector<bool>& left_out) {
  const std::vector<std::size_t> use = predicting(logs, left_out);
  Judge judge = make_judge(logs, use, nominal, centre, options);
  const Seen own = see(log, judge.point, nominal, options);
  return judge.predict(log, own, use);
}

AgreementResult judge_runs(const std::vector<TickLog>& logs, const FitNominal& nominal,
                           const FitGeometry& centre, const AgreementOptions& options,
                           const std::vector<bool>& left_out, const std::vector<bool>& exempt) {
  AgreementResult out;
  std::vector<std::size_t> use = predicting(logs, left_out);
  std::optional<Judge> judge;
  judge.emplace(make_judge(logs, use, nominal, centre, options));
  for (std::size_t i = 0; i < logs.size(); ++i) {
    if (judge->seen[i].measured) {
      RunJudgement j = judge->predict(logs[i], judge->seen[i], without(use, i));
      j.index = i;
      out.runs.push_back(j);
    }
  }
  // The worst run that disagrees is named; the rest are judged again without it (a second wrong
  // reading is then found by runs the first no longer bends), at most three times.
  std::vector<RunJudgement> now = out.runs;
  for (int round = 0; round < 3; ++round) {
    const RunJudgement* worst = nullptr;
    for (const RunJudgement& j : now) {
      const bool kept = j.index < exempt.size() && exempt[j.index];
      if (!kept && j.distance2 > j.allowed2 &&
          (worst == nullptr || j.distance2 / j.dof > worst->distance2 / worst->dof)) {
        worst = &j;
      }
    }
    if (worst == nullptr) {
      break;
    }
    Disagreement d{*worst, {}};
    std::vector<std::pair<double, std::size_t>> partners;
    for (const std::size_t other : use) {
      if (other == d.judgement.index) {
        continue;
      }
      const RunJudgement alone =
          judge->predict(logs[d.judgement.index], judge->seen[d.judgement.index],
                         without(use, d.judgement.index, other));
      if (alone.distance2 <= alone.allowed2) {
        partners.emplace_back(alone.distance2, other);
      }
    }
    std::sort(partners.begin(), partners.end());
    for (const auto& [distance2, index] : partners) {
      d.partners.push_back(index);
    }
    out.disagreements.push_back(d);
    use = without(use, d.judgement.index);
    judge.emplace(make_judge(logs, use, nominal, centre, options));
    std::vector<RunJudgement> next;
    for (const RunJudgement& j : now) {
      if (j.index == d.judgement.index) {
        continue;
      }
      bool named = false;
      for (const Disagreement& e : out.disagreements) {
        named = named || e.judgement.index == j.index;
      }
      if (!named) {
        RunJudgement again =
            judge->predict(logs[j.index], judge->seen[j.index], without(use, j.index));
        again.index = j.index;
        next.push_back(again);
      }
    }
    now = next;
  }
  return out;
}

}  // namespace odocal::host
