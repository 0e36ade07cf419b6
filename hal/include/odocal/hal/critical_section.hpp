#pragma once
/// @file
/// Critical section: excludes the edge and tick contexts while a multi-word value is read.

namespace odocal::hal {

/// Masks the interrupts (bare metal) or takes a lock (Linux) that the edge context uses.
/// Nesting is allowed: the backend restores the previous state on exit.
class CriticalSection {
 public:
  /// Enters the section. ISR-safe.
  void enter() { do_enter(); }
  /// Leaves the section entered last. ISR-safe.
  void exit() { do_exit(); }

 protected:
  ~CriticalSection() = default;

 private:
  virtual void do_enter() = 0;
  virtual void do_exit() = 0;
};

/// RAII guard: enters on construction, exits on destruction.
class CriticalGuard {
 public:
  explicit CriticalGuard(CriticalSection& section) : section_(section) { section_.enter(); }
  ~CriticalGuard() { section_.exit(); }
  CriticalGuard(const CriticalGuard&) = delete;
  CriticalGuard& operator=(const CriticalGuard&) = delete;

 private:
  CriticalSection& section_;
};

}  // namespace odocal::hal
