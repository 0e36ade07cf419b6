#pragma once
/// @file
/// Name lists of the console's enumerations (error codes, fault and self-test flags): one string
/// of NUL-ended names instead of a table of pointers (the robot's flash), counted when compiled
/// so that an enumerator added without its name does not compile.

#include <cstddef>

namespace odocal::console {

/// The NULs in `names`, its literal's own terminator included: the number of names in a list
/// `"a\0b"` (2), or the names plus the empty one that ends a list `"a\0b\0"` (2 + 1).
template <std::size_t Size>
consteval std::size_t nul_count(const char (&names)[Size]) {
  std::size_t count = 0u;
  for (std::size_t i = 0u; i < Size; ++i) {
    count += names[i] == '\0' ? 1u : 0u;
  }
  return count;
}

}  // namespace odocal::console
