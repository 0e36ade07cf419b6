// The random part of odometry error (Chong & Kleeman's per-wheel model): propagation along a
// logged path and the maximum-likelihood estimate beside `odocal fit`. See fit_noise.hpp.

#include "odocal/host/fit_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>

#include "odocal/calib/quantile.hpp"
#include "odocal/drive/robot_model.hpp"

namespace odocal::host {
namespace {

using std::numbers::pi;

/// One independent end residual and the matrices its covariance is made of, restricted to the
/// components measured at its end (x and y, heading, or all three).
struct Stretch {
  Eigen::VectorXd residual;
  Eigen::MatrixXd left;     ///< A_l
  Eigen::MatrixXd right;    ///< A_r
  Eigen::MatrixXd measure;  ///< M (per unit of σ_m²)
};

/// Deterministic normal deviates on every platform (splitmix64, Box-Muller).
class Normal {
 public:
  explicit Normal(std::uint64_t seed) : state_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(next() >> 11) * 0x1.0p-53;
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * pi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * pi * u2);
  }

 private:
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

bool full_truth(const TickRow& row) {
  return row.has_xy && row.has_theta;
}

/// The stretches of one log: restart at a row with full ground truth once the mean wheel travel
/// since the stretch's start reaches `stretch_mm`; the end of the log closes the last one when it
/// is the only one or at least half as long.
void stretches_of(const TickLog& log, const FitNominal& nominal, const FitGeometry& geometry,
                  const NoiseOptions& o, std::vector<Stretch>& out) {
  const std::vector<TickRow>& rows = log.rows;
  const double mm_per_count = pi / nominal.counts_per_rev;
  Eigen::Matrix3d shape = Eigen::Matrix3d::Zero();
  shape(0, 0) = 1.0;
  shape(1, 1) = 1.0;
  shape(2, 2) = 1.0 / (o.heading_length_mm * o.heading_length_mm);
  const auto close = [&](std::size_t first, std::size_t last) {
    // The last row with ground truth in (first, last].
    std::size_t end = last;
    while (end > first && !rows[end].has_xy && !rows[end].has_theta) {
      --end;
    }
    if (end == first) {
      return;
    }
    const EndSensitivity s = end_sensitivity(log, first, end, nominal, geometry);
    std::vector<int> dims;
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    if (rows[end].has_xy) {
      r[0] = s.end[0] - rows[end].x_mm;
      r[1] = s.end[1] - rows[end].y_mm;
      dims.push_back(0);
      dims.push_back(1);
    }
    if (rows[end].has_theta) {
      r[2] = std::remainder(s.end[2] - rows[end].theta_deg * pi / 180.0, 2.0 * pi);
      dims.push_back(2);
    }
    Eigen::Matrix3d m = shape;
    if (full_truth(rows[first])) {
      // The start pose is measured too: its noise moves the end by J·ν.
      Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
      j(0, 2) = -(s.end[1] - s.start[1]);
      j(1, 2) = s.end[0] - s.start[0];
      m += j * shape * j.transpose();
    }
    Stretch st;
    const auto n = static_cast<Eigen::Index>(dims.size());
    st.residual.resize(n);
    st.left.resize(n, n);
    st.right.resize(n, n);
    st.measure.resize(n, n);
    for (Eigen::Index a = 0; a < n; ++a) {
      st.residual[a] = r[dims[a]];
      for (Eigen::Index b = 0; b < n; ++b) {
        st.left(a, b) = s.left(dims[a], dims[b]);
        st.right(a, b) = s.right(dims[a], dims[b]);
        st.measure(a, b) = m(dims[a], dims[b]);
      }
    }
    out.push_back(std::move(st));
  };
  std::size_t first = 0;
  double travel = 0.0;
  bool closed_any = false;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    travel += 0.5 * mm_per_count *
              (geometry.wheel_diameter_left_mm * std::fabs(rows[i].count_l - rows[i - 1].count_l) +
               geometry.wheel_diameter_right_mm * std::fabs(rows[i].count_r - rows[i - 1].count_r));
    if (travel >= o.stretch_mm && full_truth(rows[i]) && i + 1 < rows.size()) {
      close(first, i);
      closed_any = true;
      first = i;
      travel = 0.0;
    }
  }
  if (!closed_any || travel >= 0.5 * o.stretch_mm) {
    close(first, rows.size() - 1);
  }
}

