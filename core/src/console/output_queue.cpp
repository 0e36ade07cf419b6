#include "odocal/console/output_queue.hpp"

namespace odocal::console {

bool OutputQueue::push(const char* data, std::size_t size) {
  if (data == nullptr || size > free_space()) {
    return false;
  }
  std::size_t tail = (head_ + size_) % capacity;
  for (std::size_t i = 0; i < size; ++i) {
    bytes_[tail] = static_cast<std::uint8_t>(data[i]);
    tail = tail + 1u == capacity ? 0u : tail + 1u;
  }
  size_ += size;
  return true;
}

std::size_t OutputQueue::flush(hal::ByteStream& stream) {
  std::size_t total = 0u;
  while (size_ > 0u) {
    // The contiguous run from head_ (the queue wraps at most once).
    const std::size_t run = head_ + size_ <= capacity ? size_ : capacity - head_;
    const std::size_t written = stream.write(bytes_.data() + head_, run);
    const std::size_t accepted = written > run ? run : written;
    head_ = (head_ + accepted) % capacity;
    size_ -= accepted;
    total += accepted;
    if (accepted < run) {
      break;
    }
  }
  if (size_ == 0u) {
    head_ = 0u;
  }
  return total;
}

}  // namespace odocal::console
