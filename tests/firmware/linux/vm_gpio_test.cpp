// The Linux backend against a real kernel GPIO device: runs inside a QEMU VM whose kernel has
// gpio-mockup loaded with two chips (gpio_mockup_ranges=-1,8,-1,4). Encoder edges are made by
// writing the mockup's debugfs files, which raise real line events through the kernel's GPIO
// character device; everything on the other side is the real hal/linux_gpiod backend and the
// real core decoders and control loop.
//
// Lines: gpiochip0 0..3 encoder left A/B, right A/B; 4, 5 direction left/right; 6 enable;
// 7 left PWM (software). gpiochip1 0 right PWM (software); 1 the duty-cycle test line;
// 2, 3 the "in use" test lines.
//
// Prints one line per check and ends with "ODOCAL-VM-RESULT: PASS" or "... FAIL"; benchmark
// lines start with "BENCH" and do not decide the result.

#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "odocal/drive/control_loop.hpp"
#include "odocal/hal/linux_gpiod/encoder_events.hpp"
#include "odocal/hal/linux_gpiod/gpio_chips.hpp"
#include "odocal/hal/linux_gpiod/gpio_output.hpp"
#include "odocal/hal/linux_gpiod/mutex_critical_section.hpp"
#include "odocal/hal/linux_gpiod/posix_clock.hpp"
#include "odocal/hal/linux_gpiod/software_pwm.hpp"
#include "odocal/hal/linux_gpiod/sysfs_pwm.hpp"
#include "odocal/hal/linux_gpiod/timerfd_tick.hpp"
#include "robot.hpp"
#include "vm_backend_checks.hpp"
#include "vm_mockup.hpp"