struct Likelihood {
  double value = 0.0;  ///< log-likelihood (without the constant)
  Eigen::Vector3d score = Eigen::Vector3d::Zero();
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  bool ok = true;
};

Likelihood likelihood(const std::vector<Stretch>& stretches,
                      const std::vector<Eigen::VectorXd>& residuals, const Eigen::Vector3d& p) {
  Likelihood l;
  for (std::size_t j = 0; j < stretches.size(); ++j) {
    const Stretch& s = stretches[j];
    const Eigen::MatrixXd* b[3] = {&s.left, &s.right, &s.measure};
    const Eigen::MatrixXd cov = p[0] * s.left + p[1] * s.right + p[2] * s.measure;
    const Eigen::LLT<Eigen::MatrixXd> llt(cov);
    if (llt.info() != Eigen::Success) {
      l.ok = false;
      return l;
    }
    const Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(cov.rows(), cov.cols()));
    const Eigen::VectorXd w = inv * residuals[j];
    double log_det = 0.0;
    for (Eigen::Index i = 0; i < cov.rows(); ++i) {
      log_det += 2.0 * std::log(llt.matrixL()(i, i));
    }
    l.value += -0.5 * (log_det + residuals[j].dot(w));
    Eigen::MatrixXd ib[3];
    for (int c = 0; c < 3; ++c) {
      ib[c] = inv * *b[c];
      l.score[c] += 0.5 * (w.dot(*b[c] * w) - ib[c].trace());
    }
    for (int c = 0; c < 3; ++c) {
      for (int d = c; d < 3; ++d) {
        const double v = 0.5 * (ib[c].cwiseProduct(ib[d].transpose())).sum();
        l.information(c, d) += v;
        if (d != c) {
          l.information(d, c) += v;
        }
      }
    }
  }
  return l;
}

/// Maximum likelihood of (k_l, k_r, σ_m²) >= 0 by Fisher scoring with an active set at the bounds
/// and step halving. σ_m² is kept above `floor_v` so that every covariance stays positive.
Eigen::Vector3d maximise(const std::vector<Stretch>& stretches,
                         const std::vector<Eigen::VectorXd>& residuals, Eigen::Vector3d p,
                         std::size_t& iterations) {
  constexpr double floor_v = 1e-8;
  Likelihood current = likelihood(stretches, residuals, p);
  iterations = 0;
  for (; iterations < 300 && current.ok; ++iterations) {
    bool free[3];
    for (int c = 0; c < 3; ++c) {
      const double bound = c == 2 ? floor_v : 0.0;
      free[c] = !(p[c] <= bound && current.score[c] <= 0.0);
    }
    Eigen::Matrix3d info = current.information;
    Eigen::Vector3d score = current.score;
    for (int c = 0; c < 3; ++c) {
      if (!free[c]) {
        info.row(c).setZero();
        info.col(c).setZero();
        info(c, c) = 1.0;
        score[c] = 0.0;
      }
    }
    // Scale to unit diagonal: the parameters differ by orders of magnitude.
    Eigen::Vector3d scale;
    for (int c = 0; c < 3; ++c) {
      scale[c] = info(c, c) > 0.0 ? 1.0 / std::sqrt(info(c, c)) : 1.0;
    }
    const Eigen::Matrix3d scaled = scale.asDiagonal() * info * scale.asDiagonal();
    const Eigen::Vector3d step =
        scale.asDiagonal() * scaled.ldlt().solve(scale.asDiagonal() * score).eval();
    bool improved = false;
    for (double t = 1.0; t > 1e-6; t *= 0.5) {
      Eigen::Vector3d q = p + t * step;
      q[0] = std::max(q[0], 0.0);
      q[1] = std::max(q[1], 0.0);
      q[2] = std::max(q[2], floor_v);
      const Likelihood next = likelihood(stretches, residuals, q);
      if (next.ok && next.value >= current.value - 1e-12 * std::fabs(current.value)) {
        const double change = (q - p)
                                  .cwiseQuotient(p.cwiseAbs() + Eigen::Vector3d::Constant(1e-12))
                                  .cwiseAbs()
                                  .maxCoeff();
        p = q;
        improved = next.value > current.value;
        current = next;
        if (change < 1e-9) {
          improved = false;
        }
        break;
      }
    }
    if (!improved) {
      break;
    }
  }
  return p;
}

