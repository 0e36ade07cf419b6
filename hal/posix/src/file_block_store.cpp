#include "odocal/posix/file_block_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace odocal::posix {
namespace {

bool write_all(int fd, const std::uint8_t* data, std::size_t size) {
  while (size > 0u) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) {
    return ".";
  }
  return slash == 0u ? "/" : path.substr(0, slash);
}

}  // namespace

FileBlockStore::FileBlockStore(std::string path, std::size_t sector_size, std::size_t sector_count,
                               std::size_t program_granularity)
    : path_(std::move(path)),
      sector_size_(sector_size),
      sector_count_(sector_count),
      granularity_(program_granularity),
      image_(sector_size * sector_count, 0xFFu) {}

bool FileBlockStore::open(std::string& error) {
  usable_ = false;
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) {
      std::fill(image_.begin(), image_.end(), 0xFFu);
      usable_ = true;
      return true;
    }
    error = path_ + ": " + std::strerror(errno);
    return false;
  }
  struct stat info {};
  if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size == 0) {
    // An empty file (e.g. from mktemp or `: > store.bin`) is a new, erased flash.
    ::close(fd);
    std::fill(image_.begin(), image_.end(), 0xFFu);
    usable_ = true;
    return true;
  }
  // Any other size is not ours: refuse rather than overwrite someone's file.
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode) ||
      static_cast<std::size_t>(info.st_size) != image_.size()) {
    error = path_ + ": not a store image of " + std::to_string(image_.size()) + " bytes";
    ::close(fd);
    return false;
  }
  std::size_t got = 0u;
  while (got < image_.size()) {
    const ssize_t n = ::read(fd, image_.data() + got, image_.size() - got);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      error = path_ + ": read failed";
      ::close(fd);
      return false;
    }
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  usable_ = true;
  return true;
}

bool FileBlockStore::commit(const std::vector<std::uint8_t>& image) {
  const std::string temporary = path_ + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    return false;
  }
  const bool written = write_all(fd, image.data(), image.size()) && ::fsync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed || ::rename(temporary.c_str(), path_.c_str()) != 0) {
    ::unlink(temporary.c_str());
    return false;
  }
  // The rename is durable only once the directory entry is on disk.
  const int dir = ::open(directory_of(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
  image_ = image;
  ++commits_;
  return true;
}

hal::StoreStatus FileBlockStore::do_erase(std::size_t index) {
  if (!usable_) {
    return hal::StoreStatus::device_error;
  }
  std::vector<std::uint8_t> next = image_;
  std::fill(next.begin() + static_cast<std::ptrdiff_t>(index * sector_size_),
            next.begin() + static_cast<std::ptrdiff_t>((index + 1u) * sector_size_), 0xFFu);
  return commit(next) ? hal::StoreStatus::ok : hal::StoreStatus::device_error;
}

hal::StoreStatus FileBlockStore::do_program(std::size_t address, const std::uint8_t* data,
                                            std::size_t size) {
  if (!usable_) {
    return hal::StoreStatus::device_error;
  }
  for (std::size_t i = 0; i < size; ++i) {
    if ((data[i] & ~image_[address + i] & 0xFFu) != 0u) {
      return hal::StoreStatus::not_erased;
    }
  }
  std::vector<std::uint8_t> next = image_;
  for (std::size_t i = 0; i < size; ++i) {
    next[address + i] &= data[i];
  }
  return commit(next) ? hal::StoreStatus::ok : hal::StoreStatus::device_error;
}

hal::StoreStatus FileBlockStore::do_read(std::size_t address, std::uint8_t* out, std::size_t size) {
  if (!usable_) {
    return hal::StoreStatus::device_error;
  }
  std::memcpy(out, image_.data() + address, size);
  return hal::StoreStatus::ok;
}

}  // namespace odocal::posix
