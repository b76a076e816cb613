// The short-record estimator (welch_spectrum: FFTW, Hann, half-overlapping segments) on
// random walks of a measured record's lengths, beside the streaming estimator on the same
// record in the same run. scipy.signal.welch on the same lengths: bench/welch_scipy.py.
#include <benchmark/benchmark.h>

#include <random>

#include "slidespec/analysis.hpp"
#include "slidespec/estimator.hpp"

namespace {

constexpr double kDt = 0.1;  // [s]

std::vector<double> random_walk(std::size_t samples) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> step;
  std::vector<double> x(samples);
  double position = 0;
  for (double& value : x) value = position += step(rng);
  return x;
}

void BM_WelchSpectrum(benchmark::State& state) {
  const std::vector<double> x = random_walk(std::size_t(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(slidespec::welch_spectrum(x, kDt, {}));
  state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
  state.counters["segment_samples"] = double(slidespec::welch_segment_samples(x.size(), kDt, 0));
}

void BM_StreamingEstimator(benchmark::State& state) {
  const std::vector<double> x = random_walk(std::size_t(state.range(0)));
  slidespec::EstimatorConfig config;
  config.dt = kDt;
  config.input = slidespec::SampleKind::value;
  for (auto _ : state) {
    slidespec::SpectrumEstimator estimator(config, 1);
    estimator.push(x.data(), x.size());
    benchmark::DoNotOptimize(estimator.merged().spectrum(slidespec::PointValue::bin_average));
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
}

}  // namespace

BENCHMARK(BM_WelchSpectrum)->Arg(3900)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StreamingEstimator)->Arg(3900)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
