#pragma once
/// @file
/// Counts heap allocations made by the test process, so a test can assert that core code made
/// none. The test binaries replace the global operator new to count.

#include <cstddef>

namespace odocal::test {

/// Allocations since the process started.
std::size_t allocation_count();

/// Records the count at construction; `allocations()` is how many happened since.
class AllocationWatch {
 public:
  AllocationWatch() : start_(allocation_count()) {}
  [[nodiscard]] std::size_t allocations() const { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace odocal::test
