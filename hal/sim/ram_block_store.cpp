#include "odocal/sim/ram_block_store.hpp"

#include <cstring>

namespace odocal::sim {

RamBlockStore::RamBlockStore(std::uint8_t* memory, std::size_t sector_size,
                             std::size_t sector_count, std::size_t program_granularity)
    : memory_(memory),
      sector_size_(memory == nullptr ? 0u : sector_size),
      sector_count_(memory == nullptr ? 0u
                                      : (sector_count > kMaxSectors ? kMaxSectors : sector_count)),
      granularity_(program_granularity) {
  if (memory_ != nullptr) {
    std::memset(memory_, 0xFF, sector_size_ * sector_count_);
  }
}

void RamBlockStore::cut_after(std::size_t operations, std::size_t partial_units, bool tear_bits) {
  armed_ = true;
  powered_off_ = false;
  remaining_ = operations;
  partial_units_ = partial_units;
  tear_bits_ = tear_bits;
}

void RamBlockStore::power_on() {
  armed_ = false;
  powered_off_ = false;
}

std::uint32_t RamBlockStore::erase_count(std::size_t sector) const {
  return sector < sector_count_ ? erases_[sector] : 0u;
}

bool RamBlockStore::take_operation() {
  ++operations_;
  if (!armed_) {
    return false;
  }
  if (remaining_ == 0u) {
    armed_ = false;
    powered_off_ = true;
    return true;
  }
  --remaining_;
  return false;
}

hal::StoreStatus RamBlockStore::do_erase(std::size_t index) {
  if (powered_off_) {
    return hal::StoreStatus::device_error;
  }
  std::uint8_t* sector = memory_ + index * sector_size_;
  if (take_operation()) {
    std::size_t bytes = partial_units_ * granularity_;
    if (bytes > sector_size_) {
      bytes = sector_size_;
    }
    std::memset(sector, 0xFF, bytes);
    ++erases_[index];
    return hal::StoreStatus::device_error;
  }
  std::memset(sector, 0xFF, sector_size_);
  ++erases_[index];
  return hal::StoreStatus::ok;
}

hal::StoreStatus RamBlockStore::do_program(std::size_t address, const std::uint8_t* data,
                                           std::size_t size) {
  if (powered_off_) {
    return hal::StoreStatus::device_error;
  }
  // Flash can only clear bits: refuse before writing anything.
  for (std::size_t i = 0; i < size; ++i) {
    if ((data[i] & ~memory_[address + i] & 0xFFu) != 0u) {
      ++operations_;
      return hal::StoreStatus::not_erased;
    }
  }
  if (take_operation()) {
    std::size_t bytes = partial_units_ * granularity_;
    if (bytes > size) {
      bytes = size;
    }
    for (std::size_t i = 0; i < bytes; ++i) {
      memory_[address + i] &= data[i];
    }
    if (tear_bits_ && bytes < size) {
      // The unit being programmed when power failed: only some of its bits reached 0.
      const std::size_t end = bytes + granularity_ > size ? size : bytes + granularity_;
      for (std::size_t i = bytes; i < end; ++i) {
        memory_[address + i] &= static_cast<std::uint8_t>(data[i] | 0xAAu);
      }
    }
    programmed_bytes_ += bytes;
    return hal::StoreStatus::device_error;
  }
  for (std::size_t i = 0; i < size; ++i) {
    memory_[address + i] &= data[i];
  }
  programmed_bytes_ += size;
  return hal::StoreStatus::ok;
}

hal::StoreStatus RamBlockStore::do_read(std::size_t address, std::uint8_t* out, std::size_t size) {
  std::memcpy(out, memory_ + address, size);
  return hal::StoreStatus::ok;
}

}  // namespace odocal::sim
