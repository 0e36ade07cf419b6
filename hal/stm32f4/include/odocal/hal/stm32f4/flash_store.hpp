#pragma once
/// @file
/// The parameter store on internal flash sectors, through an injectable register bus.

#include <cstddef>
#include <cstdint>

#include "odocal/hal/block_store.hpp"
#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/stm32f4/flash_registers.hpp"

namespace odocal::hal::stm32f4 {

#if defined(ODOCAL_FLASH_BUS_DIRECT)
/// On the robot image (ODOCAL_FLASH_BUS_DIRECT, set by the stm32f4 HAL library): plain volatile
/// word loads and stores, inlined into the store; no virtual calls (-0.2 KB of flash).
class FlashBus {
 public:
  [[nodiscard]] std::uint32_t read32(std::uintptr_t address) { return Register{address}.read(); }
  void write32(std::uintptr_t address, std::uint32_t value) { Register{address}.write(value); }
};

/// The real bus: word loads and stores at the addresses given.
class MemoryBus final : public FlashBus {};
#else
/// 32-bit access to the flash interface registers and to flash memory. On the MCU it is
/// `MemoryBus` (volatile loads and stores); host tests put a model of the STM32F4 flash rules
/// behind it, so the store's register sequences are tested without hardware.
class FlashBus {
 public:
  [[nodiscard]] std::uint32_t read32(std::uintptr_t address) { return do_read32(address); }
  void write32(std::uintptr_t address, std::uint32_t value) { do_write32(address, value); }

 protected:
  ~FlashBus() = default;

 private:
  virtual std::uint32_t do_read32(std::uintptr_t address) = 0;
  virtual void do_write32(std::uintptr_t address, std::uint32_t value) = 0;
};

/// The real bus: word loads and stores at the addresses given.
class MemoryBus final : public FlashBus {
 private:
  std::uint32_t do_read32(std::uintptr_t address) override;
  void do_write32(std::uintptr_t address, std::uint32_t value) override;
};
#endif

/// A block store on `sector_count` consecutive, equally sized flash sectors starting at
/// `first_sector` (odocal uses sectors 1 and 2, 16 KiB each, between the vector table in sector 0
/// and the program from sector 3). Program granularity is 4 bytes (x32 parallelism: 2.7..3.6 V).
///
/// Each operation unlocks the controller (KEY1, KEY2, only when locked), clears stale error flags,
/// runs with BSY polled under a timeout, checks the error flags, and locks again, whatever the
/// outcome. `program` refuses (nothing written) a range that would need a 0 -> 1 change, and
/// verifies what it wrote. After an erase the data cache is flushed (RM0090 3.5.2).
///
/// While an erase runs the CPU stalls on every flash fetch (single bank): a 16 KiB sector takes
/// typically 0.25 s, at most 0.5 s, with no interrupt served. The caller parks the motors first.
/// Main-loop only.
class FlashStore final : public hal::BlockStore {
 public:
  /// @param clock for operation timeouts (erase 2 s, program 10 ms per word).
  constexpr FlashStore(FlashBus& bus, hal::MonotonicClock& clock, std::size_t first_sector,
                       std::size_t sector_count)
      : bus_(bus), clock_(clock), first_sector_(first_sector), sector_count_(sector_count) {
    valid_ = first_sector >= 1u && sector_count >= 1u && first_sector < flash::sector_count &&
             sector_count <= flash::sector_count - first_sector;
    if (valid_) {
      sector_size_ = flash::sector_bytes(first_sector);
      for (std::size_t s = first_sector; s < first_sector + sector_count; ++s) {
        valid_ = valid_ && flash::sector_bytes(s) == sector_size_;
      }
    }
    if (valid_) {
      base_ = flash::sector_address(first_sector);
    } else {
      sector_size_ = 0u;
      sector_count_ = 0u;
    }
  }

  /// True when the sectors exist, are all the same size, and exclude sector 0 (the vectors).
  /// An invalid store has no sectors: every operation is refused with `out_of_range`.
  [[nodiscard]] bool valid() const { return valid_; }
  /// FLASH_SR error bits of the last operation that failed (0 if none). Diagnostics.
  [[nodiscard]] std::uint32_t last_error_flags() const { return last_error_flags_; }
  /// Address of byte 0 of the store.
  [[nodiscard]] std::uintptr_t base_address() const { return base_; }

 private:
  std::size_t do_sector_size() const override;
  std::size_t do_sector_count() const override;
  std::size_t do_program_granularity() const override { return 4u; }
  hal::StoreStatus do_erase(std::size_t index) override;
  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override;
  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override;

  [[nodiscard]] bool unlock();
  void lock();
  [[nodiscard]] bool wait_not_busy(std::uint32_t timeout_us);
  /// The start of an erase or a program: waits for BSY to clear, unlocks and clears stale flags.
  /// @return false (the controller locked again, its error flags kept) when it cannot.
  [[nodiscard]] bool begin(std::uint32_t timeout_us);
  [[nodiscard]] hal::StoreStatus finish(bool completed);
  void flush_data_cache();

  FlashBus& bus_;
  hal::MonotonicClock& clock_;
  std::size_t first_sector_;
  std::size_t sector_count_;
  std::size_t sector_size_ = 0u;
  std::uintptr_t base_ = 0u;
  std::uint32_t last_error_flags_ = 0u;
  bool valid_ = false;
};

}  // namespace odocal::hal::stm32f4
