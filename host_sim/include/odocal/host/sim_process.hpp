#pragma once
/// @file
/// `odocal-sim` started as a child on a pty, as the robot link's channel (`odocal session --sim`).

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>

#include "odocal/host/robot_link.hpp"

namespace odocal::host {

/// `odocal-sim` started as a child on a pty; stopped (SIGTERM, then waited for) on destruction.
class SimProcess {
 public:
  /// Starts `program --pty --speed 0 --seed S [--robot FILE] [--store FILE] [--protocol P]`,
  /// reads the pty path it prints and opens it. Throws LinkError (program missing, exited, no pty
  /// announced).
  SimProcess(const std::string& program, const std::string& robot_file, std::uint64_t seed,
             const std::string& store_file, const std::string& protocol = std::string());
  ~SimProcess();
  SimProcess(const SimProcess&) = delete;
  SimProcess& operator=(const SimProcess&) = delete;
  [[nodiscard]] FdChannel& channel() { return *channel_; }
  /// Stops the child now (idempotent).
  void stop();

 private:
  pid_t pid_ = -1;
  std::unique_ptr<FdChannel> channel_;
};

/// `odocal-sim` beside the running executable (/proc/self/exe's directory).
[[nodiscard]] std::string sibling_program(const std::string& name);

}  // namespace odocal::host
