// The whole reference spectrum beside the plain cost of its randomness, in one benchmark
// run: `slidespec run --case reference` (0.1 .. 1e5 rad/s, 5% and 1% per point, with the
// shadow and without) on two threads against a plain loop drawing 4.19e7 renewals, on one core.
#include <benchmark/benchmark.h>
#include <cairo.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <random>
#include <string>

#include "cli/plot.hpp"
#include "figure/png.hpp"
#include "figure/spectrum_figure.hpp"
#include "process_time.hpp"
#include "slidespec/run.hpp"

namespace {

using namespace slidespec;
using bench::process_cpu_seconds;

/// The renewals a run of `result`'s plan draws, on average: x/a marks per miniblock
/// (the reference case is flat), x = v t, over the warm-up and the realization, twice
/// where the shadow runs.
double expected_renewals(const Parameters& p, const RunResult& result) {
  double renewals = 0;
  for (const SubBand& band : result.sub_bands)
    renewals += static_cast<double>(band.realizations) * p.N * p.renewal_rate() * (band.duration + band.warm_up) *
                (band.shadow ? 2 : 1);
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

// The yardstick of issues 29 and 40: the renewals the reference run at 5% drew before the
// warm-up and the shadow (x/a per miniblock over its realizations), a fixed count so that
// the ratio compares runs of any plan against the same plain work.
constexpr double kYardstickRenewals = 4.19e7;

// Args: threads of the run, its precision in per mille, the shadow control variate (1 on,
// 0 off). One iteration is one run then the plain loop, so both see the same load;
// `run_over_plain` is the ratio (wall time; goals: 5% <= 0.1, 1% <= 0.5).
// `renewals` counts the run's own draws (warm-ups and shadows included).
void ReferenceSpectrumVsPlainRenewals(benchmark::State& state) {
  const Parameters p = ParameterBuilder("reference").build();
  RunRequest request;
  request.threads = static_cast<int>(state.range(0));
  request.omega_min = 0.1;
  request.omega_max = 1e5;
  request.precision = static_cast<double>(state.range(1)) / 1000;
  request.control_variate = state.range(2) != 0;
  double run_wall = 0, run_cpu = 0, plain_wall = 0, plain_cpu = 0, renewals = 0;
  for (auto _ : state) {
    double cpu = process_cpu_seconds();
    const RunResult result = run_spectrum(p, request);
    run_cpu += process_cpu_seconds() - cpu;
    run_wall += result.wall_seconds;
    renewals = expected_renewals(p, result);
    cpu = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(draw_plain_renewals(static_cast<std::uint64_t>(kYardstickRenewals)));
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
    ->ArgsProduct({{2}, {50, 10}, {1, 0}})
    ->ArgNames({"threads", "permille", "shadow"})
    ->Iterations(3)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// The command a user types, with its figure and with --no-plot, alternated in one
// iteration so both see the same load: `figure_over_no_plot` is the ratio (wall
// time, goal <= 1.1). The executable runs as a child process; its outputs go to /tmp under
// this process's id (benchmarks of other checkouts may run beside it). The CPU seconds of
// the commands say what the figure costs when the cores are shared and wall times stretch.
// Ten alternations: the figure adds ~20 ms to a ~0.25 s run whose own wall time varies by
// more than that from one run to the next.
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
BENCHMARK(ReferenceRunWithFigureVsNoPlot)->Iterations(10)->Unit(benchmark::kSecond)->UseRealTime();

double milliseconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The figure of a reference run's table, part by part, in this process, as `run` draws it
// at its end (ms): the fine theory line, the page drawn (the PNG's encoding excluded), the
// PNG encoded; `first_figure_ms` is the first whole figure of the process, the exact
// theory's first use in it included (a run's figure follows the run's own use of it).
void ReferenceRunFigureParts(benchmark::State& state) {
  const std::string prefix = "/tmp/slidespec_bench_" + std::to_string(getpid()) + "_parts";
  if (std::system(
          (std::string(SLIDESPEC_EXECUTABLE) + " run --case reference --quiet --no-plot --out " + prefix).c_str()) !=
      0) {
    state.SkipWithError("the reference run failed");
    return;
  }
  const std::string table = prefix + ".tsv";
  auto start = std::chrono::steady_clock::now();
  const std::string first = cli::draw_run_figure(table, {});
  const double first_figure = milliseconds_since(start);
  cairo_surface_t* page = figure::read_png(first);
  double theory = 0, drawing = 0, encoding = 0;
  for (auto _ : state) {
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(cli::fine_theory_of_table(table));
    theory += milliseconds_since(start);
    const cli::RunFigure figure = cli::run_figure(table, {});
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(figure::draw(figure.figure, figure.page));
    const double whole = milliseconds_since(start);
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(figure::encode_png(cairo_image_surface_get_data(page), cairo_image_surface_get_width(page),
                                                cairo_image_surface_get_height(page),
                                                cairo_image_surface_get_stride(page), figure.page.dpi));
    const double png = milliseconds_since(start);
    encoding += png;
    drawing += whole - png;
  }
  cairo_surface_destroy(page);
  for (const char* suffix : {".tsv", ".json"}) std::remove((prefix + suffix).c_str());
  const double n = static_cast<double>(state.iterations());
  state.counters["first_figure_ms"] = first_figure;
  state.counters["theory_line_ms"] = theory / n;
  state.counters["page_ms"] = drawing / n;
  state.counters["png_ms"] = encoding / n;
  state.counters["png_kB"] = static_cast<double>(first.size()) / 1000;
}
BENCHMARK(ReferenceRunFigureParts)->Iterations(10)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
