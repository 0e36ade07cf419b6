#include "odocal/console/output_queue.hpp"

#include <cstring>

namespace odocal::console {

bool OutputQueue::push(const char* data, std::size_t size) {
  if (data == nullptr || size > free_space()) {
    return false;
  }
  std::memcpy(tail(), data, size);
  size_ += size;
  return true;
}

std::size_t OutputQueue::flush(hal::ByteStream& stream) {
  if (size_ == 0u) {
    return 0u;
  }
  const std::size_t written =
      stream.write(reinterpret_cast<const std::uint8_t*>(bytes_.data()), size_);
  const std::size_t accepted = written > size_ ? size_ : written;
  size_ -= accepted;
  if (accepted > 0u) {
    for (std::size_t i = 0; i < size_; ++i) {  // forward: the regions may overlap
      bytes_[i] = bytes_[i + accepted];
    }
  }
  return accepted;
}

}  // namespace odocal::console
