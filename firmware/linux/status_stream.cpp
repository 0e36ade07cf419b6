#include "status_stream.hpp"

#include <cstring>

namespace odocal::linux_target {
namespace {

constexpr char kStatusPrefix[] = "ok mode=";
constexpr std::size_t kPrefixLength = sizeof(kStatusPrefix) - 1u;

}  // namespace

void StatusStream::flush() {
  while (!queued_.empty()) {
    const std::size_t taken =
        inner_.write(reinterpret_cast<const std::uint8_t*>(queued_.data()), queued_.size());
    if (taken == 0u) {
      return;
    }
    queued_.erase(0u, taken);
  }
}

std::size_t StatusStream::do_read(std::uint8_t* out, std::size_t capacity) {
  return inner_.read(out, capacity);
}

void StatusStream::finish_line() {
  const bool is_status = line_.compare(0u, kPrefixLength, kStatusPrefix) == 0 &&
                         line_.find(" ticks=") != std::string::npos;
  if (is_status && pairs_ != nullptr) {
    std::size_t end = line_.size() - 1u;  // the '\n'
    if (end > 0u && line_[end - 1u] == '\r') {
      --end;
    }
    char extra[512];
    const std::size_t length = pairs_(context_, extra, sizeof extra);
    line_.insert(end, extra, length < sizeof extra ? length : sizeof extra);
  }
  queued_ += line_;
  line_.clear();
}

std::size_t StatusStream::do_write(const std::uint8_t* data, std::size_t size) {
  flush();
  std::size_t accepted = 0u;
  for (; accepted < size && queued_.size() + line_.size() < max_queued; ++accepted) {
    const char byte = static_cast<char>(data[accepted]);
    line_ += byte;
    if (byte == '\n') {
      finish_line();
    } else if (line_.size() <= kPrefixLength
                   ? std::strncmp(line_.c_str(), kStatusPrefix, line_.size()) != 0
                   : line_.compare(0u, kPrefixLength, kStatusPrefix) != 0) {
      queued_ += line_;  // cannot be the status reply: pass it on now
      line_.clear();
    }
  }
  flush();
  return accepted;
}

}  // namespace odocal::linux_target
