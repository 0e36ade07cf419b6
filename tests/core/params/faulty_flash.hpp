#pragma once
// Power-cut and flash-damage injection in front of any hal::BlockStore backend (the RAM flash,
// the file store, the STM32F4 driver on its flash model), for power_cut_harness.hpp.
//
// Faults, all through the backend's own erase/program (so its rules still hold):
//  - a cut during an operation after `bit` bits of it took effect, in programming order: bytes
//    ascending, within a byte MSB first or LSB first (program clears bits, erase sets them);
//    `bit` past the end is a cut after the operation completed but before it returned. The
//    operation and every later one fail until power_on();
//  - a weak cell: the next program reports ok but one of its bits stays 1;
//  - a lost bit: a programmed 1 bit of the image reads 0 later (disturb, retention), which a
//    program can do at any time.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "odocal/hal/block_store.hpp"

namespace odocal::test {

/// A block store that passes every operation to the backend in front of which it sits, but
/// for the faults armed.
class FaultyFlash final : public hal::BlockStore {
 public:
  explicit FaultyFlash(hal::BlockStore* inner) : inner_(inner) {}
  /// After a reboot the backend driver is a new object over the same medium.
  void retarget(hal::BlockStore* inner) { inner_ = inner; }

  /// Cut power in the operation `after_ops` operations from now, after `bit` of its bits.
  void arm_cut(std::size_t after_ops, std::size_t bit, bool msb_first) {
    cut_armed_ = true;
    cut_after_ = after_ops;
    cut_bit_ = bit;
    msb_first_ = msb_first;
  }
  /// The next program reports ok but leaves bit `bit` (of its data, in MSB-first order) at 1.
  void arm_weak_bit(std::size_t bit) {
    weak_armed_ = true;
    weak_bit_ = bit;
  }
  void disarm() { cut_armed_ = weak_armed_ = false; }
  [[nodiscard]] bool powered_off() const { return powered_off_; }
  void power_on() {
    powered_off_ = false;
    disarm();
  }
  [[nodiscard]] std::size_t operations() const { return operations_; }
  [[nodiscard]] std::size_t cuts() const { return cuts_; }

  /// Clears bit `bit` of the byte at `address` if it is 1 (a lost bit). False if it was 0.
  bool lose_bit(std::size_t address, unsigned bit) {
    // Program the unit holding it with its own contents minus that bit (flash rules: a program
    // may only clear bits, and asks for no 0 -> 1 change).
    const std::size_t g = inner_->program_granularity();
    const std::size_t base = address - address % g;
    std::vector<std::uint8_t> unit(g);
    if (inner_->read(base, unit.data(), g) != hal::StoreStatus::ok ||
        (unit[address - base] & (1u << bit)) == 0u) {
      return false;
    }
    unit[address - base] = static_cast<std::uint8_t>(unit[address - base] & ~(1u << bit));
    return inner_->program(base, unit.data(), g) == hal::StoreStatus::ok;
  }

  /// The whole image, and putting one back (bypassing the faults).
  std::vector<std::uint8_t> snapshot() {
    std::vector<std::uint8_t> image(inner_->total_size());
    EXPECT_EQ(inner_->read(0u, image.data(), image.size()), hal::StoreStatus::ok);
    return image;
  }
  void restore(const std::vector<std::uint8_t>& image) {
    const std::size_t sector = inner_->sector_size();
    for (std::size_t s = 0; s < inner_->sector_count(); ++s) {
      ASSERT_EQ(inner_->erase(s), hal::StoreStatus::ok);
      ASSERT_EQ(inner_->program(s * sector, image.data() + s * sector, sector),
                hal::StoreStatus::ok);
    }
  }

 private:
  std::size_t do_sector_size() const override { return inner_->sector_size(); }
  std::size_t do_sector_count() const override { return inner_->sector_count(); }
  std::size_t do_program_granularity() const override { return inner_->program_granularity(); }

  // True when this operation is the one cut.
  bool take() {
    ++operations_;
    if (!cut_armed_) {
      return false;
    }
    if (cut_after_ > 0u) {
      --cut_after_;
      return false;
    }
    cut_armed_ = false;
    powered_off_ = true;
    ++cuts_;
    return true;
  }
  // Mask of the bits of byte `index` that took effect when `bits` bits of the operation had.
  std::uint8_t done_mask(std::size_t index, std::size_t bits) const {
    if (bits >= (index + 1u) * 8u) {
      return 0xFFu;
    }
    if (bits <= index * 8u) {
      return 0u;
    }
    const std::size_t n = bits - index * 8u;  // 1..7 bits of this byte
    const auto low = static_cast<std::uint8_t>((1u << n) - 1u);
    return msb_first_ ? static_cast<std::uint8_t>(low << (8u - n)) : low;
  }

  hal::StoreStatus do_erase(std::size_t index) override {
    if (powered_off_) {
      return hal::StoreStatus::device_error;
    }
    if (!take()) {
      return inner_->erase(index);
    }
    // Part of the sector is erased: erase it all, then program back the bits not yet erased.
    const std::size_t size = inner_->sector_size();
    std::vector<std::uint8_t> old(size);
    if (inner_->read(index * size, old.data(), size) != hal::StoreStatus::ok ||
        inner_->erase(index) != hal::StoreStatus::ok) {
      return hal::StoreStatus::device_error;
    }
    for (std::size_t i = 0; i < size; ++i) {
      old[i] = static_cast<std::uint8_t>(old[i] | done_mask(i, cut_bit_));
    }
    (void)inner_->program(index * size, old.data(), size);
    return hal::StoreStatus::device_error;
  }

  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override {
    if (powered_off_) {
      return hal::StoreStatus::device_error;
    }
    std::vector<std::uint8_t> landed(data, data + size);
    if (weak_armed_) {
      weak_armed_ = false;
      ++operations_;
      const std::size_t byte = (weak_bit_ / 8u) % size;
      landed[byte] = static_cast<std::uint8_t>(landed[byte] | (0x80u >> (weak_bit_ % 8u)));
      (void)inner_->program(address, landed.data(), size);
      return hal::StoreStatus::ok;  // the cell did not take the charge; nobody noticed
    }
    if (!take()) {
      return inner_->program(address, data, size);
    }
    for (std::size_t i = 0; i < size; ++i) {
      // Bits not yet programmed are still 1.
      landed[i] = static_cast<std::uint8_t>(landed[i] | ~done_mask(i, cut_bit_));
    }
    (void)inner_->program(address, landed.data(), size);
    return hal::StoreStatus::device_error;
  }

  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override {
    return inner_->read(address, out, size);
  }

  hal::BlockStore* inner_;
  bool cut_armed_ = false;
  std::size_t cut_after_ = 0u;
  std::size_t cut_bit_ = 0u;
  bool msb_first_ = true;
  bool weak_armed_ = false;
  std::size_t weak_bit_ = 0u;
  bool powered_off_ = false;
  std::size_t operations_ = 0u;
  std::size_t cuts_ = 0u;
};

}  // namespace odocal::test
