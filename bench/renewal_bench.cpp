// Renewals per CPU second: the stepper in its renewal-bound regime against the plain loop
// that merely draws them (std::mt19937_64, an exponential spacing and a uniform force per
// renewal, one core), side by side in one binary. See bench/README.md.
#include <benchmark/benchmark.h>

#include <random>

#include "process_time.hpp"
#include "slidespec/stepper.hpp"

using namespace slidespec;
using slidespec::bench::process_cpu_seconds;

namespace {

// Draws renewals the obvious way and nothing else: the floor any engine is compared with.
void PlainRenewalDraws(benchmark::State& state) {
  std::mt19937_64 engine(1);
  std::exponential_distribution<double> spacing(1.0 / 1e-3);
  std::uniform_real_distribution<double> force(-0.5, 0.5);
  const std::int64_t renewals = 1 << 20;
  const double cpu_start = process_cpu_seconds();
  double sum = 0;
  for (auto _ : state) {
    for (std::int64_t r = 0; r < renewals; ++r) sum += spacing(engine) + force(engine);
    benchmark::DoNotOptimize(sum);
  }
  const double cpu = process_cpu_seconds() - cpu_start;
  state.counters["renewals_per_cpu_s"] = double(renewals) * double(state.iterations()) / cpu;
}

// The whole stepper (renewals applied at their own time inside each step) at the time step of a
// run's lowest sub-band, dt = 0.2 s (lambda dt = 0.1): every miniblock renews every 10 steps,
// so the time is the renewal path's. Args: N, path index, periodic.
void StepperRenewals(benchmark::State& state) {
  const auto paths = available_simd_paths();
  const auto path_index = static_cast<size_t>(state.range(1));
  if (path_index >= paths.size()) {
    state.SkipWithError("path not available on this CPU");
    return;
  }
  const Parameters p = ParameterBuilder()
                           .set("N", std::to_string(state.range(0)))
                           .set("renewal", state.range(2) ? "periodic" : "poisson")
                           .build();
  StepperConfig config;
  config.dt = 0.2;
  config.simd = paths[path_index];
  const std::int64_t steps = 300000 / state.range(0);
  double renewals = 0, lane_passes = 0;
  const double cpu_start = process_cpu_seconds();
  for (auto _ : state)
    run_batches(p, config, 0, 64, steps, 1, 64, {}, [&](std::size_t, std::vector<RealizationSummary> s) {
      for (const RealizationSummary& r : s) renewals += double(r.renewals), lane_passes += double(r.renewal_passes);
    });
  const double cpu = process_cpu_seconds() - cpu_start;
  state.counters["renewals_per_cpu_s"] = renewals / cpu;
  state.counters["lane_utilization"] = renewals / lane_passes;
  state.SetLabel(std::string(to_string(config.simd)) + (state.range(2) ? " periodic" : " poisson"));
}

// Cost per renewal as the number of contacts grows, the rest of the reference case
// unchanged: a run's batches (8 realizations, 64 in all, one thread, the widest path), the
// time step scaled as 1/N so that a lane renews 3 forces per step at every N (as the
// reference run's lowest sub-band at N = 30), and 20 renewals per contact, so each
// realization's start (N forces drawn) weighs the same at every N. Arg: N.
void RenewalsAcrossContacts(benchmark::State& state) {
  const auto contacts = state.range(0);
  const Parameters p = ParameterBuilder().set("N", std::to_string(contacts)).build();
  constexpr double kRenewalsPerLaneStep = 3, kRenewalsPerContact = 20;
  const double rate = p.v / p.a;  // renewals per contact per second
  StepperConfig config;
  config.dt = kRenewalsPerLaneStep / (static_cast<double>(contacts) * rate);
  const auto steps =
      static_cast<std::int64_t>(kRenewalsPerContact * static_cast<double>(contacts) / kRenewalsPerLaneStep);
  double renewals = 0, lane_passes = 0;
  const double cpu_start = process_cpu_seconds();
  for (auto _ : state)
    run_batches(p, config, 0, 64, steps, 1, 8, {}, [&](std::size_t, std::vector<RealizationSummary> s) {
      for (const RealizationSummary& r : s) renewals += double(r.renewals), lane_passes += double(r.renewal_passes);
    });
  const double cpu = process_cpu_seconds() - cpu_start;
  state.counters["renewals_per_cpu_s"] = renewals / cpu;
  state.counters["ns_per_renewal"] = 1e9 * cpu / renewals;
  state.counters["lane_utilization"] = renewals / lane_passes;
  state.SetLabel(to_string(resolve_simd_path(config.simd)));
}

}  // namespace

BENCHMARK(PlainRenewalDraws)->Unit(benchmark::kMillisecond);
BENCHMARK(StepperRenewals)
    ->ArgsProduct({{30, 1000}, {0, 3}, {0, 1}})
    ->ArgNames({"N", "path", "periodic"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(RenewalsAcrossContacts)
    ->Arg(30)
    ->Arg(300)
    ->Arg(3000)
    ->Arg(30000)
    ->ArgName("N")
    ->Unit(benchmark::kMillisecond);
