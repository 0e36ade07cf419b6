#include "odocal/params/crc32.hpp"

namespace odocal::params {

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc) {
  // Bitwise, table-free: a record is a few hundred bytes and is checked only on load and save,
  // so 1 KiB of table in flash would buy nothing.
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) {
      const std::uint32_t mask = 0u - (crc & 1u);
      crc = (crc >> 1) ^ (0xEDB88320u & mask);
    }
  }
  return ~crc;
}

}  // namespace odocal::params
