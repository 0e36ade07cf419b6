#pragma once
/// @file
/// Sine/cosine and angle wrapping for bounded angles (headings in [-pi, pi], per-tick
/// half-increments, the UMBmark square's few turns), without newlib's full-range reduction:
/// `sinf`/`cosf` pull ~3.6 KB of Payne-Hanek tables and code into the robot image, double
/// `sin`/`cos` ~4.5 KB, `remainderf`/`fmodf` ~0.7 KB. Quadrant reduction by a split pi/2
/// (Cody-Waite), then Taylor polynomials on [-pi/4, pi/4] whose truncation error is far below the
/// type's rounding. Accuracy (tests/core/math/bounded_trig_test.cpp, against std::sin/std::cos):
/// a few roundings of the type for |x| up to 2^12 pi/2 (float) or 2^20 pi/2 (double); beyond that
/// the reduction loses precision, so such inputs are outside the contract. ISR-safe, no state.

#include <cstdint>
#include <numbers>

namespace odocal::math {

template <typename T>
struct SinCosOf {
  T sin;
  T cos;
};
using SinCos = SinCosOf<float>;

namespace trig_detail {

template <typename T>
struct HalfPi;
// pi/2 = head + mid + tail with head and mid short enough that k * head and k * mid are exact for
// |k| < 2^12.
template <>
struct HalfPi<float> {
  static constexpr float head = 1.5703125f;               // 8 significant bits
  static constexpr float mid = 4.837512969970703125e-4f;  // 12 significant bits
  static constexpr float tail = 7.549790126404332e-08f;   // pi/2 - head - mid, rounded
};
// Double: head with 33 significant bits (k * head exact for |k| < 2^20); tail's own rounding
// error is 3.5e-27.
template <>
struct HalfPi<double> {
  static constexpr double head = 1.5707963267341256;
  static constexpr double mid = 6.077100506506192e-11;
  static constexpr double tail = 0.0;
};

// Nearest integer (half away from zero) without lround.
template <typename T>
std::int32_t nearest(T v) {
  return static_cast<std::int32_t>(v < T(0) ? v - T(0.5) : v + T(0.5));
}

template <typename T>
T reduce(T x, T k) {
  return ((x - k * HalfPi<T>::head) - k * HalfPi<T>::mid) - k * HalfPi<T>::tail;
}

// sin r and cos r for |r| <= pi/4, z = r^2. Float: Taylor to r^9 / r^10 (truncation < 2e-9);
// double: to r^17 / r^18 (truncation < 1e-18).
inline SinCosOf<float> kernel(float r, float z) {
  const float s =
      r + r * z * (-1.0f / 6.0f + z * (1.0f / 120.0f + z * (-1.0f / 5040.0f + z / 362880.0f)));
  const float c =
      1.0f - 0.5f * z +
      z * z * (1.0f / 24.0f + z * (-1.0f / 720.0f + z * (1.0f / 40320.0f - z / 3628800.0f)));
  return {s, c};
}
inline SinCosOf<double> kernel(double r, double z) {
  // Horner from the highest term: terms alternate in sign, term(n+2) = term(n) * -z/((n+1)(n+2)).
  double s = 0.0;
  for (int n = 17; n >= 3; n -= 2) {
    s = (1.0 - s) * z / static_cast<double>(n * (n - 1));
  }
  double c = 0.0;
  for (int n = 18; n >= 2; n -= 2) {
    c = (1.0 - c) * z / static_cast<double>(n * (n - 1));
  }
  return {r - r * s, 1.0 - c};
}

}  // namespace trig_detail

/// sin and cos of `x` (float or double), |x| < 2^12 pi/2 for float, 2^20 pi/2 for double.
template <typename T>
SinCosOf<T> sin_cos(T x) {
  using namespace trig_detail;
  constexpr T two_over_pi = T(0.636619772367581343075535053490057448);
  const std::int32_t k = nearest(x * two_over_pi);
  const T r = reduce(x, static_cast<T>(k));
  const SinCosOf<T> sc = kernel(r, r * r);
  switch (static_cast<std::uint32_t>(k) & 3u) {
    case 0u:
      return sc;
    case 1u:
      return {sc.cos, -sc.sin};
    case 2u:
      return {-sc.sin, -sc.cos};
    default:
      return {-sc.cos, sc.sin};
  }
}

/// `angle` wrapped into [-pi, pi] (as `std::remainder(angle, 2 pi)` for |angle| < 2^12 pi).
inline float wrap_pi(float angle) {
  using namespace trig_detail;
  constexpr float quarter_over_pi_half = 0.159154943091895335769f;  // 1/(2 pi)
  // Whole turns are multiples of 4 quadrants, which the split pi/2 removes exactly.
  const std::int32_t turns = nearest(angle * quarter_over_pi_half);
  float r = reduce(angle, static_cast<float>(turns * 4));
  constexpr float pi = std::numbers::pi_v<float>;
  if (r > pi) {
    r -= 2.0f * pi;
  } else if (r < -pi) {
    r += 2.0f * pi;
  }
  return r;
}

namespace trig_detail {

// atan t for 0 <= t <= 1: above tan(pi/8), atan t = pi/4 + atan((t - 1)/(t + 1)), which brings
// the argument u within |u| <= tan(pi/8) = 0.4142; there the Taylor series to u^19 truncates
// below 0.4142^21 / 21 < 5e-10, far under the float rounding of the result.
inline float atan_unit(float t) {
  constexpr float tan_pi_8 = 0.41421356237309504880f;
  const bool shifted = t > tan_pi_8;
  const float u = shifted ? (t - 1.0f) / (t + 1.0f) : t;
  const float z = u * u;
  float series = 1.0f / 19.0f;
  for (int n = 17; n >= 3; n -= 2) {  // Horner: 1/n - z * (...)
    series = 1.0f / static_cast<float>(n) - z * series;
  }
  const float atan_u = u - u * z * series;
  return shifted ? 0.78539816339744830962f + atan_u : atan_u;
}

}  // namespace trig_detail

/// The angle of the vector (x, y), in [-pi, pi], as `std::atan2` for finite arguments, without
/// newlib's atan2f/atanf (750 B). Error within 3e-7 rad of the exact angle (two roundings of pi;
/// tests/core/math/bounded_trig_test.cpp). atan2(0, 0) is 0. ISR-safe, no state.
inline float arctan2(float y, float x) {
  constexpr float pi = std::numbers::pi_v<float>;
  const float ax = x < 0.0f ? -x : x;
  const float ay = y < 0.0f ? -y : y;
  float angle = 0.0f;
  if (ay <= ax) {
    angle = ax > 0.0f ? trig_detail::atan_unit(ay / ax) : 0.0f;
  } else {
    angle = 0.5f * pi - trig_detail::atan_unit(ax / ay);
  }
  if (x < 0.0f) {
    angle = pi - angle;
  }
  return y < 0.0f ? -angle : angle;
}

/// atan(v) for finite v, in (-pi/2, pi/2), within 3e-7 rad (see arctan2).
inline float arctan(float v) {
  return arctan2(v, 1.0f);
}

}  // namespace odocal::math
