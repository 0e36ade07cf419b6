#pragma once
/// @file
/// A flash simulated in RAM, with the rules of real NOR flash and power-cut injection.
/// Used by the host tests and by the QEMU firmware image: no heap, no exceptions, fixed size
/// (the caller provides the memory, or uses StaticRamBlockStore).

#include <array>
#include <cstddef>
#include <cstdint>

#include "odocal/hal/block_store.hpp"

namespace odocal::sim {

/// RAM flash over caller-provided memory of `sector_size * sector_count` bytes.
///
/// Rules enforced like real flash: erase sets a whole sector to 0xFF; program only clears bits
/// (a 0 -> 1 transition is refused with `not_erased` and writes nothing); program addresses and
/// sizes are multiples of the granularity (checked by hal::BlockStore).
///
/// Power-cut injection: `cut_after(n, partial_units)` lets `n` more erase/program operations
/// succeed; operation n + 1 is cut. A cut program writes only its first `partial_units`
/// granularity units (and, with `tear_bits`, clears half the bits of the next unit, like a
/// program interrupted mid-word); a cut erase erases only its first `partial_units` units.
/// The cut operation and every later one return `device_error` until `power_on()`. Reads keep
/// working after a cut so a test can inspect the image; `power_on()` models the reboot.
class RamBlockStore : public hal::BlockStore {
 public:
  /// @param memory `sector_size * sector_count` bytes owned by the caller; filled with 0xFF.
  RamBlockStore(std::uint8_t* memory, std::size_t sector_size, std::size_t sector_count,
                std::size_t program_granularity);
  ~RamBlockStore() = default;

  /// Arms a power cut (see class doc). `partial_units` is clamped to the operation's size.
  void cut_after(std::size_t operations, std::size_t partial_units = 0u, bool tear_bits = false);
  /// Disarms the cut and restores power; the memory keeps whatever the cut left.
  void power_on();
  /// True once an armed cut has happened (until power_on()).
  [[nodiscard]] bool cut_happened() const { return powered_off_; }

  /// Erase and program operations attempted since construction (also those refused).
  [[nodiscard]] std::size_t operations() const { return operations_; }
  /// Erase operations performed on `sector` (wear), 0 for an index out of range.
  [[nodiscard]] std::uint32_t erase_count(std::size_t sector) const;
  /// Bytes programmed since construction.
  [[nodiscard]] std::size_t programmed_bytes() const { return programmed_bytes_; }
  /// Direct view of the memory (tests corrupt or inspect it).
  [[nodiscard]] std::uint8_t* memory() { return memory_; }

 private:
  static constexpr std::size_t kMaxSectors = 64u;

  std::size_t do_sector_size() const override { return sector_size_; }
  std::size_t do_sector_count() const override { return sector_count_; }
  std::size_t do_program_granularity() const override { return granularity_; }
  hal::StoreStatus do_erase(std::size_t index) override;
  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override;
  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override;

  /// Counts an operation; true when it must be cut.
  bool take_operation();

  std::uint8_t* memory_;
  std::size_t sector_size_;
  std::size_t sector_count_;
  std::size_t granularity_;
  std::array<std::uint32_t, kMaxSectors> erases_{};
  std::size_t operations_ = 0u;
  std::size_t programmed_bytes_ = 0u;
  bool armed_ = false;
  bool powered_off_ = false;
  bool tear_bits_ = false;
  std::size_t remaining_ = 0u;
  std::size_t partial_units_ = 0u;
};

namespace detail {
/// The memory of a StaticRamBlockStore, a base so it exists before RamBlockStore fills it.
template <std::size_t Size>
struct RamStorage {
  std::array<std::uint8_t, Size> bytes{};
};
}  // namespace detail

/// A RamBlockStore that owns its memory (a static or stack object: no heap).
template <std::size_t SectorSize, std::size_t SectorCount, std::size_t Granularity>
class StaticRamBlockStore final : private detail::RamStorage<SectorSize * SectorCount>,
                                  public RamBlockStore {
 public:
  StaticRamBlockStore()
      : detail::RamStorage<SectorSize * SectorCount>(),
        RamBlockStore(this->bytes.data(), SectorSize, SectorCount, Granularity) {}
};

}  // namespace odocal::sim
