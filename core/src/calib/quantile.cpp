#include "odocal/calib/quantile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace odocal::calib {
namespace {

/// Regularized incomplete beta I_x(a, b) by its continued fraction (modified Lentz).
double incomplete_beta(double x, double a, double b) {
  if (x <= 0.0) {
    return 0.0;
  }
  if (x >= 1.0) {
    return 1.0;
  }
  if (x > (a + 1.0) / (a + b + 2.0)) {
    return 1.0 - incomplete_beta(1.0 - x, b, a);
  }
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  constexpr double tiny = 1e-300;
  double f = 1.0, c = 1.0, d = 0.0;
  for (int i = 0; i <= 400; ++i) {
    const int m = i / 2;
    double numerator = 1.0;
    if (i > 0) {
      numerator = i % 2 == 0 ? m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m))
                             : -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
    }
    d = 1.0 + numerator * d;
    d = std::fabs(d) < tiny ? tiny : d;
    d = 1.0 / d;
    c = 1.0 + numerator / c;
    c = std::fabs(c) < tiny ? tiny : c;
    f *= c * d;
    if (std::fabs(1.0 - c * d) < 1e-15) {
      break;
    }
  }
  return std::exp(log_front) * (f - 1.0) / a;
}

/// P(T_dof <= t) for t >= 0 (A&S 26.7.1 through 26.5.27).
double student_t_cdf_upper_half(double t, double dof) {
  return 1.0 - 0.5 * incomplete_beta(dof / (dof + t * t), 0.5 * dof, 0.5);
}

/// Cornish-Fisher expansion of the t quantile about the normal one z, to 1/dof⁴ (A&S 26.7.5).
double cornish_fisher_t(double z, double dof) {
  const double z2 = z * z;
  const double z3 = z2 * z, z5 = z3 * z2, z7 = z5 * z2, z9 = z7 * z2;
  const double g1 = (z3 + z) / 4.0;
  const double g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
  const double g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
  const double g4 = (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / 92160.0;
  const double inv = 1.0 / dof;
  return z + inv * (g1 + inv * (g2 + inv * (g3 + inv * g4)));
}

/// From here on the expansion is exact to double precision, and lgamma's rounding of large
/// arguments would cost the continued fraction digits.
constexpr double cornish_fisher_from_dof = 1e5;

}  // namespace

double sample_quantile(double* values, std::size_t count, double probability) {
  const double h = probability * static_cast<double>(count - 1);
  const auto below = static_cast<std::size_t>(std::floor(h));
  std::nth_element(values, values + below, values + count);
  const double low = values[below];
  if (below + 1 >= count) {
    return low;
  }
  const double high = *std::min_element(values + below + 1, values + count);
  return low + (h - static_cast<double>(below)) * (high - low);
}

double normal_cdf(double z) {
  return 0.5 * std::erfc(-z / std::sqrt(2.0));
}

double normal_quantile(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double inv_sqrt_2pi = 0.39894228040143267794;
  const bool upper = probability >= 0.5;
  const double q = upper ? probability : 1.0 - probability;
  double z = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double step = (normal_cdf(z) - q) / (inv_sqrt_2pi * std::exp(-0.5 * z * z));
    z -= step;
    if (std::fabs(step) < 1e-14 * (1.0 + std::fabs(z))) {
      break;
    }
  }
  return upper ? z : -z;
}

double student_t_quantile(double probability, double dof) {
  if (!(probability > 0.0 && probability < 1.0) || !(dof > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (probability == 0.5) {
    return 0.0;
  }
  if (probability < 0.5) {
    return -student_t_quantile(1.0 - probability, dof);
  }
  if (dof >= cornish_fisher_from_dof) {
    return cornish_fisher_t(normal_quantile(probability), dof);
  }
  double lo = 0.0, hi = 1.0;
  while (student_t_cdf_upper_half(hi, dof) < probability && hi < 1e12) {
    hi *= 2.0;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf_upper_half(mid, dof) < probability ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace odocal::calib
