#include "odocal/hal/linux_gpiod/sysfs_pwm.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace odocal::hal::linux_gpiod {
namespace {

bool exists(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0;
}

// Writes `text` to a sysfs attribute; returns 0 or the errno.
int write_attribute(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) {
    return errno;
  }
  const ssize_t written = ::write(fd, text.data(), text.size());
  const int error_number = written < 0 ? errno : 0;
  ::close(fd);
  return error_number;
}

// Reads an unsigned decimal attribute; false when missing or unreadable.
bool read_unsigned(const std::string& path, unsigned long* value) {
  FILE* file = std::fopen(path.c_str(), "re");
  if (file == nullptr) {
    return false;
  }
  const bool ok = std::fscanf(file, "%lu", value) == 1;
  std::fclose(file);
  return ok;
}

}  // namespace

SysfsPwm::~SysfsPwm() {
  close();
}

SetupResult SysfsPwm::open(unsigned int chip, unsigned int channel, std::uint32_t frequency_hz,
                           const std::string& role) {
  close();
  const std::string chip_name = "pwmchip" + std::to_string(chip);
  const std::string chip_dir = root_ + "/" + chip_name;
  const std::string who = role.empty() ? std::string() : role + ": ";
  if (frequency_hz < 1u || frequency_hz > 10000000u) {
    return SetupResult::failure(
        SetupCode::bad_argument,
        who + "PWM frequency " + std::to_string(frequency_hz) + " Hz outside 1..10000000");
  }
  if (!exists(chip_dir)) {
    return SetupResult::failure(SetupCode::not_found,
                                who + "PWM chip " + chip_dir +
                                    " not found (is the PWM overlay enabled? On a Raspberry Pi: "
                                    "dtoverlay=pwm-2chan in config.txt)");
  }
  unsigned long channels = 0u;
  if (read_unsigned(chip_dir + "/npwm", &channels) && channel >= channels) {
    return SetupResult::failure(SetupCode::not_found,
                                who + chip_name + " has " + std::to_string(channels) +
                                    " channels; channel " + std::to_string(channel) +
                                    " does not exist");
  }
  channel_dir_ = chip_dir + "/pwm" + std::to_string(channel);
  name_ = chip_name + "/pwm" + std::to_string(channel);
  channel_ = channel;
  if (!exists(channel_dir_)) {
    const int error_number = write_attribute(chip_dir + "/export", std::to_string(channel));
    if (error_number != 0) {
      const SetupCode code = code_of_errno(error_number);
      return SetupResult::failure(
          code, who + "cannot export " + name_ + ": " + std::strerror(error_number) +
                    (code == SetupCode::busy ? " (the channel is used by a kernel driver)" : ""));
    }
    exported_by_us_ = true;
    // udev may still be fixing the new directory's permissions: wait up to a second.
    for (int attempt = 0; attempt < 100 && access((channel_dir_ + "/enable").c_str(), W_OK) != 0;
         ++attempt) {
      const timespec pause{0, 10000000};
      nanosleep(&pause, nullptr);
    }
  }
  period_ns_ = static_cast<std::uint32_t>(1000000000u / frequency_hz);
  // Duty first (it must never exceed the period), then the period, then enable.
  int error_number = write_attribute(channel_dir_ + "/duty_cycle", "0\n");
  if (error_number == 0) {
    error_number = write_attribute(channel_dir_ + "/period", std::to_string(period_ns_) + "\n");
  }
  if (error_number == 0) {
    error_number = write_attribute(channel_dir_ + "/enable", "1\n");
  }
  if (error_number == 0) {
    duty_fd_ = ::open((channel_dir_ + "/duty_cycle").c_str(), O_WRONLY | O_CLOEXEC);
    if (duty_fd_ < 0) {
      error_number = errno;
    }
  }
  if (error_number != 0) {
    SetupResult failed =
        SetupResult::failure(code_of_errno(error_number), who + "cannot set up " + channel_dir_ +
                                                              ": " + std::strerror(error_number));
    close();
    return failed;
  }
  duty_.store(0.0f, std::memory_order_relaxed);
  return SetupResult::success();
}

void SysfsPwm::close() {
  if (duty_fd_ >= 0) {
    (void)!::pwrite(duty_fd_, "0\n", 2, 0);
    ::close(duty_fd_);
    duty_fd_ = -1;
    (void)write_attribute(channel_dir_ + "/enable", "0\n");
  }
  if (exported_by_us_) {
    const std::string chip_dir = channel_dir_.substr(0, channel_dir_.rfind('/'));
    (void)write_attribute(chip_dir + "/unexport", std::to_string(channel_));
    exported_by_us_ = false;
  }
  period_ns_ = 0u;
  duty_.store(0.0f, std::memory_order_relaxed);
}

void SysfsPwm::do_set_duty(float duty) {
  duty_.store(duty, std::memory_order_relaxed);
  if (duty_fd_ < 0) {
    return;
  }
  // No allocation here: this runs on the tick thread.
  const auto high_ns = static_cast<std::uint32_t>(static_cast<double>(duty) * period_ns_ + 0.5);
  char text[16];
  const int length = std::snprintf(text, sizeof text, "%u\n", static_cast<unsigned>(high_ns));
  if (length > 0) {
    (void)!::pwrite(duty_fd_, text, static_cast<std::size_t>(length), 0);
  }
}

}  // namespace odocal::hal::linux_gpiod
