#pragma once
// Scratch files for the fuzz targets whose code under test reads a path (a tick log, a
// measurements CSV, a session's directory): one directory per fuzzing process under $TMPDIR (or
// /tmp), named with the process id, removed when the process exits normally (a crash leaves it
// with the input that crashed, which libFuzzer also saves).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace odocal::fuzz {

class ScratchDir {
 public:
  explicit ScratchDir(const char* target) {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/odocal-fuzz-" + target +
            "-" + std::to_string(::getpid());
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }

  /// Writes `size` bytes as `name` in the directory (replacing it); returns its path.
  std::string write(const std::string& name, const void* data, std::size_t size) const {
    const std::string file = path_ + "/" + name;
    std::FILE* out = std::fopen(file.c_str(), "wb");
    if (out == nullptr || (size != 0u && std::fwrite(data, 1, size, out) != size) ||
        std::fclose(out) != 0) {
      std::perror(file.c_str());
      std::abort();  // the harness's own failure, not a finding
    }
    return file;
  }
  std::string write(const std::string& name, const std::string& text) const {
    return write(name, text.data(), text.size());
  }

  /// Removes `name` from the directory when it is there.
  void remove(const std::string& name) const {
    std::error_code ignored;
    std::filesystem::remove(path_ + "/" + name, ignored);
  }

 private:
  std::string path_;
};

}  // namespace odocal::fuzz
