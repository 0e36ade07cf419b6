#include "flash_model.hpp"

#include "odocal/hal/stm32f4/flash_registers.hpp"

namespace odocal::test {
namespace flash = hal::stm32f4::flash;

namespace {
constexpr std::size_t memory_bytes = 1024u * 1024u;

int sector_of(std::uintptr_t address) {
  for (std::size_t s = 0u; s < flash::sector_count; ++s) {
    const std::uintptr_t start = flash::sector_address(s);
    if (address >= start && address < start + flash::sector_bytes(s)) {
      return static_cast<int>(s);
    }
  }
  return -1;
}
}  // namespace

FlashModel::FlashModel() : memory_(memory_bytes, 0xFFu) {}

bool FlashModel::in_memory(std::uintptr_t address) const {
  return address >= flash::memory_base && address - flash::memory_base < memory_.size();
}

std::uint8_t FlashModel::byte(std::uintptr_t address) const {
  return memory_.at(address - flash::memory_base);
}

void FlashModel::poke(std::uintptr_t address, std::uint8_t value) {
  memory_.at(address - flash::memory_base) = value;
}

std::uint32_t FlashModel::read32(std::uintptr_t address) {
  if (address == flash::sr.address) {
    const std::uint32_t value = sr_ | (busy() ? flash::sr_bsy.mask() : 0u);
    if (busy_polls_ > 0u) {
      --busy_polls_;
    }
    return value;
  }
  if (address == flash::cr.address) {
    return cr_ | (locked_ ? flash::cr_lock.mask() : 0u);
  }
  if (address == flash::acr.address) {
    return acr_;
  }
  if (in_memory(address) && address % 4u == 0u) {
    const std::size_t i = address - flash::memory_base;
    return static_cast<std::uint32_t>(memory_[i]) |
           static_cast<std::uint32_t>(memory_[i + 1]) << 8 |
           static_cast<std::uint32_t>(memory_[i + 2]) << 16 |
           static_cast<std::uint32_t>(memory_[i + 3]) << 24;
  }
  ++violations_;  // unaligned or unmapped read
  return 0u;
}

void FlashModel::write32(std::uintptr_t address, std::uint32_t value) {
  if (address == flash::keyr.address) {
    if (hard_locked_ || !locked_) {
      hard_locked_ = true;  // keys while unlocked: locked to reset
      locked_ = true;
      ++violations_;
    } else if (!key1_seen_ && value == flash::key1) {
      key1_seen_ = true;
    } else if (key1_seen_ && value == flash::key2) {
      key1_seen_ = false;
      locked_ = false;
    } else {
      hard_locked_ = true;
      ++violations_;
    }
    return;
  }
  if (address == flash::sr.address) {
    sr_ &= ~(value & (flash::sr_errors | flash::sr_eop.mask()));
    return;
  }
  if (address == flash::cr.address) {
    write_cr(value);
    return;
  }
  if (address == flash::acr.address) {
    if ((value & flash::acr_dcrst.mask()) != 0u) {
      if ((value & flash::acr_dcen.mask()) != 0u) {
        ++violations_;  // the cache may only be reset while disabled
      }
      ++cache_resets_;
    }
    acr_ = value;
    return;
  }
  if (in_memory(address)) {
    program_word(address, value);
    return;
  }
  ++violations_;
}

void FlashModel::write_cr(std::uint32_t value) {
  if (locked_ || busy()) {
    ++violations_;
    return;
  }
  if ((value & flash::cr_lock.mask()) != 0u) {
    locked_ = true;
    cr_ = 0u;
    return;
  }
  cr_ = value & ~flash::cr_strt.mask();
  if ((value & flash::cr_strt.mask()) == 0u || (value & flash::cr_ser.mask()) == 0u) {
    return;
  }
  const std::uint32_t sector = flash::cr_snb.get(value);
  if (sector >= flash::sector_count || (value & flash::cr_pg.mask()) != 0u) {
    sr_ |= flash::sr_pgserr.mask();
    return;
  }
  if (injected_errors_ != 0u) {
    sr_ |= injected_errors_;
    injected_errors_ = 0u;
    busy_polls_ = erase_polls;
    return;
  }
  if (static_cast<int>(sector) == protected_sector_) {
    sr_ |= flash::sr_wrperr.mask();
    return;
  }
  const std::size_t start = flash::sector_address(sector) - flash::memory_base;
  for (std::size_t i = 0u; i < flash::sector_bytes(sector); ++i) {
    memory_[start + i] = 0xFFu;
  }
  ++erases_;
  busy_polls_ = erase_polls;
}

void FlashModel::program_word(std::uintptr_t address, std::uint32_t value) {
  if (busy()) {
    ++violations_;
    return;
  }
  if (locked_ || (cr_ & flash::cr_pg.mask()) == 0u || (cr_ & flash::cr_ser.mask()) != 0u) {
    sr_ |= flash::sr_pgserr.mask();
    return;
  }
  if (flash::cr_psize.get(cr_) != flash::psize_x32) {
    sr_ |= flash::sr_pgperr.mask();
    return;
  }
  if (address % 4u != 0u) {
    sr_ |= flash::sr_pgaerr.mask();
    return;
  }
  if (injected_errors_ != 0u) {
    sr_ |= injected_errors_;
    injected_errors_ = 0u;
    return;
  }
  if (sector_of(address) == protected_sector_) {
    sr_ |= flash::sr_wrperr.mask();
    return;
  }
  const std::size_t i = address - flash::memory_base;
  for (std::size_t b = 0u; b < 4u; ++b) {
    const auto wanted = static_cast<std::uint8_t>(value >> (8u * b));
    if ((wanted & ~memory_[i + b]) != 0u) {
      ++raise_attempts_;
    }
    memory_[i + b] &= wanted;
  }
  ++words_programmed_;
  busy_polls_ = program_polls;
}

}  // namespace odocal::test

template class odocal::hal::stm32f4::FlashStore<odocal::test::FlashModel>;
