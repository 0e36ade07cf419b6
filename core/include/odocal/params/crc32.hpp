#pragma once
/// @file
/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, init and final XOR 0xFFFFFFFF), the
/// checksum of the parameter records.

#include <cstddef>
#include <cstdint>

namespace odocal::params {

/// Continues a CRC-32 over `size` bytes. Start with `crc = 0` for a new checksum; feeding the
/// data in pieces gives the same result as one call. Pure; ISR-safe. crc32("123456789") ==
/// 0xCBF43926.
[[nodiscard]] std::uint32_t crc32(const std::uint8_t* data, std::size_t size,
                                  std::uint32_t crc = 0u);

}  // namespace odocal::params
