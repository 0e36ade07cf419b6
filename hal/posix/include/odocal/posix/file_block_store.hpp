#pragma once
/// @file
/// A hal::BlockStore kept in a file, for the host simulator and the Linux board.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "odocal/hal/block_store.hpp"

namespace odocal::posix {

/// A flash image in a file. Each erase or program is atomic on disk: the whole new image is
/// written to `<path>.tmp`, fsync'd, renamed over `<path>`, and the directory fsync'd, so a crash
/// or power cut leaves either the image before the operation or the one after it.
/// Flash rules are kept (erase to 0xFF by sector, program only clears bits, aligned to the
/// granularity) so the parameter store behaves exactly as on the robot's flash.
/// Main-loop only. Not for concurrent use by two processes.
class FileBlockStore final : public hal::BlockStore {
 public:
  FileBlockStore(std::string path, std::size_t sector_size = 4096u, std::size_t sector_count = 2u,
                 std::size_t program_granularity = 4u);
  ~FileBlockStore() = default;

  /// Reads the image from the file; a missing file is an erased device (the file appears at the
  /// first erase or program). @return false, with `error` set, when the file cannot be read or
  /// its size is not sector_size * sector_count (it is then left untouched and every operation
  /// fails with device_error).
  bool open(std::string& error);

  [[nodiscard]] const std::string& path() const { return path_; }
  /// Erase + program operations that reached the disk.
  [[nodiscard]] std::size_t commits() const { return commits_; }

 private:
  std::size_t do_sector_size() const override { return sector_size_; }
  std::size_t do_sector_count() const override { return sector_count_; }
  std::size_t do_program_granularity() const override { return granularity_; }
  hal::StoreStatus do_erase(std::size_t index) override;
  hal::StoreStatus do_program(std::size_t address, const std::uint8_t* data,
                              std::size_t size) override;
  hal::StoreStatus do_read(std::size_t address, std::uint8_t* out, std::size_t size) override;

  /// Writes `image` atomically; on success it becomes the current image.
  bool commit(const std::vector<std::uint8_t>& image);

  std::string path_;
  std::size_t sector_size_;
  std::size_t sector_count_;
  std::size_t granularity_;
  std::vector<std::uint8_t> image_;
  bool usable_ = false;
  std::size_t commits_ = 0u;
};

}  // namespace odocal::posix
