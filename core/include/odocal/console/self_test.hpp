#pragma once
/// @file
/// The wiring self-test's state machine (console command `selftest`, docs/wiring.md): drives each
/// wheel alone, slowly and briefly, lets it coast to rest, and says what the wiring got wrong.

#include <cstdint>

#include "odocal/console/settings.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/name_list.hpp"

namespace odocal::console {

/// One self-test at a time, watched from the console's `poll`. Two timed drives the control loop
/// runs as it would a `drive` (its trials); the test only reads counts, illegal transitions and
/// duties, and replaces each drive with zero set-points when its time is up. Main loop only.
class SelfTest {
 public:
  /// What the test can find, bit n of `faults()` for enumerator n. A wheel's faults come in
  /// left / right pairs: the right one is the left one's bit shifted by one.
  enum class Fault : std::uint8_t {
    left_reversed,   ///< the wheel counted against its command
    right_reversed,  ///<
    left_still,      ///< it did not count
    right_still,     ///<
    crossed,         ///< the other wheel's encoder counted
    left_illegal,    ///< illegal transitions while it was driven
    right_illegal,   ///<
    left_weak,       ///< it turned only above `stall_duty`
    right_weak,      ///<
    count,           ///< not a fault: the number of them
  };
  /// The names of the faults in bit order, each ended by a NUL, the list by an empty name
  /// (Console::flag_names).
  static constexpr char fault_names[] =
      "left_reversed\0right_reversed\0left_still\0right_still\0crossed\0left_illegal\0"
      "right_illegal\0left_weak\0right_weak\0";
  static_assert(nul_count(fault_names) == static_cast<std::size_t>(Fault::count) + 1u,
                "one name per SelfTest::Fault, in its order");

  /// Which wheels to test.
  enum class Wheels : std::uint8_t {
    both,  ///< left, then right
    left,  ///< the left one alone (the host then measures where the robot went)
    right,
  };

  /// What `start` or `advance` came to.
  enum class Step : std::uint8_t {
    running,  ///< call `advance` again later
    done,     ///< finished: `faults()` and `counts()` hold the result
    refused,  ///< the drive refused to move (a latched fault): the test is over
  };

  /// A test of `loop`'s wheels with the parameters in force in `settings`.
  SelfTest(drive::ControlLoop& loop, const Settings& settings) : loop_(loop), settings_(settings) {}

  /// Starts a test (the console checked that the robot is still). @param now_us the console's
  /// clock. @return running or refused.
  Step start(Wheels wheels, std::uint32_t now_us);
  /// Moves the test on: ends a drive whose time is up (or that runs away), reads a coasted wheel,
  /// starts the next. Acknowledges the stall fault a miswired wheel causes when done.
  Step advance(std::uint32_t now_us);
  /// Abandons the test (the caller stops the loop).
  void cancel() { phase_ = Phase::off; }
  [[nodiscard]] bool running() const { return phase_ != Phase::off; }

  /// The faults found, bit n for Fault n.
  [[nodiscard]] unsigned faults() const { return faults_; }
  /// Counts moved while a wheel was driven: left drive: left, right encoder; right drive: the
  /// same (`ll lr rl rr` of the reply).
  [[nodiscard]] const std::int32_t* counts() const { return counts_; }

 private:
  /// 0 off; 2w + 1 wheel w driven; 2w + 2 wheel w coasting (w: 0 left, 1 right).
  enum class Phase : std::uint8_t { off, left_driven, left_coasting, right_driven, right_coasting };

  Step start_wheel(unsigned wheel, std::uint32_t now_us);
  /// True when `counts` tell a turning wheel from jitter.
  [[nodiscard]] bool counted(std::int32_t counts) const;

  drive::ControlLoop& loop_;
  const Settings& settings_;
  Phase phase_ = Phase::off;
  std::uint8_t last_ = 1u;  ///< the last wheel to test (0 left, 1 right)
  std::uint16_t faults_ = 0u;
  float duty_ = 0.0f;              ///< largest |duty| of the driven wheel in this phase
  float enough_ = 0.0f;            ///< counts that tell a turning wheel from jitter
  std::uint32_t due_us_ = 0u;      ///< end of this phase
  std::int32_t start_[2] = {};     ///< counts when the wheel's drive began: left, right
  std::uint32_t illegal_[2] = {};  ///< illegal transitions then
  std::int32_t counts_[4] = {};    ///< see counts()
};

}  // namespace odocal::console
