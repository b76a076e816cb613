// slidespec command line: a thin layer over the core library.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"

namespace {

using namespace slidespec;

/// The options every model-facing command shares: a case, overrides, a parameter file.
struct ModelOptions {
  std::string case_name = "reference";
  std::vector<std::string> overrides;
  std::string parameter_file;

  void add_to(CLI::App& command) {
    command.add_option("--case", case_name, "named case (see 'slidespec cases')");
    command.add_option("--set", overrides, "override a parameter, KEY=VALUE (repeatable)");
    command.add_option("--params", parameter_file, "JSON file of parameter overrides");
  }

  Parameters build() const {
    ParameterBuilder builder(case_name);
    if (!parameter_file.empty())
      for (const auto& assignment : read_parameter_file(parameter_file)) builder.set(assignment);
    for (const auto& assignment : overrides) builder.set(assignment);
    return builder.build();
  }
};

void warn_if_outside_first_order(const Parameters& p) {
  const Landmarks l = landmarks(p);
  if (l.forces_can_stall)
    std::cerr << "slidespec: warning: alpha F_kin >= 2 (F_drive - F_kin): the random forces can "
                 "stall the block; the first-order theory does not hold here\n";
  else if (l.coupling_eps > 0.3)
    std::cerr << "slidespec: warning: eps = " << l.coupling_eps
              << " > 0.3: the first-order theory does not hold here\n";
}

int command_cases() {
  for (const Case& c : cases()) {
    const Parameters p = ParameterBuilder(c.name).build();
    std::cout << c.name << "\t" << c.description << "\n ";
    for (const auto& [key, value] : describe(p)) std::cout << " " << key << "=" << value;
    std::cout << "\n";
  }
  return 0;
}

struct TheoryOptions {
  double omega_min = 0.1, omega_max = 1e5;
  int points_per_decade = 8;
  std::string out;
};

int command_theory(const ModelOptions& model, const TheoryOptions& options) {
  const Parameters p = model.build();
  const std::vector<double> omegas =
      log_spaced_omegas(options.omega_min, options.omega_max, options.points_per_decade);
  if (!options.out.empty()) io::check_output_prefix(options.out);
  warn_if_outside_first_order(p);
  const std::vector<double> spectrum = exact_spectrum(p, omegas);

  std::ostringstream table;
  table << io::metadata_lines(p, model.case_name)
        << "# columns: omega [rad/s], C_x [m^2 s] exact first-order theory, "
           "C_eq1 [m^2 s] the paper's Eq. (1)\n"
        << "omega\tC_x\tC_eq1\n";
  for (size_t k = 0; k < omegas.size(); ++k)
    table << io::format_number(omegas[k]) << "\t" << io::format_number(spectrum[k]) << "\t"
          << io::format_number(eq1_asymptote(p, omegas[k])) << "\n";
  if (options.out.empty()) std::cout << table.str();
  else io::write_atomically(options.out + ".tsv", table.str());
  return 0;
}

std::atomic<bool> stop_requested{false};
std::atomic<int> stop_signal{0};
extern "C" void request_stop(int signal) {
  stop_signal = signal;
  stop_requested = true;
}

struct RunOptions {
  RunRequest request;
  std::string simd = "auto";
  std::string out = "spectrum";
  bool quiet = false;
  bool no_plot = false;
};

/// Runs one parameter set and writes PREFIX.tsv, .json (and .png); returns the result.
RunResult run_and_write(const Parameters& p, const std::string& case_name, const RunOptions& options,
                        const std::string& out) {
  cli::Progress progress(options.quiet);
  const RunResult result = run_spectrum(
      p, options.request, [&](double f, const std::string& what) { progress.update(f, what); },
      &stop_requested);
  progress.finish();
  io::write_atomically(out + ".tsv", io::run_table(p, case_name, options.request, result));
  io::write_atomically(out + ".json", io::run_json(p, case_name, options.request, result));
  const bool plotted = !options.no_plot && cli::plot({out + ".tsv"}, out + ".png", "") == 0;
  if (!options.no_plot && !plotted) std::cerr << "slidespec: warning: " << out << ".png not drawn\n";
  if (!options.quiet) {
    std::cerr << "slidespec: " << (result.complete ? "wrote " : "interrupted; wrote what accumulated to ")
              << out << ".tsv, .json" << (plotted ? ", .png" : "") << " (" << result.points.size()
              << " points, largest relative error " << io::format_number(result.reached_precision)
              << ", measured mean speed " << io::format_number(result.mean_speed) << " m/s, "
              << result.wall_seconds << " s)\n";
    if (result.complete && result.reached_precision > options.request.precision && options.request.duration == 0 &&
        options.request.realizations == 0)
      std::cerr << "slidespec: warning: the precision " << options.request.precision
                << " was not reached within the work budget of a sub-band; the table says what was\n";
  }
  return result;
}

void catch_stop_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

int command_run(const ModelOptions& model, RunOptions options) {
  const Parameters p = model.build();
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  plan_sub_bands(p, options.request);  // validates the band and precision before any work
  io::check_output_prefix(options.out);
  if (!options.quiet) warn_if_outside_first_order(p);
  catch_stop_signals();
  const RunResult result = run_and_write(p, model.case_name, options, options.out);
  if (!result.complete && stop_requested) return 128 + stop_signal;
  return 0;
}

struct PlotOptions {
  std::vector<std::string> tables;
  std::string out;
  std::string title;
};

int command_plot(const PlotOptions& options) {
  io::check_output_prefix(options.out);
  return cli::plot(options.tables, options.out, options.title);
}

/// The paper's figures: which cases each overlays.
const std::vector<std::pair<std::string, std::vector<std::string>>>& paper_figures() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> figures = {
      {"fig2", {"reference", "fast", "short-renewal", "many-contacts"}},
      {"fig3", {"reference", "medium-noise", "weak-noise"}},
      {"fig6", {"concrete-fit"}},
      {"hierarchy", {"reference", "hierarchical"}},  // MODEL.md section 6, docs/hierarchy.md
  };
  return figures;
}

