#pragma once
/// @file
/// Embedded flash interface (RM0090 section 3) as typed register descriptions, and the sector map
/// of the 1 MiB STM32F405/407.

#include <cstddef>

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::flash {

inline constexpr Block block{0x4002'3C00u};

/// Access control: wait states, prefetch and the instruction/data caches.
inline constexpr Register acr = block.at(0x00);
inline constexpr Field acr_latency = {0, 3};  ///< wait states (5 at 168 MHz, 2.7..3.6 V)
inline constexpr Field acr_prften = bit(8);
inline constexpr Field acr_icen = bit(9);
inline constexpr Field acr_dcen = bit(10);
inline constexpr Field acr_icrst = bit(11);  ///< reset the instruction cache (only while disabled)
inline constexpr Field acr_dcrst = bit(12);  ///< reset the data cache (only while disabled)

/// Key register: KEY1 then KEY2 unlocks CR; any other write locks it until the next reset.
inline constexpr Register keyr = block.at(0x04);
inline constexpr std::uint32_t key1 = 0x4567'0123u;
inline constexpr std::uint32_t key2 = 0xCDEF'89ABu;

/// Status. Error flags are cleared by writing 1.
inline constexpr Register sr = block.at(0x0C);
inline constexpr Field sr_eop = bit(0);     ///< end of operation (only with EOPIE)
inline constexpr Field sr_operr = bit(1);   ///< operation error
inline constexpr Field sr_wrperr = bit(4);  ///< write-protection error
inline constexpr Field sr_pgaerr = bit(5);  ///< programming alignment error
inline constexpr Field sr_pgperr = bit(6);  ///< programming parallelism (size) error
inline constexpr Field sr_pgserr = bit(7);  ///< programming sequence error
inline constexpr Field sr_bsy = bit(16);    ///< an operation is in progress
/// Every error flag.
inline constexpr std::uint32_t sr_errors =
    sr_operr.mask() | sr_wrperr.mask() | sr_pgaerr.mask() | sr_pgperr.mask() | sr_pgserr.mask();

/// Control. Writable only after the key sequence; LOCK set again by writing 1.
inline constexpr Register cr = block.at(0x10);
inline constexpr Field cr_pg = bit(0);     ///< programming mode
inline constexpr Field cr_ser = bit(1);    ///< sector erase
inline constexpr Field cr_mer = bit(2);    ///< mass erase
inline constexpr Field cr_snb = {3, 4};    ///< sector number for SER
inline constexpr Field cr_psize = {8, 2};  ///< program size: 0 x8, 1 x16, 2 x32, 3 x64
inline constexpr Field cr_strt = bit(16);  ///< start the erase
inline constexpr Field cr_lock = bit(31);

/// Program size codes of `cr_psize`. x32 needs a supply of 2.7..3.6 V.
inline constexpr std::uint32_t psize_x8 = 0u;
inline constexpr std::uint32_t psize_x16 = 1u;
inline constexpr std::uint32_t psize_x32 = 2u;

/// Main memory.
inline constexpr std::uintptr_t memory_base = 0x0800'0000u;
inline constexpr std::size_t sector_count = 12u;

/// Start address of `sector` (0..11): four of 16 KiB, one of 64 KiB, seven of 128 KiB.
[[nodiscard]] constexpr std::uintptr_t sector_address(std::size_t sector) {
  if (sector <= 4u) {
    return memory_base + 0x4000u * sector;
  }
  return memory_base + 0x2'0000u * (sector - 4u);
}
/// Size of `sector` in bytes.
[[nodiscard]] constexpr std::size_t sector_bytes(std::size_t sector) {
  return sector < 4u ? 0x4000u : (sector == 4u ? 0x1'0000u : 0x2'0000u);
}

static_assert(sector_address(4) == 0x0801'0000u && sector_address(5) == 0x0802'0000u &&
                  sector_address(11) == 0x080E'0000u,
              "RM0090 table 5: sector map of the 1 MiB devices");

}  // namespace odocal::hal::stm32f4::flash
