// Driving through a spring against a constant force, in one benchmark run (docs/model.md
// §9): the reference case's spectrum run both ways, and the exact theory both ways.
// Iterations alternate the two so both see the same load; the ratios are CPU times.
#include <benchmark/benchmark.h>

#include <vector>

#include "process_time.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"

namespace {

using namespace slidespec;
using bench::process_cpu_seconds;

Parameters reference(bool spring) {
  ParameterBuilder builder("reference");
  if (spring) builder.set("drive=spring").set("k_drive=1e4");  // omega_s = 1 rad/s
  return builder.build();
}

// The reference case over 0.1 .. 1e4 rad/s with 64 realizations per sub-band on one
// thread, constant force then spring. `spring_over_force` is the time ratio (goal <= 1.1);
// `per_step_ratio` the same per realization-step (the spring's plan serves omega_s in
// the sub-band below it, so it takes a few more steps there).
void SpringRunVsConstantForce(benchmark::State& state) {
  RunRequest request;
  request.threads = 1;
  request.omega_min = 0.1;
  request.omega_max = 1e4;
  request.realizations = 64;
  const Parameters force = reference(false), spring = reference(true);
  double force_cpu = 0, spring_cpu = 0, force_steps = 0, spring_steps = 0;
  for (auto _ : state) {
    double start = process_cpu_seconds();
    const RunResult f = run_spectrum(force, request);
    force_cpu += process_cpu_seconds() - start;
    start = process_cpu_seconds();
    const RunResult s = run_spectrum(spring, request);
    spring_cpu += process_cpu_seconds() - start;
    force_steps = f.realization_steps;
    spring_steps = s.realization_steps;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["force_cpu_s"] = force_cpu / n;
  state.counters["spring_cpu_s"] = spring_cpu / n;
  state.counters["spring_over_force"] = spring_cpu / force_cpu;
  state.counters["steps_ratio"] = spring_steps / force_steps;
  state.counters["per_step_ratio"] = (spring_cpu / spring_steps) / (force_cpu / force_steps);
}
BENCHMARK(SpringRunVsConstantForce)->Iterations(3)->Unit(benchmark::kSecond)->UseRealTime();

// The exact theory at 9001 omegas over 1e-3 .. 1e6 rad/s, with and without the spring:
// the same full-structure solve with one more stiffness term (goal: the same cost order).
void TheoryWithAndWithoutSpring(benchmark::State& state) {
  const std::vector<double> omegas = log_spaced_omegas(1e-3, 1e6, 1000);
  const Parameters force = reference(false), spring = reference(true);
  double force_cpu = 0, spring_cpu = 0;
  for (auto _ : state) {
    double start = process_cpu_seconds();
    benchmark::DoNotOptimize(exact_spectrum(force, omegas));
    force_cpu += process_cpu_seconds() - start;
    start = process_cpu_seconds();
    benchmark::DoNotOptimize(exact_spectrum(spring, omegas));
    spring_cpu += process_cpu_seconds() - start;
  }
  state.counters["omegas"] = static_cast<double>(omegas.size());
  state.counters["force_us_per_omega"] = 1e6 * force_cpu / static_cast<double>(state.iterations() * omegas.size());
  state.counters["spring_us_per_omega"] = 1e6 * spring_cpu / static_cast<double>(state.iterations() * omegas.size());
  state.counters["spring_over_force"] = spring_cpu / force_cpu;
}
BENCHMARK(TheoryWithAndWithoutSpring)->Iterations(20)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
