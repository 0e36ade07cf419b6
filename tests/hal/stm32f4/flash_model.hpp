#pragma once
/// @file
/// A model of the STM32F4 embedded-flash interface (RM0090 section 3) as the flash store's register
/// bus, so the store's register sequences run on the host. It enforces the rules and counts
/// breaches.

#include <cstdint>
#include <vector>

#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/stm32f4/flash_store.hpp"

namespace odocal::test {

/// What the model enforces:
///  - FLASH_CR is locked after reset; KEY1 then KEY2 unlocks it; a wrong key, or a key written
///    while unlocked, locks it until reset (`hard_locked`); writing LOCK locks it again;
///  - CR writes while locked, or while BSY, are ignored (and counted as violations);
///  - SER + SNB + STRT erases one sector to 0xFF (BSY for `erase_polls` SR reads); SNB out of
///    range -> PGSERR; a write-protected sector -> WRPERR, nothing erased;
///  - with PG set, a 32-bit write to flash needs PSIZE = x32 (else PGPERR) and an aligned
///    address (else PGAERR); programming only clears bits: memory &= value; a write that wants a
///    0 -> 1 change is counted in `raise_attempts` (silicon would leave a corrupt word);
///  - a flash write without PG, or while locked, sets PGSERR and changes nothing;
///  - SR error flags and EOP are cleared by writing 1;
///  - ACR is stored as written (the data-cache reset bit is counted).
class FlashModel final {
 public:
  FlashModel();

  /// The bus (`FlashStore`'s `Bus`): 32-bit reads and writes of the registers and the memory.
  std::uint32_t read32(std::uintptr_t address);
  void write32(std::uintptr_t address, std::uint32_t value);

  /// Sector `s` refuses erase and program with WRPERR.
  void protect(std::size_t sector) { protected_sector_ = static_cast<int>(sector); }
  /// The next erase or program fails with these SR error bits (and changes nothing).
  void fail_next(std::uint32_t error_bits) { injected_errors_ = error_bits; }
  /// BSY never clears again (a hung controller).
  void stick_busy() { stuck_busy_ = true; }
  /// SR reads that report BSY after an erase / a word program.
  std::uint32_t erase_polls = 5u;
  std::uint32_t program_polls = 1u;

  [[nodiscard]] bool locked() const { return locked_; }
  [[nodiscard]] bool hard_locked() const { return hard_locked_; }
  [[nodiscard]] std::uint32_t violations() const { return violations_; }
  [[nodiscard]] std::uint32_t raise_attempts() const { return raise_attempts_; }
  [[nodiscard]] std::uint32_t erases() const { return erases_; }
  [[nodiscard]] std::uint32_t words_programmed() const { return words_programmed_; }
  [[nodiscard]] std::uint32_t cache_resets() const { return cache_resets_; }
  [[nodiscard]] std::uint32_t sr_bits() const { return sr_; }
  /// Byte of main memory at `address` (0x08000000-based).
  [[nodiscard]] std::uint8_t byte(std::uintptr_t address) const;
  /// Writes memory directly (test set-up), bypassing the rules.
  void poke(std::uintptr_t address, std::uint8_t value);

 private:
  void write_cr(std::uint32_t value);
  void program_word(std::uintptr_t address, std::uint32_t value);
  [[nodiscard]] bool busy() const { return stuck_busy_ || busy_polls_ > 0u; }
  [[nodiscard]] bool in_memory(std::uintptr_t address) const;

  std::vector<std::uint8_t> memory_;
  std::uint32_t cr_ = 0u;
  std::uint32_t sr_ = 0u;
  std::uint32_t acr_ = 0u;
  bool locked_ = true;
  bool hard_locked_ = false;
  bool key1_seen_ = false;
  bool stuck_busy_ = false;
  std::uint32_t busy_polls_ = 0u;
  int protected_sector_ = -1;
  std::uint32_t injected_errors_ = 0u;
  std::uint32_t violations_ = 0u;
  std::uint32_t raise_attempts_ = 0u;
  std::uint32_t erases_ = 0u;
  std::uint32_t words_programmed_ = 0u;
  std::uint32_t cache_resets_ = 0u;
};

/// A clock that advances 10 µs per reading (so timeouts expire in a bounded number of polls).
class SteppingClock final : public hal::MonotonicClock {
 public:
  std::uint32_t step_us = 10u;

 private:
  std::uint32_t do_now_us() override { return now_ += step_us; }
  std::uint32_t now_ = 0u;
};

/// The flash store on the model (built once, in flash_model.cpp).
using ModelFlashStore = hal::stm32f4::FlashStore<FlashModel>;

}  // namespace odocal::test

extern template class odocal::hal::stm32f4::FlashStore<odocal::test::FlashModel>;
