#pragma once
/// @file
/// Storage for an object that start-up code builds exactly once, from values known only at run
/// time (the clock actually reached, the board's parts).

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
    return *::new (static_cast<void*>(bytes_)) T{std::forward<Args>(args)...};
  }

 private:
  alignas(T) unsigned char bytes_[sizeof(T)];
};

}  // namespace odocal::firmware