/// A starting point: the diagonal moments r_d² ≈ k_l·A_l,dd + k_r·A_r,dd + v·M_dd by least
/// squares, each kept positive.
Eigen::Vector3d start_point(const std::vector<Stretch>& stretches) {
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const Stretch& s : stretches) {
    for (Eigen::Index d = 0; d < s.residual.size(); ++d) {
      const Eigen::Vector3d a(s.left(d, d), s.right(d, d), s.measure(d, d));
      const double w = 1.0 / std::max(a.squaredNorm(), 1e-300);
      ata += w * a * a.transpose();
      atb += w * a * s.residual[d] * s.residual[d];
    }
  }
  Eigen::Vector3d p = ata.ldlt().solve(atb);
  const double k = std::max({p[0], p[1], 1e-6});
  p[0] = std::max(p[0], 0.1 * k);
  p[1] = std::max(p[1], 0.1 * k);
  p[2] = std::max(p[2], 1e-4);
  return p;
}

}  // namespace

EndSensitivity end_sensitivity(const TickLog& log, std::size_t first, std::size_t last,
                               const FitNominal& nominal, const FitGeometry& geometry) {
  EndSensitivity s;
  const std::vector<TickRow>& rows = log.rows;
  const double mm_per_count = pi / nominal.counts_per_rev;
  if (full_truth(rows[first])) {
    s.start = Eigen::Vector3d(rows[first].x_mm, rows[first].y_mm, rows[first].theta_deg * pi / 180);
  }
  // First pass: the odometry (the one model's exact arcs, drive::model::advance, with the arc
  // wheelbase where the fit chose it), keeping each increment's travel, mid heading, wheelbase
  // in force and the pose after it.
  struct Step {
    double dl, dr, mid, b, x, y;
  };
  const double b_arc =
      geometry.model == FitModelKind::arc_wheelbase ? geometry.second_wheelbase_mm : 0.0;
  std::vector<Step> steps;
  steps.reserve(last - first);
  drive::model::PoseOf<double> pose{s.start[0], s.start[1], s.start[2]};
  for (std::size_t i = first + 1; i <= last; ++i) {
    const double count_l = rows[i].count_l - rows[i - 1].count_l;
    const double count_r = rows[i].count_r - rows[i - 1].count_r;
    const double dl = mm_per_count * count_l * geometry.wheel_diameter_left_mm;
    const double dr = mm_per_count * count_r * geometry.wheel_diameter_right_mm;
    const double b = drive::model::wheelbase_for(geometry.wheelbase_mm, b_arc, count_l, count_r);
    const double mid = pose.theta + 0.5 * (dr - dl) / b;
    drive::model::advance(pose, dl, dr, b);
    steps.push_back(Step{dl, dr, mid, b, pose.x, pose.y});
    s.left_travel_mm += std::fabs(dl);
    s.right_travel_mm += std::fabs(dr);
  }
  s.end = Eigen::Vector3d(pose.x, pose.y, pose.theta);
  // Second pass: an error ε in one increment's left travel moves that increment's end by
  // (ε/2)·(cos, sin) of its heading and turns the robot by −ε/b, which swings the rest of the path
  // about that point (right wheel: +ε/b). Variance k·|travel| per increment, independent.
  for (const Step& st : steps) {
    const double c = 0.5 * std::cos(st.mid);
    const double sn = 0.5 * std::sin(st.mid);
    const double ex = (pose.x - st.x) / st.b;
    const double ey = (pose.y - st.y) / st.b;
    const Eigen::Vector3d g_left(c + ey, sn - ex, -1.0 / st.b);
    const Eigen::Vector3d g_right(c - ey, sn + ex, 1.0 / st.b);
    s.left.noalias() += std::fabs(st.dl) * g_left * g_left.transpose();
    s.right.noalias() += std::fabs(st.dr) * g_right * g_right.transpose();
  }
  return s;
}

