#pragma once
/// @file
/// An address-keyed fake of the STM32F4 register space behind a register bus (`read32`,
/// `write32`, as `MemoryBus` on the MCU), recording every access in order into fixed storage.

#include <array>
#include <cstddef>
#include <cstdint>

namespace odocal::test {

/// Plain memory at any address: a read returns the value last set or written there (0 if none),
/// a write stores its value. Every access is logged, so a test asserts the exact sequence a
/// routine runs (which registers, in which order, which bits written) rather than its result.
class RegisterFake {
 public:
  struct Access {
    bool write;
    std::uintptr_t address;
    std::uint32_t value;  ///< written, or returned by the read
  };
  static constexpr std::size_t max_registers = 32u;
  static constexpr std::size_t max_accesses = 64u;

  /// Test set-up: what the register at `address` reads from now on. Not logged.
  void set(std::uintptr_t address, std::uint32_t value) { cell(address) = value; }
  /// What the register at `address` holds, for a test's assertion. Not logged.
  [[nodiscard]] std::uint32_t peek(std::uintptr_t address) { return cell(address); }

  std::uint32_t read32(std::uintptr_t address) {
    const std::uint32_t value = cell(address);
    log(Access{false, address, value});
    return value;
  }
  void write32(std::uintptr_t address, std::uint32_t value) {
    cell(address) = value;
    log(Access{true, address, value});
  }

  /// The accesses since the last `clear_log`, oldest first (at most `max_accesses`).
  [[nodiscard]] std::size_t access_count() const { return accesses_; }
  [[nodiscard]] const Access& access(std::size_t i) const { return log_.at(i); }
  /// Accesses beyond `max_accesses` (not kept), and registers beyond `max_registers`.
  [[nodiscard]] std::size_t overflows() const { return overflows_; }
  void clear_log() { accesses_ = 0u; }

 private:
  std::uint32_t& cell(std::uintptr_t address) {
    for (std::size_t i = 0u; i < used_; ++i) {
      if (addresses_[i] == address) {
        return values_[i];
      }
    }
    if (used_ == max_registers) {
      ++overflows_;
      return spare_;
    }
    addresses_[used_] = address;
    values_[used_] = 0u;
    return values_[used_++];
  }
  void log(const Access& access) {
    if (accesses_ == max_accesses) {
      ++overflows_;
      return;
    }
    log_[accesses_++] = access;
  }

  std::array<std::uintptr_t, max_registers> addresses_{};
  std::array<std::uint32_t, max_registers> values_{};
  std::size_t used_ = 0u;
  std::uint32_t spare_ = 0u;
  std::array<Access, max_accesses> log_{};
  std::size_t accesses_ = 0u;
  std::size_t overflows_ = 0u;
};

}  // namespace odocal::test
