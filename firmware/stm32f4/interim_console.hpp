#pragma once
/// @file
/// A minimal console for the image until the core console (core/console) is wired in: the
/// prompt, line echo, and `version`, `status`, `odom [reset]`, `drive <v> <w> [ms]`, `stop`,
/// `run umbmark-cw|umbmark-ccw|line <m>`, in the DESIGN reply format. Main-loop only.

#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/hal/block_store.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/hal/stm32f4/systick_timer.hpp"

namespace odocal::firmware {

class InterimConsole {
 public:
  InterimConsole(hal::ByteStream& stream, drive::ControlLoop& loop,
                 hal::stm32f4::SysTickTimer& timer, hal::BlockStore& store, const BoardInfo& info,
                 bool watchdog_reset);

  /// Prints the banner and the first prompt.
  void begin();
  /// Handles pending input. @return true when it did something (call again before sleeping).
  bool poll();

 private:
  void handle_line();
  void reply(const char* text);
  void put(const char* text);
  void put_number(float value, int decimals);
  void put_unsigned(std::uint32_t value);

  hal::ByteStream& stream_;
  drive::ControlLoop& loop_;
  hal::stm32f4::SysTickTimer& timer_;
  const BoardInfo& info_;
  bool watchdog_reset_;
  char line_[128]{};
  std::size_t length_ = 0u;
  bool overflow_ = false;
};

}  // namespace odocal::firmware
