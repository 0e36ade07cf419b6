// Host-portable: no assembly, no fixed addresses dereferenced here (the bus does that), so the
// host tests compile this file unchanged against a flash model.
#include "odocal/hal/stm32f4/flash_store.hpp"

#include "odocal/hal/stm32f4/flash_registers.hpp"

namespace odocal::hal::stm32f4 {
namespace {

constexpr std::uint32_t erase_timeout_us = 2'000'000u;  // 16 KiB: 0.5 s max; 128 KiB: 2 s
constexpr std::uint32_t program_timeout_us = 10'000u;   // one word: 100 µs max

std::uint32_t load_le32(const std::uint8_t* bytes) {
  return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
         static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

}  // namespace

std::size_t FlashStore::do_sector_size() const {
  return sector_size_;
}
std::size_t FlashStore::do_sector_count() const {
  return sector_count_;
}

bool FlashStore::unlock() {
  if ((bus_.read32(flash::cr.address) & flash::cr_lock.mask()) != 0u) {
    bus_.write32(flash::keyr.address, flash::key1);
    bus_.write32(flash::keyr.address, flash::key2);
  }
  // Still locked: a wrong sequence happened earlier and the controller stays locked to reset.
  return (bus_.read32(flash::cr.address) & flash::cr_lock.mask()) == 0u;
}

void FlashStore::lock() {
  bus_.write32(flash::cr.address, flash::cr_lock.mask());
}

bool FlashStore::wait_not_busy(std::uint32_t timeout_us) {
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

bool FlashStore::begin(std::uint32_t timeout_us) {
  if (!wait_not_busy(timeout_us) || !unlock()) {
    last_error_flags_ = bus_.read32(flash::sr.address) & flash::sr_errors;
    lock();
    return false;
  }
  bus_.write32(flash::sr.address, flash::sr_errors | flash::sr_eop.mask());
  return true;
}

hal::StoreStatus FlashStore::finish(bool completed) {
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

void FlashStore::flush_data_cache() {
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

hal::StoreStatus FlashStore::do_erase(std::size_t index) {
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

hal::StoreStatus FlashStore::do_program(std::size_t address, const std::uint8_t* data,
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

hal::StoreStatus FlashStore::do_read(std::size_t address, std::uint8_t* out, std::size_t size) {
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

#if !defined(ODOCAL_FLASH_BUS_DIRECT)
std::uint32_t MemoryBus::do_read32(std::uintptr_t address) {
  return Register{address}.read();
}

void MemoryBus::do_write32(std::uintptr_t address, std::uint32_t value) {
  Register{address}.write(value);
}

#endif

}  // namespace odocal::hal::stm32f4
