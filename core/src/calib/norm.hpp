#pragma once
// |(x, y)| for the calibration solvers: float without libm's hypotf (the robot's console; the
// magnitudes here are far from overflow), double with std::hypot (the host, output unchanged).

#include <cmath>

namespace odocal::calib {

inline float norm_of(float x, float y) {
  return std::sqrt(x * x + y * y);
}
inline double norm_of(double x, double y) {
  return std::hypot(x, y);
}

}  // namespace odocal::calib
