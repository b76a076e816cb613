// The whole reference spectrum beside the plain cost of its randomness, in one benchmark
// run: `slidespec run --case reference` (0.1 .. 1e5 rad/s, 5% per point) on two threads
// against a plain loop that only draws as many renewals as that run needs, on one core.
#include <benchmark/benchmark.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <random>
#include <string>

#include "process_time.hpp"
#include "slidespec/run.hpp"

namespace {

using namespace slidespec;
using bench::process_cpu_seconds;

/// The renewals a run of `result`'s plan draws, on average: x/a marks per miniblock
/// (the reference case is flat), x = v t.
double expected_renewals(const Parameters& p, const RunResult& result) {
  double renewals = 0;
  for (const SubBand& band : result.sub_bands)
    renewals += static_cast<double>(band.realizations) * p.N * p.renewal_rate() * band.duration;
  return renewals;
}

/// The plain loop: each renewal is a new mark spacing (exponential) and a new force
/// (uniform), drawn with std::mt19937_64 the obvious way.
double draw_plain_renewals(std::uint64_t count) {
  std::mt19937_64 rng(1);
  std::exponential_distribution<double> spacing(1.0);
  std::uniform_real_distribution<double> force(-0.5, 0.5);
  double sum = 0;
  for (std::uint64_t i = 0; i < count; ++i) sum += spacing(rng) + force(rng);
  return sum;
}

// Args: threads of the run. One iteration is one run then the plain loop, so both see
// the same load; `run_over_plain` is the ratio (wall time, goal <= 0.5).
void ReferenceSpectrumVsPlainRenewals(benchmark::State& state) {
  const Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  request.threads = static_cast<int>(state.range(0));
  request.omega_min = 0.1;
  request.omega_max = 1e5;
  request.precision = 0.05;
  double run_wall = 0, run_cpu = 0, plain_wall = 0, plain_cpu = 0, renewals = 0;
  for (auto _ : state) {
    double cpu = process_cpu_seconds();
    const RunResult result = run_spectrum(p, request);
    run_cpu += process_cpu_seconds() - cpu;
    run_wall += result.wall_seconds;
    renewals = expected_renewals(p, result);
    cpu = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(draw_plain_renewals(static_cast<std::uint64_t>(renewals)));
    plain_wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    plain_cpu += process_cpu_seconds() - cpu;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["run_s"] = run_wall / n;
  state.counters["run_cpu_s"] = run_cpu / n;
  state.counters["plain_renewals_s"] = plain_wall / n;
  state.counters["renewals"] = renewals;
  state.counters["run_over_plain"] = run_wall / plain_wall;
  state.counters["run_cpu_over_plain_cpu"] = run_cpu / plain_cpu;
}
BENCHMARK(ReferenceSpectrumVsPlainRenewals)
    ->Arg(2)
    ->ArgName("threads")
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// The command a user types, with its figure and with --no-plot, alternated in one
// iteration so both see the same load: `figure_over_no_plot` is the ratio (wall
// time, goal <= 1.1). The executable runs as a child process; its outputs go to /tmp under
// this process's id (benchmarks of other checkouts may run beside it). The CPU seconds of
// the commands (the plotter's included) say what the figure costs when the cores are
// shared and wall times stretch.
struct CommandTime {
  double wall = 0, cpu = 0;
};

double children_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

CommandTime time_of(const std::string& command) {
  const double cpu = children_cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  if (std::system(command.c_str()) != 0) return {std::nan(""), std::nan("")};
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          children_cpu_seconds() - cpu};
}

void ReferenceRunWithFigureVsNoPlot(benchmark::State& state) {
  const std::string run = std::string(SLIDESPEC_EXECUTABLE) +
                          " run --case reference --quiet --out /tmp/slidespec_bench_" + std::to_string(getpid()) + "_";
  CommandTime with_figure, without;
  for (auto _ : state) {
    const CommandTime plain = time_of(run + "no_plot --no-plot");
    const CommandTime drawn = time_of(run + "figure");
    without.wall += plain.wall;
    without.cpu += plain.cpu;
    with_figure.wall += drawn.wall;
    with_figure.cpu += drawn.cpu;
  }
  for (const char* suffix : {"no_plot.tsv", "no_plot.json", "figure.tsv", "figure.json", "figure.png"})
    std::remove(("/tmp/slidespec_bench_" + std::to_string(getpid()) + "_" + suffix).c_str());
  const double n = static_cast<double>(state.iterations());
  state.counters["figure_s"] = with_figure.wall / n;
  state.counters["no_plot_s"] = without.wall / n;
  state.counters["figure_over_no_plot"] = with_figure.wall / without.wall;
  state.counters["figure_cpu_s"] = with_figure.cpu / n;
  state.counters["no_plot_cpu_s"] = without.cpu / n;
}
BENCHMARK(ReferenceRunWithFigureVsNoPlot)->Iterations(3)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
