#pragma once
/// @file
/// A small dense linear solve for the walls' fits (host only).

#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

namespace odocal::host::walls {

/// Solves the small dense system A x = b in place (Gaussian elimination, partial pivoting):
/// false when A is singular (a pivot of 1e-300 or less), b then partly eliminated.
template <std::size_t n>
bool solve_dense(std::array<std::array<double, n>, n> a, std::array<double, n>& b) {
  for (std::size_t col = 0u; col < n; ++col) {
    std::size_t pivot = col;
    for (std::size_t row = col + 1u; row < n; ++row) {
      if (std::fabs(a[row][col]) > std::fabs(a[pivot][col])) {
        pivot = row;
      }
    }
    if (!(std::fabs(a[pivot][col]) > 1e-300)) {
      return false;
    }
    std::swap(a[pivot], a[col]);
    std::swap(b[pivot], b[col]);
    for (std::size_t row = col + 1u; row < n; ++row) {
      const double factor = a[row][col] / a[col][col];
      for (std::size_t k = col; k < n; ++k) {
        a[row][k] -= factor * a[col][k];
      }
      b[row] -= factor * b[col];
    }
  }
  for (std::size_t col = n; col-- > 0u;) {
    for (std::size_t k = col + 1u; k < n; ++k) {
      b[col] -= a[col][k] * b[k];
    }
    b[col] /= a[col][col];
  }
  return true;
}

}  // namespace odocal::host::walls
