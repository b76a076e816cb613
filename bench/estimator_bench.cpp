// Cost of the streaming estimator per sample: increments at dt = 1e-4 s over two decades
// below pi/(2 dt) (every band transforms), and in a run sub-band's configuration; and the
// share of a reference run's time that goes to the estimator.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <random>
#include <vector>

#include "process_time.hpp"
#include "slidespec/estimator.hpp"
#include "slidespec/run.hpp"

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

// The configuration of a run's sub-band: increments at dt, one decade of points up to
// omega dt = 0.3 (so the two fastest bands of the cascade only decimate), 8 lanes.
slidespec::EstimatorConfig sub_band_config() {
  const double dt = 1e-4;
  return {dt, 0.03 / dt, 0.3 / dt, 8, slidespec::SampleKind::increment};
}

std::vector<double> white_increments(std::size_t count) {
  std::vector<double> data(count);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  for (double& x : data) x = normal(rng);
  return data;
}

// Args: lanes. Items: samples (lane x step) per CPU second.
void BM_EstimatorSubBand(benchmark::State& state) {
  const int lanes = static_cast<int>(state.range(0));
  const std::size_t steps = 1 << 16;
  slidespec::SpectrumEstimator estimator(sub_band_config(), lanes);
  const std::vector<double> data = white_increments(steps * lanes);
  for (auto _ : state) {
    estimator.push(data.data(), steps);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps) * lanes);
}
BENCHMARK(BM_EstimatorSubBand)->Arg(1)->Arg(8);

// Args: index into available_simd_paths(). The sub-band configuration, 8 lanes, on one
// path: every path gives the same bits, so this only shows what each is worth.
void BM_EstimatorSubBandPath(benchmark::State& state) {
  const auto paths = slidespec::available_simd_paths();
  const auto index = static_cast<std::size_t>(state.range(0));
  if (index >= paths.size()) {
    state.SkipWithError("path not available on this CPU");
    return;
  }
  state.SetLabel(slidespec::to_string(paths[index]));
  const int lanes = 8;
  const std::size_t steps = 1 << 16;
  slidespec::SpectrumEstimator estimator(sub_band_config(), lanes, paths[index]);
  const std::vector<double> data = white_increments(steps * lanes);
  for (auto _ : state) {
    estimator.push(data.data(), steps);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps) * lanes);
}
BENCHMARK(BM_EstimatorSubBandPath)->DenseRange(0, 3);

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

namespace {

using namespace slidespec;
using bench::process_cpu_seconds;

struct Cost {
  double wall = 0, cpu = 0;
  double renewals = 0, lane_passes = 0;  // renewals, and renewal passes times their lanes
};

/// Wall and CPU time of the plan `result` ran (same sub-bands, time steps, streams and
/// realizations, in batches of 8 as a run makes them), stepping alone or stepping into one
/// estimator per batch as run_spectrum does.
Cost replay_plan(const Parameters& p, const RunRequest& request, const RunResult& result, bool estimate) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  double renewals = 0, lane_passes = 0;
  for (std::size_t b = 0; b < result.sub_bands.size(); ++b) {
    const SubBand& band = result.sub_bands[b];
    StepperConfig config;
    config.dt = band.dt;
    config.seed = request.seed;
    config.stream = b;
    config.simd = result.simd_path;
    EstimatorConfig estimator_config{band.dt, band.omega_low, band.omega_high, request.points_per_decade,
                                     SampleKind::increment};
    auto make_sink = [&](std::uint64_t, int count) -> IncrementSink {
      if (!estimate) return {};
      auto estimator = std::make_shared<SpectrumEstimator>(estimator_config, count);
      return [estimator](const double* data, std::size_t n) { estimator->push(data, n); };
    };
    std::mutex counting;
    run_batches(p, config, 0, band.realizations, std::llround(band.duration / band.dt), result.threads, 8, make_sink,
                [&](std::size_t, std::vector<RealizationSummary> summaries) {
                  const std::lock_guard<std::mutex> lock(counting);
                  for (const RealizationSummary& r : summaries)
                    renewals += double(r.renewals), lane_passes += double(r.renewal_passes);
                });
  }
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          process_cpu_seconds() - cpu_start, renewals, lane_passes};
}

// Args: threads. The reference case over 0.1 .. 1e5 rad/s at 5% precision: one
// run_spectrum, then its plan replayed stepping alone and stepping into the estimators,
// in the same iteration so that the three times see the same machine load.
void ReferenceRun(benchmark::State& state) {
  const Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  request.threads = static_cast<int>(state.range(0));
  Cost run, stepping, both;
  double samples = 0, utilization = 0;
  for (auto _ : state) {
    const double cpu_start = process_cpu_seconds();
    const RunResult result = run_spectrum(p, request);
    run.cpu += process_cpu_seconds() - cpu_start;
    run.wall += result.wall_seconds;
    const Cost alone = replay_plan(p, request, result, false), estimated = replay_plan(p, request, result, true);
    stepping.wall += alone.wall;
    stepping.cpu += alone.cpu;
    both.wall += estimated.wall;
    both.cpu += estimated.cpu;
    samples = result.realization_steps;
    utilization = alone.renewals / alone.lane_passes;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["run_s"] = run.wall / n;
  state.counters["run_cpu_s"] = run.cpu / n;
  state.counters["stepping_cpu_s"] = stepping.cpu / n;
  state.counters["stepping_and_estimation_cpu_s"] = both.cpu / n;
  // Shares in CPU time: the machine is shared, and wall-time differences of a few tenths
  // of a second between the three passes are mostly other processes.
  state.counters["estimator_share_of_run"] = (both.cpu - stepping.cpu) / run.cpu;
  state.counters["stepping_share_of_run"] = stepping.cpu / run.cpu;
  state.counters["estimator_samples_per_cpu_s"] = samples * n / (both.cpu - stepping.cpu);
  state.counters["realization_steps"] = samples;
  state.counters["lane_utilization"] = utilization;  // of the renewal passes, in the replay
}
BENCHMARK(ReferenceRun)->Arg(1)->Arg(2)->ArgName("threads")->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
