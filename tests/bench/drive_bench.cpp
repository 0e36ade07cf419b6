// Drive-stack hot paths: the edge handler, one control tick, an odometry update and the inverse
// kinematics. Host figures; the Cortex-M4 instruction counts are in docs/performance.md.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "odocal/drive/control_loop.hpp"

namespace {

using namespace odocal;

class NullPwm final : public hal::PwmOutput {
  void do_set_duty(float) override {}
};
class NullOutput final : public hal::DigitalOutput {
  void do_set(bool) override {}
};
class NullCritical final : public hal::CriticalSection {
  void do_enter() override {}
  void do_exit() override {}
};

constexpr bool kA[4] = {false, true, true, false};
constexpr bool kB[4] = {false, false, true, true};

void BM_EdgeHandler(benchmark::State& state) {
  drive::QuadratureDecoder decoder;
  decoder.reset(false, false);
  std::uint32_t t = 0;
  unsigned phase = 0;
  for (auto _ : state) {
    phase = (phase + 1u) & 3u;
    decoder.on_edge(kA[phase], kB[phase], ++t);
    benchmark::DoNotOptimize(decoder);
  }
}
BENCHMARK(BM_EdgeHandler);

void BM_ControlTickOnAPath(benchmark::State& state) {
  NullPwm pwm_l, pwm_r;
  NullOutput dir_l, dir_r;
  NullCritical critical;
  drive::ControlLoop loop(drive::MotorChannel{pwm_l, dir_l}, drive::MotorChannel{pwm_r, dir_r},
                          critical);
  (void)loop.run(drive::make_umbmark_square(true, 4.0f));
  std::uint32_t t = 0;
  unsigned phase = 0;
  for (auto _ : state) {
    // About six edges per wheel per tick, as at cruise speed.
    for (int i = 0; i < 6; ++i) {
      phase = (phase + 1u) & 3u;
      t += 160u;
      loop.left_decoder().on_edge(kA[phase], kB[phase], t);
      loop.right_decoder().on_edge(kA[phase], kB[phase], t);
    }
    loop.tick(t);
  }
}
BENCHMARK(BM_ControlTickOnAPath);

void BM_OdometryUpdate(benchmark::State& state) {
  drive::Odometry odometry;
  float l = 0.0004f;
  for (auto _ : state) {
    odometry.update(l, 0.0005f, 0.15f);
    benchmark::DoNotOptimize(odometry);
    l = -l;
  }
}
BENCHMARK(BM_OdometryUpdate);

void BM_InverseKinematics(benchmark::State& state) {
  drive::DriveConfig config;
  config.f_lat = 1.01f;
  config.f_lon = 0.99f;
  const drive::DiffDriveKinematics kinematics(config);
  drive::Twist twist{0.2f, 0.3f};
  for (auto _ : state) {
    benchmark::DoNotOptimize(twist);
    const drive::WheelRates rates = kinematics.inverse(twist);
    benchmark::DoNotOptimize(rates);
  }
}
BENCHMARK(BM_InverseKinematics);

}  // namespace
