#pragma once
/// @file
/// Storage for an object that start-up code builds exactly once, from values known only at run
/// time (the clock actually reached, the board's parts).

#include <cstddef>
#include <cstring>
#include <new>
#include <utility>

namespace odocal::firmware {

/// What a function-local `static T x{...}` gives, without its guard variable and the test of it
/// (the start-up functions run once; ten guards were ~150 B of the robot's flash). The bytes are
/// zero-filled .bss like any static object; `make` constructs the object in them (placement new:
/// no heap). Never destroyed: the firmware does not return from main. Call `make` once.
template <typename T>
class BuiltOnce {
 public:
  template <typename... Args>
  T& make(Args&&... args) {
    if constexpr (sizeof(T) > zero_first_above) {
      // Zero (as they are already, which the compiler cannot know): the constructor's stores of
      // zero into them are then dead and dropped (the build keeps the storage's value at the
      // start of a constructor, -flifetime-dse=1; toolchain/odocal.cmake). A few hundred bytes
      // of the robot's flash for the control loop and the console.
      std::memset(bytes_, 0, sizeof bytes_);
    }
    return *::new (static_cast<void*>(bytes_)) T{std::forward<Args>(args)...};
  }

 private:
  /// Below this size a memset call costs more than the zero stores it makes dead.
  static constexpr std::size_t zero_first_above = 256u;
  alignas(T) unsigned char bytes_[sizeof(T)];
};

}  // namespace odocal::firmware