Eigen::Matrix3d end_covariance(const EndSensitivity& s, const WheelNoise& noise) {
  return noise.k_l * s.left + noise.k_r * s.right;
}

NoiseEstimate estimate_wheel_noise(const std::vector<TickLog>& runs, const FitNominal& nominal,
                                   const FitGeometry& geometry, const NoiseOptions& o) {
  NoiseEstimate e;
  e.level = o.level;
  e.heading_length_mm = o.heading_length_mm;
  std::vector<Stretch> stretches;
  for (const TickLog& log : runs) {
    if (log.rows.size() >= 2) {
      stretches_of(log, nominal, geometry, o, stretches);
    }
  }
  e.stretches = stretches.size();
  if (stretches.size() < 3) {
    e.error =
        "the random error growth needs at least 3 runs (or stretches of runs) measured at "
        "their end, got " +
        std::to_string(stretches.size());
    return e;
  }
  std::vector<Eigen::VectorXd> residuals;
  for (const Stretch& s : stretches) {
    residuals.push_back(s.residual);
  }
  const Eigen::Vector3d p = maximise(stretches, residuals, start_point(stretches), e.iterations);
  e.noise = WheelNoise{p[0], p[1]};
  e.measure_sigma_mm = std::sqrt(p[2]);
  e.ok = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  if (!e.ok) {
    e.error = "the random error growth did not converge";
    return e;
  }
  if (o.replicates == 0) {
    return e;
  }
  // Parametric bootstrap: residuals drawn from the fitted model, the estimate redone.
  std::vector<Eigen::MatrixXd> roots;
  for (const Stretch& s : stretches) {
    const Eigen::MatrixXd cov = p[0] * s.left + p[1] * s.right + p[2] * s.measure;
    roots.push_back(Eigen::LLT<Eigen::MatrixXd>(cov).matrixL());
  }
  Normal normal(o.seed);
  std::vector<double> k_l, k_r, sigma;
  for (std::uint32_t b = 0; b < o.replicates; ++b) {
    std::vector<Eigen::VectorXd> drawn(stretches.size());
    for (std::size_t j = 0; j < stretches.size(); ++j) {
      Eigen::VectorXd z(roots[j].rows());
      for (Eigen::Index i = 0; i < z.size(); ++i) {
        z[i] = normal();
      }
      drawn[j] = roots[j] * z;
    }
    std::size_t iterations = 0;
    const Eigen::Vector3d q = maximise(stretches, drawn, p, iterations);
    k_l.push_back(q[0]);
    k_r.push_back(q[1]);
    sigma.push_back(std::sqrt(q[2]));
  }
  const double tail = 0.5 * (1.0 - o.level);
  const auto percentile = [](std::vector<double>& values, double q) {
    return calib::sample_quantile(values.data(), values.size(), q);
  };
  e.ci_k_l = FitInterval{percentile(k_l, tail), percentile(k_l, 1.0 - tail)};
  e.ci_k_r = FitInterval{percentile(k_r, tail), percentile(k_r, 1.0 - tail)};
  e.ci_measure_sigma_mm = FitInterval{percentile(sigma, tail), percentile(sigma, 1.0 - tail)};
  e.has_ci = true;
  e.replicates = o.replicates;
  return e;
}

