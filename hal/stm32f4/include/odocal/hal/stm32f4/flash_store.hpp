#pragma once
/// @file
/// The parameter store on internal flash sectors, through a register bus given as a template
/// argument: `MemoryBus` on the MCU, a model of the flash rules in the host tests.

#include <cstddef>
#include <cstdint>

#include "odocal/hal/block_store.hpp"
#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/stm32f4/flash_registers.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4 {

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
///
/// `Bus` gives 32-bit access to the flash interface registers and to flash memory,
/// `read32(address)` and `write32(address, value)`: `MemoryBus` on the MCU (inline volatile
/// loads and stores, no virtual call); host tests put a model of the STM32F4 flash rules there, so
/// the store's register sequences are tested without hardware.
///
/// Main-loop only.
template <typename Bus>
class FlashStore final : public hal::BlockStore {
 public:
  /// @param clock for operation timeouts (erase 2 s, program 10 ms per word).
  constexpr FlashStore(Bus& bus, hal::MonotonicClock& clock, std::size_t first_sector,
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
  static constexpr std::uint32_t erase_timeout_us = 2'000'000u;  // 16 KiB: 0.5 s max; 128 KiB: 2 s
  static constexpr std::uint32_t program_timeout_us = 10'000u;   // one word: 100 µs max

  static std::uint32_t load_le32(const std::uint8_t* bytes) {
    return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
           static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
  }

  std::size_t do_program_granularity() const override { return 4u; }
  std::size_t do_sector_size() const override;
  std::size_t do_sector_count() const override;

  [[nodiscard]] bool unlock();
  void lock();
  [[nodiscard]] bool wait_not_busy(std::uint32_t timeout_us);
  /// The start of an erase or a program: waits for BSY to clear, unlocks and clears stale flags.
  /// @return false (the controller locked again, its error flags kept) when it cannot.
  [[nodiscard]] bool begin(std::uint32_t timeout_us);
  [[nodiscard]] hal::StoreStatus finish(bool completed);
  void flush_data_cache();

  hal::StoreStatus do_erase(std::size_t index) override;
  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override;
  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override;

  Bus& bus_;
  hal::MonotonicClock& clock_;
  std::size_t first_sector_;
  std::size_t sector_count_;
  std::size_t sector_size_ = 0u;
  std::uintptr_t base_ = 0u;
  std::uint32_t last_error_flags_ = 0u;
  bool valid_ = false;
};

template <typename Bus>
std::size_t FlashStore<Bus>::do_sector_size() const {
  return sector_size_;
}
template <typename Bus>
std::size_t FlashStore<Bus>::do_sector_count() const {
  return sector_count_;
}

template <typename Bus>
bool FlashStore<Bus>::unlock() {
  if ((bus_.read32(flash::cr.address) & flash::cr_lock.mask()) != 0u) {
    bus_.write32(flash::keyr.address, flash::key1);
    bus_.write32(flash::keyr.address, flash::key2);
  }
  // Still locked: a wrong sequence happened earlier and the controller stays locked to reset.
  return (bus_.read32(flash::cr.address) & flash::cr_lock.mask()) == 0u;
}

template <typename Bus>
void FlashStore<Bus>::lock() {
  bus_.write32(flash::cr.address, flash::cr_lock.mask());
}

template <typename Bus>
bool FlashStore<Bus>::wait_not_busy(std::uint32_t timeout_us) {
  const std::uint32_t start = clock_.now_us();
  for (;;) {
    if ((bus_.read32(flash::sr.address) & flash::sr_bsy.mask()) == 0u) {
      return true;
    }
    if (clock_.now_us() - start > timeout_us) {
      return false;
    }
  }
}

template <typename Bus>
bool FlashStore<Bus>::begin(std::uint32_t timeout_us) {
  if (!wait_not_busy(timeout_us) || !unlock()) {
    last_error_flags_ = bus_.read32(flash::sr.address) & flash::sr_errors;
    lock();
    return false;
  }
  bus_.write32(flash::sr.address, flash::sr_errors | flash::sr_eop.mask());
  return true;
}

template <typename Bus>
hal::StoreStatus FlashStore<Bus>::finish(bool completed) {
  const std::uint32_t errors = bus_.read32(flash::sr.address) & flash::sr_errors;
  if (completed && errors == 0u) {
    // PG / SER off before locking (CR is only writable while BSY is clear).
    bus_.write32(flash::cr.address, 0u);
    lock();
    return hal::StoreStatus::ok;
  }
  last_error_flags_ = errors;
  if (errors != 0u) {
    bus_.write32(flash::sr.address, errors);
  }
  if (completed) {
    bus_.write32(flash::cr.address, 0u);
  }
  lock();
  return hal::StoreStatus::device_error;
}

template <typename Bus>
void FlashStore<Bus>::flush_data_cache() {
  const std::uint32_t acr = bus_.read32(flash::acr.address);
  if ((acr & flash::acr_dcen.mask()) == 0u) {
    return;
  }
  // The cache may hold words of the erased sector: reset it while disabled.
  const std::uint32_t disabled = acr & ~flash::acr_dcen.mask();
  bus_.write32(flash::acr.address, disabled);
  bus_.write32(flash::acr.address, disabled | flash::acr_dcrst.mask());
  bus_.write32(flash::acr.address, disabled);
  bus_.write32(flash::acr.address, acr);
}

template <typename Bus>
hal::StoreStatus FlashStore<Bus>::do_erase(std::size_t index) {
  if (!begin(erase_timeout_us)) {
    return hal::StoreStatus::device_error;
  }
  const std::uint32_t sector = static_cast<std::uint32_t>(first_sector_ + index);
  const std::uint32_t command =
      flash::cr_ser.mask() | flash::cr_snb(sector) | flash::cr_psize(flash::psize_x32);
  bus_.write32(flash::cr.address, command);
  bus_.write32(flash::cr.address, command | flash::cr_strt.mask());
  const bool completed = wait_not_busy(erase_timeout_us);
  const hal::StoreStatus status = finish(completed);
  flush_data_cache();
  return status;
}

template <typename Bus>
hal::StoreStatus FlashStore<Bus>::do_program(std::size_t address, const std::uint8_t* data,
                                             std::size_t size) {
  // Flash only clears bits: refuse, before touching anything, what would need a 0 -> 1.
  for (std::size_t offset = 0u; offset < size; offset += 4u) {
    const std::uint32_t old_word = bus_.read32(base_ + address + offset);
    const std::uint32_t new_word = load_le32(data + offset);
    if ((new_word & ~old_word) != 0u) {
      return hal::StoreStatus::not_erased;
    }
  }
  if (!begin(program_timeout_us)) {
    return hal::StoreStatus::device_error;
  }
  bus_.write32(flash::cr.address, flash::cr_pg.mask() | flash::cr_psize(flash::psize_x32));
  bool completed = true;
  for (std::size_t offset = 0u; offset < size && completed; offset += 4u) {
    const std::uintptr_t word_address = base_ + address + offset;
    const std::uint32_t word = load_le32(data + offset);
    if (word == 0xFFFF'FFFFu) {
      continue;  // nothing to clear: leave the word erased (and unprogrammed)
    }
    bus_.write32(word_address, word);
    completed = wait_not_busy(program_timeout_us) &&
                (bus_.read32(flash::sr.address) & flash::sr_errors) == 0u &&
                bus_.read32(word_address) == word;
  }
  return finish(completed);
}

template <typename Bus>
hal::StoreStatus FlashStore<Bus>::do_read(std::size_t address, std::uint8_t* out,
                                          std::size_t size) {
  for (std::size_t i = 0u; i < size;) {
    const std::uintptr_t byte_address = base_ + address + i;
    const std::uintptr_t word_address = byte_address & ~static_cast<std::uintptr_t>(3u);
    std::uint32_t word = bus_.read32(word_address);
    for (std::uintptr_t b = byte_address - word_address; b < 4u && i < size; ++b, ++i) {
      out[i] = static_cast<std::uint8_t>(word >> (8u * b));
    }
  }
  return hal::StoreStatus::ok;
}

/// Built once, in flash_store.cpp.
extern template class FlashStore<MemoryBus>;

}  // namespace odocal::hal::stm32f4
