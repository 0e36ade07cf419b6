#pragma once
/// @file
/// Non-volatile block store with real flash semantics.

#include <cstddef>
#include <cstdint>

namespace odocal::hal {

/// Outcome of a block-store operation.
enum class StoreStatus : std::uint8_t {
  ok,
  out_of_range,  ///< address or size outside the device, or not aligned to the granularity
  not_erased,    ///< program would need a 0 -> 1 transition (flash can only clear bits)
  device_error,  ///< the backend failed (I/O error, flash controller error, power cut)
};

/// A flash-like store: `sector_count()` sectors of `sector_size()` bytes each. Erase sets a whole
/// sector to 0xFF; program can only clear bits (1 -> 0), in units of `program_granularity()`
/// bytes at aligned addresses. Main-loop only; never called from the tick or an ISR.
class BlockStore {
 public:
  std::size_t sector_size() const { return do_sector_size(); }
  std::size_t sector_count() const { return do_sector_count(); }
  std::size_t program_granularity() const { return do_program_granularity(); }

  /// Erases sector `index` to 0xFF.
  [[nodiscard]] StoreStatus erase(std::size_t index) {
    if (index >= sector_count()) {
      return StoreStatus::out_of_range;
    }
    return do_erase(index);
  }

  /// Programs `size` bytes at byte `address` (aligned to the granularity).
  [[nodiscard]] StoreStatus program(std::size_t address, const std::uint8_t* data,
                                    std::size_t size) {
    const std::size_t g = program_granularity();
    if (data == nullptr || g == 0u || address % g != 0u || size % g != 0u ||
        address > total_size() || size > total_size() - address) {
      return StoreStatus::out_of_range;
    }
    return do_program(address, data, size);
  }

  /// Reads `size` bytes at byte `address`.
  [[nodiscard]] StoreStatus read(std::size_t address, std::uint8_t* out, std::size_t size) {
    if (out == nullptr || address > total_size() || size > total_size() - address) {
      return StoreStatus::out_of_range;
    }
    return do_read(address, out, size);
  }

  std::size_t total_size() const { return sector_size() * sector_count(); }

 protected:
  ~BlockStore() = default;

 private:
  virtual std::size_t do_sector_size() const = 0;
  virtual std::size_t do_sector_count() const = 0;
  virtual std::size_t do_program_granularity() const = 0;
  virtual StoreStatus do_erase(std::size_t index) = 0;
  virtual StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                                 std::size_t size) = 0;
  virtual StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) = 0;
};

}  // namespace odocal::hal
