#pragma once
/// @file
/// Typed descriptions of memory-mapped registers: an address, and bit fields inside it.
///
/// Every peripheral header of this folder describes its registers with these two types, so a
/// register is a `constexpr` value that can be named, passed and unit-tested, not a macro.
/// The accessors are the only place that turns an address into a volatile pointer.
/// The field and read-modify-write helpers are forced inline (`gnu::always_inline`): left to the
/// link-time optimiser they stayed out of line, each call loading its field from a constant in
/// flash (10 B at every use instead of an immediate); inlined, the robot image is 244 B smaller.

#include <cstdint>

namespace odocal::hal::stm32f4 {

/// A contiguous bit field of a 32-bit register: `width` bits starting at bit `shift`.
struct Field {
  std::uint8_t shift;
  std::uint8_t width;

  /// The field's bits in place.
  [[nodiscard, gnu::always_inline]] constexpr std::uint32_t mask() const {
    return (width >= 32u ? 0xFFFF'FFFFu : ((1u << width) - 1u)) << shift;
  }
  /// `value` moved into place (excess bits dropped).
  [[nodiscard, gnu::always_inline]] constexpr std::uint32_t operator()(std::uint32_t value) const {
    return (value << shift) & mask();
  }
  /// The field's value read out of a whole register value.
  [[nodiscard, gnu::always_inline]] constexpr std::uint32_t get(
      std::uint32_t register_value) const {
    return (register_value & mask()) >> shift;
  }
};

/// A one-bit field.
[[nodiscard]] constexpr Field bit(std::uint8_t position) {
  return Field{position, 1u};
}

/// A 32-bit memory-mapped register. Reads and writes are single volatile word accesses, so they
/// are ISR-safe in themselves; read-modify-write (`modify`, `set`, `clear`) is not atomic and
/// must only be used on registers that no other context writes.
struct Register {
  std::uintptr_t address;

  [[nodiscard]] std::uint32_t read() const { return *pointer(); }
  void write(std::uint32_t value) const { *pointer() = value; }
  /// Replaces `field` with `value`, leaving the other bits as read.
  [[gnu::always_inline]] void modify(Field field, std::uint32_t value) const {
    write((read() & ~field.mask()) | field(value));
  }
  /// Sets (ORs in) `mask`.
  [[gnu::always_inline]] void set(std::uint32_t mask) const { write(read() | mask); }
  /// Clears `mask`.
  [[gnu::always_inline]] void clear(std::uint32_t mask) const { write(read() & ~mask); }
  /// Reads one field.
  [[nodiscard, gnu::always_inline]] std::uint32_t get(Field field) const {
    return field.get(read());
  }

 private:
  [[nodiscard]] volatile std::uint32_t* pointer() const {
    // The one cast from an address to a register.
    return reinterpret_cast<volatile std::uint32_t*>(address);
  }
};

/// A register block: registers at offsets from a base address (one per peripheral instance).
struct Block {
  std::uintptr_t base;
  [[nodiscard]] constexpr Register at(std::uintptr_t offset) const {
    return Register{base + offset};
  }
};

/// The MCU's register bus: 32-bit volatile loads and stores at the addresses given, inlined.
/// Register-level routines that the host tests run on a fake or a model (`FlashStore`,
/// `serve_encoder_edge`) take their bus as a template argument; this is the one the images use.
class MemoryBus {
 public:
  [[nodiscard]] std::uint32_t read32(std::uintptr_t address) const {
    return Register{address}.read();
  }
  void write32(std::uintptr_t address, std::uint32_t value) const {
    Register{address}.write(value);
  }
};

}  // namespace odocal::hal::stm32f4
