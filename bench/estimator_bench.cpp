// Cost of the streaming estimator per sample, in the configuration a sub-run uses:
// increments at dt = 1e-4 s, two decades below pi/(2 dt), 8 lanes.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "slidespec/estimator.hpp"

namespace {

void BM_EstimatorPush(benchmark::State& state) {
  const int lanes = static_cast<int>(state.range(0));
  const std::size_t steps = 1 << 16;
  slidespec::SpectrumEstimator estimator({1e-4, 0, 0, 8, slidespec::SampleKind::increment}, lanes);
  std::vector<double> data(steps * lanes);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  for (double& x : data) x = normal(rng);
  for (auto _ : state) {
    estimator.push(data.data(), steps);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps) * lanes);
}
BENCHMARK(BM_EstimatorPush)->Arg(1)->Arg(8);

// The plain baseline: one FFT-free pass over the same data (reading every sample once).
void BM_ReadSamples(benchmark::State& state) {
  const int lanes = static_cast<int>(state.range(0));
  const std::size_t steps = 1 << 16;
  std::vector<double> data(steps * lanes, 1.0);
  for (auto _ : state) {
    double sum = 0;
    for (double x : data) sum += x;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps) * lanes);
}
BENCHMARK(BM_ReadSamples)->Arg(8);

}  // namespace
