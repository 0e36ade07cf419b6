// `odocal fit` intervals: the runs are independent clusters of residuals (the slip of a run
// carries on along its path, so the rows of one run are not independent, the runs are).
//
// Standard error: the cluster-robust sandwich with the bias-reduced (CR2, Bell & McCaffrey 2002)
// residual adjustment, on the fit linearised at the estimate. With few runs this standard error
// is itself a noisy estimate, the more so when only some runs inform a parameter (the straight
// lines and the wheel size): its reference distribution is a Student t with the Bell-McCaffrey
// degrees of freedom (Imbens & Kolesár 2016), and, without assuming normal errors, the wild
// cluster bootstrap-t (each run's adjusted residuals times one random weight, refitted and
// studentized by its own CR2 standard error). All of it reduces to 3×3 algebra per run: with
// N_g = J_gᵀJ_g, the CR2 adjustment A_g = (I − H_gg)^(−1/2) = I + J_g W_g J_gᵀ.

#include "fit_interval.hpp"

#include <algorithm>
#include <cmath>

#include "odocal/calib/quantile.hpp"
#include "odocal/calib/random.hpp"

namespace odocal::host::fit_detail {
namespace {

using Matrix3 = Square;  // the parameters' count square (3 or 4), fixed maximum size
using Vector3 = Params;

/// Per unit: N_g (scaled JᵀJ), P_g = I + N_g W_g (so that J_gᵀ A_g v = P_g J_gᵀ v), and
/// s_g = J_gᵀ A_g r_g.
struct Cluster {
  Matrix3 n;
  Matrix3 w;
  Matrix3 pmat;
  Vector3 s;
};

/// CR2 covariance (scaled parameters) of residual sums c_g = J_gᵀ e_g.
Matrix3 cr2_meat(const std::vector<Cluster>& clusters, const std::vector<Vector3>& c) {
  const Eigen::Index np = c.front().size();
  Matrix3 meat = Matrix3::Zero(np, np);
  for (std::size_t g = 0; g < clusters.size(); ++g) {
    const Vector3 s = clusters[g].pmat * c[g];
    meat.noalias() += s * s.transpose();
  }
  return meat;
}

/// The clusters' CR2 algebra at the fit: N_g, W_g, P_g, s_g, the residual sums c_g and
/// M = (Σ N_g)⁻¹ (false when that is singular).
bool cr2_clusters(const std::vector<UnitRows>& rows, const Params& p,
                  std::vector<Cluster>& clusters, std::vector<Vector3>& c, Matrix3& m) {
  // Relative parameters (ln p): columns scaled by p.
  const std::size_t g_count = rows.size();
  const Eigen::Index np = p.size();
  const int npi = static_cast<int>(np);
  const Matrix3 identity = Matrix3::Identity(np, np);
  clusters.assign(g_count, Cluster{});
  c.assign(g_count, Vector3{});
  Matrix3 jtj = Matrix3::Zero(np, np);
  for (std::size_t g = 0; g < g_count; ++g) {
    const Eigen::MatrixXd j = rows[g].jacobian * p.asDiagonal();
    clusters[g].n = j.transpose() * j;
    c[g] = j.transpose() * rows[g].residual;
    jtj += clusters[g].n;
  }
  const Eigen::FullPivLU<Matrix3> lu(jtj);
  if (!lu.isInvertible()) {
    return false;
  }
  m = lu.inverse();
  for (std::size_t g = 0; g < g_count; ++g) {
    // N_g = V S² Vᵀ; H_gg = U K Uᵀ with K = S Vᵀ M V S; (I − H_gg)^(−1/2) − I = U F Uᵀ with
    // F = Q((1 − λ)^(−1/2) − 1)Qᵀ; U = J_g V S⁻¹, so W_g = V S⁻¹ F S⁻¹ Vᵀ.
    Cluster& cl = clusters[g];
    const Eigen::SelfAdjointEigenSolver<Matrix3> ne(cl.n);
    const double top = std::max(ne.eigenvalues()[np - 1], 0.0);
    Vector3 inv_s = Vector3::Zero(np);
    for (int i = 0; i < npi; ++i) {
      const double v = ne.eigenvalues()[i];
      inv_s[i] = v > 1e-12 * top && v > 0.0 ? 1.0 / std::sqrt(v) : 0.0;
    }
    const Matrix3 vs = ne.eigenvectors() * inv_s.asDiagonal();  // V S⁻¹ (dropped directions 0)
    const Matrix3 s_vt = ne.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
                         ne.eigenvectors().transpose();  // S Vᵀ
    const Matrix3 kmat = s_vt * m * s_vt.transpose();
    const Eigen::SelfAdjointEigenSolver<Matrix3> ke(kmat);
    Vector3 f = Vector3::Zero(np);
    for (int i = 0; i < npi; ++i) {
      const double lambda = std::clamp(ke.eigenvalues()[i], 0.0, 1.0 - 1e-6);
      f[i] = 1.0 / std::sqrt(1.0 - lambda) - 1.0;
    }
    const Matrix3 fm = ke.eigenvectors() * f.asDiagonal() * ke.eigenvectors().transpose();
    cl.w = vs * fm * vs.transpose();
    cl.pmat = identity + cl.n * cl.w;
    cl.s = cl.pmat * c[g];
  }
  return true;
}

/// Bell-McCaffrey degrees of freedom of parameter l: with a_g = A_g J_g M e_l, the G×G matrix
/// diag(|a_g|²) − Sᵀ M S (S's columns J_gᵀ a_g) has trace² / |·|²_F degrees of freedom.
double bell_mccaffrey_dof(const std::vector<Cluster>& clusters, const Matrix3& m, int l) {
  const std::size_t g_count = clusters.size();
  const Vector3 u = m.col(l);
  std::vector<double> a2(g_count);
  std::vector<Vector3> sv(g_count);
  double trace = 0.0;
  for (std::size_t g = 0; g < g_count; ++g) {
    const Vector3 z = u + clusters[g].w * (clusters[g].n * u);
    sv[g] = clusters[g].n * z;
    a2[g] = z.dot(sv[g]);
    trace += a2[g] - sv[g].dot(m * sv[g]);
  }
  double frob = 0.0;
  for (std::size_t g = 0; g < g_count; ++g) {
    const Vector3 ms = m * sv[g];
    for (std::size_t h = 0; h < g_count; ++h) {
      const double e = (g == h ? a2[g] : 0.0) - sv[h].dot(ms);
      frob += e * e;
    }
  }
  return frob > 0.0 ? trace * trace / frob : 1.0;
}

/// Wild cluster bootstrap-t (Webb's six-point weights): r*_g = w_g A_g r_g, δ* = −M Σ w_g s_g,
/// and the refit's residual sums J_gᵀ e*_g = w_g s_g + N_g δ*. Fills out.lo and out.hi from the
/// t* quantiles, about p with out.se.
void wild_bootstrap_t(const std::vector<Cluster>& clusters, const Matrix3& m, const Params& p,
                      std::uint32_t replicates, std::uint64_t seed, double tail,
                      ClusterInterval& out) {
  const std::size_t g_count = clusters.size();
  const Eigen::Index np = p.size();
  const int npi = static_cast<int>(np);
  static const double webb[6] = {-std::sqrt(1.5), -1.0, -std::sqrt(0.5),
                                 std::sqrt(0.5),  1.0,  std::sqrt(1.5)};
  calib::Random random(seed);
  std::vector<double> t_star[4];
  std::vector<double> weight(g_count);
  std::vector<Vector3> c_star(g_count);
  for (std::uint32_t b = 0; b < replicates; ++b) {
    Vector3 sum = Vector3::Zero(np);
    for (std::size_t g = 0; g < g_count; ++g) {
      weight[g] = webb[random.below(6)];
      sum += weight[g] * clusters[g].s;
    }
    const Vector3 delta = -(m * sum);
    for (std::size_t g = 0; g < g_count; ++g) {
      c_star[g] = weight[g] * clusters[g].s + clusters[g].n * delta;
    }
    const Matrix3 cov_star = m * cr2_meat(clusters, c_star) * m;
    for (int l = 0; l < npi; ++l) {
      const double se = std::sqrt(std::max(cov_star(l, l), 0.0));
      t_star[l].push_back(se > 0.0 ? delta[l] / se : 0.0);
    }
  }
  for (int l = 0; l < npi && replicates > 0; ++l) {
    const double q_hi = calib::sample_quantile(t_star[l].data(), t_star[l].size(), 1.0 - tail);
    const double q_lo = calib::sample_quantile(t_star[l].data(), t_star[l].size(), tail);
    out.lo[l] = p[l] * (1.0 - q_hi * out.se[l]);
    out.hi[l] = p[l] * (1.0 - q_lo * out.se[l]);
  }
}

}  // namespace

std::vector<UnitRows> unit_rows(const std::vector<Unit>& units, const Params& p, const ModelSpec& k,
                                double heading_length_mm) {
  std::vector<UnitRows> out;
  out.reserve(units.size());
  for (const Unit& unit : units) {
    std::vector<double> r;
    std::vector<Params> j;
    integrate(unit, p, k, true, [&](const TickRow& row, const ModelState& s) {
      if (row.has_xy) {
        r.push_back(s.x - row.x_mm);
        j.push_back(s.dx);
        r.push_back(s.y - row.y_mm);
        j.push_back(s.dy);
      }
      if (row.has_theta) {
        r.push_back(heading_length_mm * heading_error(s.theta, row));
        j.push_back(heading_length_mm * s.dtheta);
      }
    });
    UnitRows u;
    u.residual = Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
    u.jacobian.resize(static_cast<Eigen::Index>(j.size()), p.size());
    for (std::size_t i = 0; i < j.size(); ++i) {
      u.jacobian.row(static_cast<Eigen::Index>(i)) = j[i].transpose();
    }
    out.push_back(std::move(u));
  }
  return out;
}

ClusterInterval cluster_interval(const std::vector<UnitRows>& rows, const Params& p,
                                 std::uint32_t replicates, std::uint64_t seed, double level) {
  ClusterInterval out;
  if (rows.size() < 2) {
    return out;
  }
  std::vector<Cluster> clusters;
  std::vector<Vector3> c;
  Matrix3 m;
  if (!cr2_clusters(rows, p, clusters, c, m)) {
    return out;
  }
  const Matrix3 cov = m * cr2_meat(clusters, c) * m;
  const double tail = 0.5 * (1.0 - level);
  for (int l = 0; l < static_cast<int>(p.size()); ++l) {
    for (int j = 0; j < static_cast<int>(p.size()); ++j) {
      out.cov[l][j] = cov(l, j);
    }
    out.se[l] = std::sqrt(std::max(cov(l, l), 0.0));
    out.dof[l] = bell_mccaffrey_dof(clusters, m, l);
    const double t = calib::student_t_quantile(1.0 - tail, std::max(out.dof[l], 1.0));
    out.t_lo[l] = p[l] * (1.0 - t * out.se[l]);
    out.t_hi[l] = p[l] * (1.0 + t * out.se[l]);
  }
  wild_bootstrap_t(clusters, m, p, replicates, seed, tail, out);
  out.ok = true;
  return out;
}

}  // namespace odocal::host::fit_detail