namespace {

using namespace odocal::hal::linux_gpiod;
using namespace odocal::vm_test;
namespace drive = odocal::drive;
using odocal::linux_target::LinuxConfig;
using odocal::linux_target::Robot;

struct Counts {
  std::int32_t left = 0;
  std::int32_t right = 0;
  std::uint32_t illegal = 0u;
};

Counts counts(drive::ControlLoop& loop, odocal::hal::CriticalSection& critical) {
  odocal::hal::CriticalGuard guard(critical);
  const drive::EncoderSnapshot l = loop.left_decoder().snapshot();
  const drive::EncoderSnapshot r = loop.right_decoder().snapshot();
  return Counts{static_cast<std::int32_t>(l.count), static_cast<std::int32_t>(r.count),
                l.illegal + r.illegal};
}

// The robot process's own wiring (firmware/linux/robot.hpp) on the mockup chips: no PWM chip
// there, so both motors take the software fallback.
LinuxConfig vm_config() {
  LinuxConfig config;
  config.left_a = LinePin{"gpiochip0", 0u, "left_a"};
  config.left_b = LinePin{"gpiochip0", 1u, "left_b"};
  config.right_a = LinePin{"gpiochip0", 2u, "right_a"};
  config.right_b = LinePin{"gpiochip0", 3u, "right_b"};
  config.left_dir = LinePin{"gpiochip0", 4u, "left_dir"};
  config.right_dir = LinePin{"gpiochip0", 5u, "right_dir"};
  config.has_enable = true;
  config.enable = LinePin{"gpiochip0", 6u, "enable"};
  config.left_pwm.has_gpio = true;
  config.left_pwm.gpio = LinePin{"gpiochip0", 7u, "left_pwm"};
  config.right_pwm.has_gpio = true;
  config.right_pwm.gpio = LinePin{"gpio-mockup-B", 0u, "right_pwm"};
  config.soft_pwm_hz = 200u;
  config.event_priority = kEventPriority;
  config.tick_priority = kTickPriority;
  config.pwm_priority = kPwmPriority;
  config.event_holdback_us = kHoldback_us;
  return config;
}

// Opens the robot and starts its encoder thread and its 1 kHz tick.
SetupResult open_robot(Robot& robot) {
  const LinuxConfig config = vm_config();
  SetupResult r = robot.open(config);
  if (r.ok()) {
    r = robot.start(config, 1000u);
  }
  return r;
}

std::string describe_counts(const Counts& c, const EncoderStats& l, const EncoderStats& r) {
  char text[240];
  std::snprintf(text, sizeof text,
                "left %d right %d illegal %u | dropped %u/%u misread %u/%u queue_full %u/%u "
                "reordered %u/%u",
                static_cast<int>(c.left), static_cast<int>(c.right), c.illegal, l.dropped,
                r.dropped, l.misread, r.misread, l.queue_full, r.queue_full, l.reordered,
                r.reordered);
  return text;
}

void check_counting(Robot& robot, QuadratureGenerator& generator) {
  const Counts before = counts(*robot.loop, robot.critical);
  const QuadratureGenerator::Result moved = generator.move(1000, -600, kCheckRate);
  sleep_ms(100);
  Counts after = counts(*robot.loop, robot.critical);
  Counts delta{after.left - before.left, after.right - before.right,
               after.illegal - before.illegal};
  EncoderStats ls = robot.encoders->stats(Wheel::left);
  EncoderStats rs = robot.encoders->stats(Wheel::right);
  char rate[80];
  std::snprintf(rate, sizeof rate, " @ %.0f edges/s", moved.rate_hz());
  check(delta.left == 1000 && delta.right == -600 && delta.illegal == 0u && ls.dropped == 0u &&
            rs.dropped == 0u,
        "counts +1000 / -600", describe_counts(delta, ls, rs) + rate);

  const Counts middle = after;
  generator.move(-300, 200, kCheckRate);
  sleep_ms(100);
  after = counts(*robot.loop, robot.critical);
  delta =
      Counts{after.left - middle.left, after.right - middle.right, after.illegal - middle.illegal};
  ls = robot.encoders->stats(Wheel::left);
  rs = robot.encoders->stats(Wheel::right);
  check(delta.left == -300 && delta.right == 200 && delta.illegal == 0u && ls.dropped == 0u &&
            rs.dropped == 0u,
        "direction reversed -300 / +200", describe_counts(delta, ls, rs));
}

void check_dropped(Robot& robot, QuadratureGenerator& generator) {
  // With the reader stopped, 41 left edges: A toggles 21 times and B 20, the kernel keeps 16 of
  // each and drops the rest. Five lost A edges (odd) show as a repeated edge type later.
  const EncoderStats before = robot.encoders->stats(Wheel::left);
  const Counts start = counts(*robot.loop, robot.critical);
  robot.encoders->stop();
  generator.move(41, 0, 2000.0);
  SetupResult r = robot.encoders->start(kEventPriority, kHoldback_us);
  generator.move(8, 0, 2000.0);
  sleep_ms(100);
  const EncoderStats after = robot.encoders->stats(Wheel::left);
  const Counts end = counts(*robot.loop, robot.critical);
  char detail[200];
  std::snprintf(detail, sizeof detail,
                "49 edges, 9 lost in the kernel: counted %d, dropped +%u, queue_full +%u",
                static_cast<int>(end.left - start.left), after.dropped - before.dropped,
                after.queue_full - before.queue_full);
  check(r.ok() && after.dropped > before.dropped && after.queue_full > before.queue_full &&
            end.left - start.left != 49,
        "lost edges detected", detail);
}

struct TurnSample {
  int left_dir = -1;
  int right_dir = -1;
  std::uint32_t left_rises = 0u;
  std::uint32_t right_rises = 0u;
};

// Turns in place for 0.3 s with the wheels held still (nothing moves the encoder lines): the
// PI loop raises the duty and the direction lines follow its sign.
TurnSample turn(Robot& robot, float w_radps) {
  MockLine left_dir(0, 4);
  MockLine right_dir(0, 5);
  MockLine left_pwm(0, 7);
  MockLine right_pwm(1, 0);
  TurnSample sample;
  if (!robot.loop->drive(drive::Twist{0.0f, w_radps}, 400u)) {
    return sample;
  }
  int prev_l = left_pwm.read();
  int prev_r = right_pwm.read();
  const std::uint64_t end_ns = monotonic_ns() + 300000000u;
  while (monotonic_ns() < end_ns) {
    const int l = left_pwm.read();
    const int r = right_pwm.read();
    sample.left_rises += (l == 1 && prev_l == 0) ? 1u : 0u;
    sample.right_rises += (r == 1 && prev_r == 0) ? 1u : 0u;
    prev_l = l;
    prev_r = r;
    sample.left_dir = left_dir.read();
    sample.right_dir = right_dir.read();
    const timespec pause{0, 100000};
    nanosleep(&pause, nullptr);
  }
  robot.loop->stop();
  sleep_ms(50);
  return sample;
}

void check_outputs(Robot& robot) {
  MockLine left_dir(0, 4);
  MockLine right_dir(0, 5);
  const int idle_left = left_dir.read();
  const int idle_right = right_dir.read();
  const TurnSample clockwise = turn(robot, -1.5f);  // left forward, right backward
  const TurnSample counter = turn(robot, 1.5f);     // left backward, right forward
  const int stopped_left = left_dir.read();
  const int stopped_right = right_dir.read();
  char detail[240];
  std::snprintf(detail, sizeof detail,
                "dir L/R idle %d/%d, cw %d/%d, ccw %d/%d, stopped %d/%d; PWM rises in 0.3 s "
                "cw %u/%u ccw %u/%u",
                idle_left, idle_right, clockwise.left_dir, clockwise.right_dir, counter.left_dir,
                counter.right_dir, stopped_left, stopped_right, clockwise.left_rises,
                clockwise.right_rises, counter.left_rises, counter.right_rises);
  check(idle_left == 1 && idle_right == 1 && clockwise.left_dir == 1 && clockwise.right_dir == 0 &&
            counter.left_dir == 0 && counter.right_dir == 1 && stopped_left == 1 &&
            stopped_right == 1 && clockwise.left_rises >= 5u && clockwise.right_rises >= 5u &&
            counter.left_rises >= 5u && counter.right_rises >= 5u,
        "direction and PWM outputs", detail);
}

void check_tick(Robot& robot) {
  robot.tick->reset_stats();
  const TickStats before = robot.tick->stats();
  const std::uint64_t start_ns = monotonic_ns();
  sleep_ms(1000);
  const TickStats after = robot.tick->stats();
  const double periods = static_cast<double>(monotonic_ns() - start_ns) * 1e-9 * after.rate_hz;
  const std::uint32_t ticks = after.ticks - before.ticks;
  const std::uint32_t accounted = ticks + after.missed;
  const drive::LoopStatus status = robot.loop->status();
  char detail[240];
  std::snprintf(detail, sizeof detail,
                "%u ticks + %u missed in %.0f periods at %u Hz; late mean %u us max %u us, "
                "handler max %u us, realtime %s",
                ticks, after.missed, periods, after.rate_hz, after.late_us_mean, after.late_us_max,
                after.handler_us_max, after.realtime ? "yes" : "no");
  // Every period is either run or counted as missed (a busy host pauses the whole guest, so the
  // number missed is not a property of the backend); the loop itself must have ticked.
  check(std::fabs(accounted - periods) <= 0.02 * periods + 2.0 && ticks >= periods / 4.0 &&
            status.ticks > 0u,
        "timerfd tick 1 kHz", detail);
  std::printf("BENCH tick_jitter rate_hz=%u late_mean_us=%u late_max_us=%u missed=%u of %.0f\n",
              after.rate_hz, after.late_us_mean, after.late_us_max, after.missed, periods);
}

void benchmark(Robot& robot, QuadratureGenerator& generator) {
  // Edge rates the backend keeps up with: exact counts and no lost edge. The generator's own
  // ceiling (one debugfs write per edge) bounds what can be offered in the VM.
  const double rates[] = {1000.0, 2000.0, 5000.0, 10000.0, 20000.0, 0.0};
  double best = 0.0;
  for (const double rate : rates) {
    const Counts before = counts(*robot.loop, robot.critical);
    const EncoderStats lb = robot.encoders->stats(Wheel::left);
    const EncoderStats rb = robot.encoders->stats(Wheel::right);
    const QuadratureGenerator::Result moved = generator.move(1000, -1000, rate);
    sleep_ms(200);
    const Counts after = counts(*robot.loop, robot.critical);
    const EncoderStats la = robot.encoders->stats(Wheel::left);
    const EncoderStats ra = robot.encoders->stats(Wheel::right);
    const bool exact = after.left - before.left == 1000 && after.right - before.right == -1000;
    const std::uint32_t lost = (la.dropped - lb.dropped) + (ra.dropped - rb.dropped);
    const std::uint32_t full = (la.queue_full - lb.queue_full) + (ra.queue_full - rb.queue_full);
    const std::uint32_t misread = (la.misread - lb.misread) + (ra.misread - rb.misread);
    std::printf(
        "BENCH edges offered=%s achieved=%.0f/s counted=%d/%d exact=%s dropped=%u "
        "misread=%u queue_full=%u\n",
        rate > 0.0 ? std::to_string(static_cast<int>(rate)).c_str() : "max", moved.rate_hz(),
        static_cast<int>(after.left - before.left), static_cast<int>(after.right - before.right),
        exact ? "yes" : "no", lost, misread, full);
    std::fflush(stdout);
    if (exact && lost == 0u && moved.rate_hz() > best) {
      best = moved.rate_hz();
    }
    // Re-align the generator's idea of the levels with the decoders' after a lossy run.
    if (!exact) {
      generator.move(4, 4, 1000.0);
      sleep_ms(50);
    }
  }
  std::printf("BENCH kept_up_edges_per_s=%.0f\n", best);
}

}  // namespace

int main() {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::printf("odocal VM test: hal/linux_gpiod against gpio-mockup\n");
  check_errors();
  check_software_pwm_duty();

  // The generator stands for the outside world: steady, but below every backend thread.
  (void)make_thread_realtime(kGeneratorPriority);
  QuadratureGenerator generator;
  check(generator.valid(), "debugfs mockup lines", kDebugfs);
  Robot robot;
  const SetupResult opened = open_robot(robot);
  check(opened.ok(), "robot wiring", opened.ok() ? "all lines requested" : opened.message);
  // Read at once: `start` returns only when the threads know whether they got SCHED_FIFO, so a
  // `status` right after start-up never reports a thread that has not tried yet (root here).
  check(opened.ok() && robot.tick->stats().realtime && robot.encoders->realtime(),
        "realtime known at start", opened.ok() ? robot.tick->realtime_reason() : "not opened");
  if (opened.ok() && generator.valid()) {
    check_tick(robot);
    check_counting(robot, generator);
    check_dropped(robot, generator);
    check_outputs(robot);
    benchmark(robot, generator);
  }
  std::printf("ODOCAL-VM-RESULT: %s (%d failed)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
