// The Linux backend's parts on the mockup chips, before any robot is wired: how it names a
// missing chip, line or PWM chip and a line in use, and the software PWM's duty cycle.
#include "vm_backend_checks.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "odocal/hal/linux_gpiod/gpio_chips.hpp"
#include "odocal/hal/linux_gpiod/gpio_output.hpp"
#include "odocal/hal/linux_gpiod/software_pwm.hpp"
#include "odocal/hal/linux_gpiod/sysfs_pwm.hpp"
#include "vm_mockup.hpp"

namespace odocal::vm_test {

using namespace hal::linux_gpiod;

void check_errors() {
  ChipSet chips;
  gpiod_line* line = nullptr;
  SetupResult r = chips.find(LinePin{"gpiochip9", 0u, "left_a"}, &line);
  check(r.code == SetupCode::not_found && contains(r.message, "gpiochip9") &&
            contains(r.message, "left_a"),
        "missing chip named", r.message);
  r = chips.find(LinePin{"gpiochip0", 8u, "right_b"}, &line);
  check(r.code == SetupCode::not_found && contains(r.message, "line 8"), "missing line named",
        r.message);

  // Another process's request, as the kernel sees it: a second, independent chip handle.
  ChipSet other;
  GpioOutput held;
  r = held.open(other, LinePin{"gpiochip1", 2u, "someone_else"}, false, "other-owner");
  check(r.ok(), "first request", r.message);
  GpioOutput second;
  r = second.open(chips, LinePin{"gpiochip1", 2u, "left_dir"}, false, "odocal");
  check(r.code == SetupCode::busy && contains(r.message, "gpiochip1 line 2 (left_dir)") &&
            contains(r.message, "other-owner"),
        "line in use named", r.message);
  // The same line twice within one process (two roles on one line).
  GpioOutput mine;
  r = mine.open(chips, LinePin{"gpiochip1", 3u, "right_dir"}, false, "odocal");
  GpioOutput again;
  SetupResult twice = again.open(chips, LinePin{"gpiochip1", 3u, "enable"}, false, "odocal");
  check(r.ok() && twice.code == SetupCode::busy && contains(twice.message, "(enable)"),
        "line used twice named", twice.message);

  SysfsPwm pwm;
  r = pwm.open(0u, 0u, 20000u, "left_pwm");
  check(r.code == SetupCode::not_found && contains(r.message, "pwmchip0"), "missing PWM chip named",
        r.message);
}

void check_software_pwm_duty() {
  ChipSet chips;
  SoftwarePwm pwm;
  SetupResult r =
      pwm.open(chips, LinePin{"gpiochip1", 1u, "test_pwm"}, 100u, kPwmPriority, "odocal-test");
  check(r.ok(), "software PWM open", r.message);
  if (!r.ok()) {
    return;
  }
  MockLine probe(1, 1);
  pwm.set_duty(0.3f);
  sleep_ms(50);
  // Sample for one second; count rising edges and the fraction of samples that were high.
  std::uint32_t samples = 0u;
  std::uint32_t high = 0u;
  std::uint32_t rises = 0u;
  int previous = probe.read();
  const std::uint64_t end_ns = monotonic_ns() + 1000000000u;
  while (monotonic_ns() < end_ns) {
    const int level = probe.read();
    if (level < 0) {
      break;
    }
    ++samples;
    high += static_cast<std::uint32_t>(level);
    rises += (level == 1 && previous == 0) ? 1u : 0u;
    previous = level;
    const timespec pause{0, 100000};
    nanosleep(&pause, nullptr);
  }
  const double fraction = samples > 0u ? static_cast<double>(high) / samples : 0.0;
  char detail[160];
  std::snprintf(detail, sizeof detail,
                "100 Hz, duty 0.30: %u rising edges in 1 s, high %.3f of %u samples, realtime %s",
                rises, fraction, samples, pwm.realtime() ? "yes" : "no");
  // Loose bounds: the carrier is low precision by design and a TCG guest adds latency.
  check(rises >= 60u && rises <= 105u && std::fabs(fraction - 0.3) < 0.1, "software PWM duty",
        detail);
  std::printf("BENCH software_pwm rises=%u high_fraction=%.3f samples=%u\n", rises, fraction,
              samples);
  pwm.set_duty(0.0f);
  sleep_ms(30);
  const int off = probe.read();
  pwm.set_duty(1.0f);
  sleep_ms(30);
  const int on = probe.read();
  check(off == 0 && on == 1, "software PWM 0 and 1",
        "duty 0 -> " + std::to_string(off) + ", duty 1 -> " + std::to_string(on));
}

}  // namespace odocal::vm_test
