#pragma once
/// @file
/// Name lists of the core's enumerations (error codes, modes, paths, statuses, fault and
/// self-test flags): one string of NUL-ended names instead of a table of pointers (the robot's
/// flash), counted when compiled so that an enumerator added without its name does not compile.

#include <cstddef>

namespace odocal {

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

/// The name at `index` in a list of NUL-ended names: the one after `index` NULs. The caller
/// keeps `index` below the list's count. Not inlined: one copy for every list.
[[gnu::noinline]] inline const char* name_at(const char* names, unsigned index) {
  while (index > 0u) {
    if (*names++ == '\0') {
      --index;
    }
  }
  return names;
}

}  // namespace odocal
