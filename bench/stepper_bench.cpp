// Stepper throughput in miniblock-steps and realization-steps per second, for every SIMD
// path this CPU has, beside the plain baseline (bench/plain_model.hpp) in the same binary.
//
// The lumped stepper's cost per realization-step does not depend on N (the exact lumped
// state has 3 components for any N), so its miniblock-steps/s grows in proportion to N;
// realization_steps_per_s is the number that measures the kernel. See bench/README.md.
#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <mutex>
#include <utility>

#include "plain_model.hpp"
#include "process_time.hpp"
#include "slidespec/stepper.hpp"

using namespace slidespec;
using slidespec::bench::PlainModel;
using slidespec::bench::process_cpu_seconds;

namespace {

constexpr double kStepDt = 1e-5;  // [s]; every path and the baseline step the same dt

Parameters bench_parameters(long N, bool periodic) {
  return ParameterBuilder().set("N", std::to_string(N)).set("renewal", periodic ? "periodic" : "poisson").build();
}

void set_rates(benchmark::State& state, double realization_steps, int N) {
  state.counters["miniblock_steps_per_s"] =
      benchmark::Counter(realization_steps * N, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["realization_steps_per_s"] =
      benchmark::Counter(realization_steps, benchmark::Counter::kIsIterationInvariantRate);
}

// Args: N, periodic. One realization on one core: the reference every speed-up is against.
void PlainBaseline(benchmark::State& state) {
  const Parameters p = bench_parameters(state.range(0), state.range(1) != 0);
  PlainModel plain(p, kStepDt, 1);
  const std::int64_t steps = 2000000 / p.N;
  for (auto _ : state) benchmark::DoNotOptimize(plain.advance(steps));
  set_rates(state, double(steps), p.N);
  state.SetLabel(state.range(1) ? "plain periodic" : "plain poisson");
}

/// Miniblock-steps per second of the plain baseline on one core, measured once per shape
/// (about 0.3 s) so that every stepper row can print its speed-up over it.
double plain_rate(long N, bool periodic) {
  static std::mutex guard;
  static std::map<std::pair<long, bool>, double> rates;
  std::lock_guard<std::mutex> lock(guard);
  auto found = rates.find({N, periodic});
  if (found != rates.end()) return found->second;
  PlainModel plain(bench_parameters(N, periodic), kStepDt, 1);
  const std::int64_t steps = 2000000 / N;
  plain.advance(steps);  // warm-up
  double work = 0;
  const auto start = std::chrono::steady_clock::now();
  std::chrono::duration<double> elapsed{};
  while (elapsed.count() < 0.3) {
    benchmark::DoNotOptimize(plain.advance(steps));
    work += double(steps) * double(N);
    elapsed = std::chrono::steady_clock::now() - start;
  }
  return rates[{N, periodic}] = work / elapsed.count();
}

/// Runs 64 realizations per thread for `steps` steps of `dt` per iteration, with the shape
/// of state's args (N, path index into available_simd_paths(), threads, periodic); sets
/// the rate counters and returns the wall time per miniblock-step, or 0 if skipped.
double step_realizations(benchmark::State& state, double dt, std::int64_t steps) {
  const auto paths = available_simd_paths();
  const auto path_index = static_cast<size_t>(state.range(1));
  if (path_index >= paths.size()) {
    state.SkipWithError("path not available on this CPU");
    return 0;
  }
  const int threads = static_cast<int>(state.range(2));
  const bool periodic = state.range(3) != 0;
  const Parameters p = bench_parameters(state.range(0), periodic);
  StepperConfig config;
  config.dt = dt;
  config.simd = paths[path_index];
  const int per_thread = 64;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  for (auto _ : state)
    run_batches(p, config, 0, static_cast<std::uint64_t>(per_thread * threads), steps, threads, per_thread, {}, {});
  const double cpu = process_cpu_seconds() - cpu_start;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  const double realization_steps = double(per_thread) * threads * double(steps);
  set_rates(state, realization_steps, p.N);
  state.counters["realization_steps_per_cpu_s"] = realization_steps * double(state.iterations()) / cpu;
  state.SetLabel(std::string(to_string(config.simd)) + (periodic ? " periodic" : " poisson"));
  return elapsed.count() / (realization_steps * p.N * double(state.iterations()));
}

// At dt = 1e-5 s a miniblock renews every ~2e5 steps: this is the kernel's own speed.
// Steps grow with N so that setting up the batch (N draws per realization) stays a few
// per cent of the time at every N.
void StepperThroughput(benchmark::State& state) {
  const double seconds_per_miniblock_step = step_realizations(state, kStepDt, 20000 * state.range(0) / 30);
  if (seconds_per_miniblock_step > 0)
    state.counters["speedup_vs_plain"] =
        1.0 / seconds_per_miniblock_step / plain_rate(state.range(0), state.range(3) != 0);
}

// At dt = 0.2 s, the time step of a run's lowest sub-band (lambda dt = 0.1), every
// miniblock renews every 10 steps: the renewal path (Philox, log1p, the tournament tree)
// is the cost. The plain baseline cannot take this step (its explicit springs blow up).
void StepperRenewalBound(benchmark::State& state) { step_realizations(state, 0.2, 600000 / state.range(0)); }

void AllShapes(benchmark::internal::Benchmark* b) {
  for (long periodic : {0, 1})
    for (long n : {30, 100, 1000})
      for (long path = 0; path < 4; ++path)
        for (long threads : {1, 2}) b->Args({n, path, threads, periodic});
}

}  // namespace

BENCHMARK(PlainBaseline)
    ->ArgsProduct({{30, 100, 1000}, {0, 1}})
    ->ArgNames({"N", "periodic"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(StepperThroughput)
    ->Apply(AllShapes)
    ->ArgNames({"N", "path", "threads", "periodic"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(StepperRenewalBound)
    ->ArgsProduct({{30, 1000}, {0, 3}, {1}, {0, 1}})
    ->ArgNames({"N", "path", "threads", "periodic"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
