// `odocal fit`: Levenberg-Marquardt on the tick logs, and the parameters of each model.

#include <algorithm>
#include <cmath>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {

const char* parameter_name(FitModelKind kind, int i) {
  static const char* const first[3] = {"wheel_diameter_left_mm", "wheel_diameter_right_mm",
                                       "wheelbase_mm"};
  if (i < 3) {
    return first[i];
  }
  return kind == FitModelKind::arc_wheelbase ? "wheelbase_arc_mm" : "wheelbase_at_1radps_mm";
}

Solved solve(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
             const Params& start, const ModelSpec& k, double heading_length_mm) {
  Solved out;
  out.heading_length_mm = heading_length_mm;
  Params p = start;
  const Eigen::Index np = p.size();
  Normal n = normal_equations(units, pick, p, k, heading_length_mm, true);
  double lambda = 1e-4;
  for (std::size_t it = 0; it < 200; ++it) {
    out.iterations = it + 1;
    if (!std::isfinite(n.cost)) {
      return out;
    }
    Square a = n.jtj;
    for (Eigen::Index i = 0; i < np; ++i) {
      a(i, i) += lambda * std::max(n.jtj(i, i), 1e-30);
    }
    const Params step = a.ldlt().solve(-n.jtr);
    const Params trial = p + step;
    if (!step.allFinite() || !(trial.minCoeff() > 0.0)) {
      lambda *= 10.0;
      if (lambda > 1e12) {
        break;
      }
      continue;
    }
    // Steps below 1e-10 of a parameter are far below anything a log can tell: converged.
    const double relative_step = (step.array().abs() / p.array()).maxCoeff();
    if (relative_step < 1e-10) {
      break;
    }
    const Normal m = normal_equations(units, pick, trial, k, heading_length_mm, true);
    if (std::isfinite(m.cost) && m.cost <= n.cost) {
      const bool flat = n.cost - m.cost <= 1e-12 * n.cost;
      p = trial;
      n = m;
      lambda = std::max(lambda * 0.1, 1e-12);
      if (flat || relative_step < 1e-9) {
        break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e12 || relative_step < 1e-9) {
        break;  // no step lowers the cost: at the minimum to working precision
      }
    }
  }
  out.ok = std::isfinite(n.cost) && p.allFinite() && p.minCoeff() > 0.0;
  out.p = p;
  out.normal = n;
  return out;
}

ModelSpec spec_for(FitModelKind kind, const FitNominal& nominal) {
  ModelSpec spec;
  spec.kind = kind;
  spec.k = pi / nominal.counts_per_rev;
  spec.rate_per_count_s = spec.k * nominal.wheel_diameter_mm / nominal.wheelbase_mm;
  return spec;
}

Params params_of(const FitGeometry& g) {
  Params p(parameter_count(g.model));
  p[0] = g.wheel_diameter_left_mm;
  p[1] = g.wheel_diameter_right_mm;
  p[2] = g.wheelbase_mm;
  if (p.size() > 3) {
    p[3] = g.second_wheelbase_mm;
  }
  return p;
}

FitGeometry geometry_of(const Params& p, FitModelKind kind) {
  FitGeometry g{p[0], p[1], p[2], kind, p.size() > 3 ? p[3] : 0.0};
  return g;
}

Params start_for(FitModelKind kind, const Params& one) {
  Params p(parameter_count(kind));
  p.head(3) = one.head(3);
  if (p.size() > 3) {
    p[3] = one[2];
  }
  return p;
}

std::vector<Unit> whole_runs(const std::vector<TickLog>& logs) {
  std::vector<Unit> units;
  for (const TickLog& log : logs) {
    units.push_back(Unit{&log, 0, log.rows.size()});
  }
  return units;
}

std::vector<std::size_t> every_unit(std::size_t count) {
  std::vector<std::size_t> all(count);
  for (std::size_t i = 0; i < all.size(); ++i) {
    all[i] = i;
  }
  return all;
}

}  // namespace odocal::host::fit_detail
