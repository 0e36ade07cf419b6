// Calibration engine timings (measured, not asserted): the residual bootstrap at the paper's
// scale with B = 10,000 (target <= 100 ms) against a plain reference implementation of the same
// bootstrap (tests/support/bootstrap_reference.hpp: heap vectors, a QR refit per replicate,
// sorting), and the UMBmark solve (target <= 10 µs).
#include <vector>

#include <benchmark/benchmark.h>

#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/random.hpp"
#include "odocal/calib/umbmark.hpp"

#include "bootstrap_reference.hpp"

namespace {

using namespace odocal::calib;

// The paper's scale: 20 training trials, 20 unknowns.
void paper_scale(std::vector<TrainingRow>& training, std::vector<UnknownRow>& unknowns) {
  Random noise(1);
  for (int i = 0; i < 20; ++i) {
    const double x = 0.25 + 0.004 * i, y = 0.013 + 0.0002 * (i % 5), w = 0.007 + 0.0003 * i;
    training.push_back({x, y, w, 33.3 * x - 2.5 * w + 0.05 * noise.normal(),
                        33.3 * x + 2.5 * w + 0.05 * noise.normal()});
    unknowns.push_back({x + 0.001, y, w});
  }
}

void BM_BootstrapReference_B10000_m20_u20(benchmark::State& state) {
  std::vector<TrainingRow> training;
  std::vector<UnknownRow> unknowns;
  paper_scale(training, unknowns);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        odocal::test::reference_bootstrap(training, unknowns, 10000, 42, 0.95));
    benchmark::ClobberMemory();
  }
  state.SetLabel("plain reference: heap, QR refit per replicate, sort");
}
BENCHMARK(BM_BootstrapReference_B10000_m20_u20)->Unit(benchmark::kMillisecond);

void BM_Bootstrap_B10000_m20_u20(benchmark::State& state) {
  std::vector<TrainingRow> training;
  std::vector<UnknownRow> unknowns;
  paper_scale(training, unknowns);
  const std::uint32_t b = 10000;
  std::vector<double> scratch(bootstrap_scratch_count(b, unknowns.size()));
  std::vector<BootstrapEstimate> estimates(unknowns.size());
  BootstrapInput in;
  in.training = training.data();
  in.training_count = training.size();
  in.unknowns = unknowns.data();
  in.unknown_count = unknowns.size();
  in.replicates = b;
  in.seed = 42;
  in.scratch = scratch.data();
  in.scratch_count = scratch.size();
  BootstrapFit fit;
  for (auto _ : state) {
    benchmark::DoNotOptimize(run_bootstrap(in, estimates.data(), estimates.size(), fit));
    benchmark::ClobberMemory();
  }
  state.SetLabel("B=10000, 20 training, 20 unknowns");
}
BENCHMARK(BM_Bootstrap_B10000_m20_u20)->Unit(benchmark::kMillisecond);

void umbmark(benchmark::State& state, bool exact) {
  const ReturnError cw[5] = {
      {-352.0, -420.0}, {-340.0, -431.0}, {-361.0, -410.0}, {-349.0, -425.0}, {-355.0, -418.0}};
  const ReturnError ccw[5] = {
      {75.0, -82.0}, {81.0, -77.0}, {70.0, -90.0}, {79.0, -80.0}, {73.0, -85.0}};
  UmbmarkInput in;
  in.cw = cw;
  in.cw_count = 5;
  in.ccw = ccw;
  in.ccw_count = 5;
  in.side_mm = 4000.0;
  in.wheelbase_mm = 340.0;
  in.exact = exact;
  UmbmarkResult result;
  for (auto _ : state) {
    benchmark::DoNotOptimize(solve_umbmark(in, result));
    benchmark::ClobberMemory();
  }
}
void BM_UmbmarkSolve_Approx(benchmark::State& state) {
  umbmark(state, false);
}
void BM_UmbmarkSolve_Exact(benchmark::State& state) {
  umbmark(state, true);
}
BENCHMARK(BM_UmbmarkSolve_Approx)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_UmbmarkSolve_Exact)->Unit(benchmark::kMicrosecond);

}  // namespace
