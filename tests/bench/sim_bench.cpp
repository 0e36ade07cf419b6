// Whole simulated procedures: how many times faster than real time `odocal sim umbmark` runs with
// 1 kHz control and every encoder edge simulated, and the cost of one Monte Carlo robot.
#include <benchmark/benchmark.h>

#include <chrono>

#include "odocal/host/sim_procedures.hpp"

namespace {

using namespace odocal::host;

void BM_SimUmbmarkRealTimeRatio(benchmark::State& state) {
  const RobotSpec robot = default_robot();
  double simulated_s = 0.0;
  double wall_s = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const UmbmarkReport report = run_umbmark(robot, 1u, UmbmarkOptions{});
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    simulated_s += report.simulated_s;
    benchmark::DoNotOptimize(report.improvement_fold);
  }
  state.counters["simulated_s"] = simulated_s / static_cast<double>(state.iterations());
  state.counters["realtime_x"] = simulated_s / wall_s;
}
BENCHMARK(BM_SimUmbmarkRealTimeRatio)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_MonteCarloPerRobot(benchmark::State& state) {
  // The `odocal sim montecarlo` settings; 1,000 robots cost 1,000x this divided by the threads.
  MonteCarloOptions options;
  options.robots = 20;
  options.threads = 2;
  options.umbmark.side_m = 1.5;
  options.umbmark.v_max_mps = 0.4;
  options.umbmark.control_hz = 500.0f;
  const RobotSpec robot = default_robot();
  for (auto _ : state) {
    const MonteCarloReport report = run_montecarlo(robot, 7u, options);
    benchmark::DoNotOptimize(report.simulated_s);
  }
  state.counters["robots_per_s"] = benchmark::Counter(
      static_cast<double>(options.robots) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MonteCarloPerRobot)->Unit(benchmark::kMillisecond)->Iterations(2)->UseRealTime();

}  // namespace