int command_paper(const std::string& figure, RunOptions options, const std::string& directory) {
  const auto& figures = paper_figures();
  const auto found = std::find_if(figures.begin(), figures.end(), [&](const auto& f) { return f.first == figure; });
  if (found == figures.end()) throw InputError("paper: unknown figure '" + figure + "' (known: fig2, fig3, fig6, hierarchy)");
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  io::check_output_prefix(directory + "/" + figure);
  std::vector<Parameters> params;
  for (const std::string& name : found->second) {
    params.push_back(ParameterBuilder(name).build());
    plan_sub_bands(params.back(), options.request);
  }
  catch_stop_signals();
  std::vector<std::string> tables;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const std::string out = directory + "/" + figure + "_" + found->second[k];
    RunOptions single = options;
    single.no_plot = true;
    const RunResult result = run_and_write(params[k], found->second[k], single, out);
    tables.push_back(out + ".tsv");
    if (!result.complete && stop_requested) return 128 + stop_signal;
  }
  const std::string title = figure == "fig6"        ? "concrete-fit model (alpha = 0.4), Fig. 6 of the paper"
                            : figure == "hierarchy" ? "flat and two-level contacts (the paper's Fig. 1c)"
                                                    : "the paper's " + figure.substr(0, 3) + ". " + figure.substr(3);
  const int status = cli::plot(tables, directory + "/" + figure + ".png", title);
  if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << directory << "/" << figure << ".png\n";
  return status == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slidespec: power spectra of frictional sliding noise (Xu, Zhou, Persson model)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SLIDESPEC_VERSION);

  CLI::App* cases_command = app.add_subcommand("cases", "list the named cases and their parameters");

  ModelOptions theory_model;
  TheoryOptions theory_options;
  CLI::App* theory_command =
      app.add_subcommand("theory", "exact first-order spectrum C_x(omega) (docs/model.md)");
  theory_model.add_to(*theory_command);
  theory_command->add_option("--omega-min", theory_options.omega_min, "lowest omega [rad/s]");
  theory_command->add_option("--omega-max", theory_options.omega_max, "highest omega [rad/s]");
  theory_command->add_option("--points", theory_options.points_per_decade, "points per decade");
  theory_command->add_option("--out", theory_options.out, "write PREFIX.tsv instead of stdout");

  ModelOptions run_model;
  RunOptions run_options;
  CLI::App* run_command = app.add_subcommand("run", "simulated spectrum with error bars, beside the theory");
  run_model.add_to(*run_command);
  RunRequest& request = run_options.request;
  run_command->add_option("--omega-min", request.omega_min, "lowest omega [rad/s] (default 0.1)");
  run_command->add_option("--omega-max", request.omega_max, "highest omega [rad/s] (default 1e5)");
  run_command->add_option("--points", request.points_per_decade, "points per decade (default 8)");
  auto* precision = run_command->add_option(
      "--precision", request.precision, "target relative standard error at every point (default 0.05)");
  auto* duration = run_command->add_option(
      "--duration", request.duration, "simulated seconds per realization of the lowest sub-band");
  duration->excludes(precision);
  run_command->add_option("--realizations", request.realizations, "realizations per sub-band");
  run_command->add_option("--seed", request.seed, "random seed (default 1)");
  run_command->add_option("--threads", request.threads, "threads (default: all cores)");
  run_command->add_option("--simd", run_options.simd, "scalar|sse2|avx2|avx512|auto (default auto)");
  run_command->add_option("--out", run_options.out, "output prefix: PREFIX.tsv, .json, .png (default spectrum)");
  run_command->add_flag("--quiet", run_options.quiet, "no progress, no summary");
  run_command->add_flag("--no-plot", run_options.no_plot, "skip PREFIX.png");

  PlotOptions plot_options;
  CLI::App* plot_command = app.add_subcommand("plot", "overlay spectrum tables in one picture");
  plot_command->add_option("tables", plot_options.tables, "TSV files from run or theory")->required();
  plot_command->add_option("-o,--out", plot_options.out, "the PNG to write")->required();
  plot_command->add_option("--title", plot_options.title, "title of the picture");

  std::string figure, paper_directory = ".";
  RunOptions paper_options;
  CLI::App* paper_command = app.add_subcommand("paper", "run the paper's cases and draw its figure");
  paper_command->add_option("figure", figure, "fig2 | fig3 | fig6 | hierarchy")->required();
  paper_command->add_option("--out-dir", paper_directory, "directory for the tables and the figure");
  paper_command->add_option("--precision", paper_options.request.precision, "target relative standard error");
  paper_command->add_option("--omega-min", paper_options.request.omega_min, "lowest omega [rad/s]");
  paper_command->add_option("--omega-max", paper_options.request.omega_max, "highest omega [rad/s]");
  paper_command->add_option("--seed", paper_options.request.seed, "random seed");
  paper_command->add_option("--threads", paper_options.request.threads, "threads (default: all cores)");
  paper_command->add_option("--simd", paper_options.simd, "scalar|sse2|avx2|avx512|auto");
  paper_command->add_flag("--quiet", paper_options.quiet, "no progress, no summary");

  try {
    app.parse(argc, argv);
    if (*cases_command) return command_cases();
    if (*theory_command) return command_theory(theory_model, theory_options);
    if (*run_command) return command_run(run_model, run_options);
    if (*plot_command) return command_plot(plot_options);
    if (*paper_command) return command_paper(figure, paper_options, paper_directory);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "slidespec: failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