nlohmann::json noise_json(const NoiseEstimate& e) {
  if (!e.ok) {
    return {{"error", e.error}, {"stretches", e.stretches}};
  }
  const auto interval = [&e](const FitInterval& i) {
    return e.has_ci ? nlohmann::json::array({i.lo, i.hi}) : nlohmann::json(nullptr);
  };
  return {{"k_l", e.noise.k_l},
          {"k_r", e.noise.k_r},
          {"measure_sigma_mm", e.measure_sigma_mm},
          {"ci",
           {{"k_l", interval(e.ci_k_l)},
            {"k_r", interval(e.ci_k_r)},
            {"measure_sigma_mm", interval(e.ci_measure_sigma_mm)}}},
          {"units", "mm^2/mm"},
          {"model", "chong-kleeman"},
          {"stretches", e.stretches},
          {"level", e.level},
          {"replicates", e.replicates},
          {"heading_length_mm", e.heading_length_mm}};
}

Ros2Covariance ros2_covariance(const WheelNoise& noise, double wheelbase_mm, double speed_mps,
                               const RosVelocityEstimate& estimate, double distance_m,
                               double unobserved) {
  // k in mm²/mm is 1e-3 m²/m; the wheelbase in m.
  const double k = (noise.k_l + noise.k_r) * 1e-3;
  const double b = wheelbase_mm * 1e-3;
  const double d = distance_m;
  // The controller's velocity: the mean of the last W per-update wheel differences, i.e. the
  // travel over the last W updates (telescoping) divided by W·T.
  const double averaged_s = static_cast<double>(estimate.window) / estimate.update_rate_hz;
  Ros2Covariance c;
  c.pose[0] = 0.25 * k * d;
  c.pose[1] = k / (b * b) * d * d * d / 3.0;
  c.pose[5] = k / (b * b) * d;
  c.twist[0] = 0.25 * k * speed_mps / averaged_s;
  c.twist[1] = c.twist[0];
  c.twist[5] = k / (b * b) * speed_mps / averaged_s;
  for (const int i : {2, 3, 4}) {
    c.pose[i] = unobserved;
    c.twist[i] = unobserved;
  }
  return c;
}

std::string ros2_covariance_note(const WheelNoise& noise, double distance_m, double speed_mps,
                                 const RosVelocityEstimate& estimate) {
  char note[320];
  std::snprintf(note, sizeof note,
                "# covariances: k_l %.4g, k_r %.4g mm^2/mm; pose after %.4g m straight; twist at "
                "%.4g m/s as diff_drive_controller estimates it: update rate %.4g Hz, "
                "velocity_rolling_window_size %zu (docs/ros.md)\n",
                noise.k_l, noise.k_r, distance_m, speed_mps, estimate.update_rate_hz,
                estimate.window);
  return note;
}

std::string noise_text(const NoiseEstimate& e) {
  std::ostringstream out;
  char line[256];
  if (!e.ok) {
    out << "Random error growth: not estimated (" << e.error << ")\n";
    return out.str();
  }
  out << "Random error growth (Chong & Kleeman: variance of each wheel's travel per mm rolled), "
      << e.stretches << " end residuals\n";
  const auto row = [&](const char* name, double value, const FitInterval& ci, const char* unit) {
    std::snprintf(line, sizeof line, "  %-24s %12.4g %-8s", name, value, unit);
    out << line;
    if (e.has_ci) {
      std::snprintf(line, sizeof line, " %.0f %% interval [%.4g, %.4g]", 100.0 * e.level, ci.lo,
                    ci.hi);
      out << line;
    }
    out << '\n';
  };
  row("k_l", e.noise.k_l, e.ci_k_l, "mm^2/mm");
  row("k_r", e.noise.k_r, e.ci_k_r, "mm^2/mm");
  row("measure_sigma_mm", e.measure_sigma_mm, e.ci_measure_sigma_mm, "mm");
  return out.str();
}

}  // namespace odocal::host
