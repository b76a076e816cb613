// Stepper throughput in miniblock-steps per second (N x realizations x steps / s), for
// every SIMD path this CPU has, beside the scalar path of the same kernel.
#include <benchmark/benchmark.h>

#include "slidespec/stepper.hpp"

using namespace slidespec;

namespace {

// Args: N, path index into available_simd_paths(), threads, renewal (0 poisson, 1 periodic).
void StepperThroughput(benchmark::State& state) {
  const auto paths = available_simd_paths();
  const auto path_index = static_cast<size_t>(state.range(1));
  if (path_index >= paths.size()) {
    state.SkipWithError("path not available on this CPU");
    return;
  }
  const int threads = static_cast<int>(state.range(2));
  const Parameters p = ParameterBuilder()
                           .set("N", std::to_string(state.range(0)))
                           .set("renewal", state.range(3) ? "periodic" : "poisson")
                           .build();
  StepperConfig config;
  config.dt = 1e-5;
  config.simd = paths[path_index];
  const int per_thread = 64;
  const std::int64_t steps = 20000;
  for (auto _ : state)
    run_batches(p, config, 0, static_cast<std::uint64_t>(per_thread * threads), steps, threads,
                per_thread, {}, {});
  const double miniblock_steps = double(p.N) * per_thread * threads * double(steps);
  state.counters["miniblock_steps_per_s"] =
      benchmark::Counter(miniblock_steps, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["realization_steps_per_s"] = benchmark::Counter(
      double(per_thread) * threads * double(steps), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(std::string(to_string(config.simd)) + (state.range(3) ? " periodic" : " poisson"));
}

void AllShapes(benchmark::internal::Benchmark* b) {
  for (long n : {30, 100, 1000})
    for (long path = 0; path < 4; ++path)
      for (long threads : {1, 2}) b->Args({n, path, threads, 0});
  for (long path = 0; path < 4; ++path) b->Args({30, path, 2, 1});
}

}  // namespace

BENCHMARK(StepperThroughput)->Apply(AllShapes)->ArgNames({"N", "path", "threads", "periodic"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
