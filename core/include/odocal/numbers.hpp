#pragma once
/// @file
/// The project's one copy of π (C++17 has no `std::numbers`): `pi_v<float>` on the robot,
/// `pi` (double) on hosts. Both are the nearest value of their type.

namespace odocal {

template <typename T>
inline constexpr T pi_v = static_cast<T>(3.14159265358979323846);

inline constexpr double pi = pi_v<double>;

}  // namespace odocal
