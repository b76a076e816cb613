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
#include <new>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/analyze.hpp"
#include "cli/outputs.hpp"
#ifdef SLIDESPEC_MPI
#include "cli/mpi.hpp"
#endif
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
  int order = 1;
  std::string out;
};

// The exact mean speed and low-frequency diffusion beyond first order, where computed
// (below the stall boundary, one touching level).
std::string long_time_line(const Parameters& p) {
  if (landmarks(p).forces_can_stall) return "";
  int touching_levels = 0;
  for (int l = 1; l <= p.levels; ++l) touching_levels += p.touches(l) ? 1 : 0;
  if (touching_levels != 1) return "";
  const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
  const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
  return "# beyond first order (docs/model.md section 7): mean speed V = " + io::format_number(exact.mean_speed) +
         " m/s, diffusion D = " + io::format_number(exact.diffusion) + " m^2/s (first order " +
         io::format_number(first.diffusion) + "), C_x -> D / (pi omega^2) below v/a\n";
}

int command_theory(const ModelOptions& model, const TheoryOptions& options) {
  const Parameters p = model.build();
  const std::vector<double> omegas =
      log_spaced_omegas(options.omega_min, options.omega_max, options.points_per_decade);
  if (options.order != 1 && options.order != 2) throw InputError("order: need 1 or 2");
  // Built before any work so that a model it does not cover is refused at once.
  const std::unique_ptr<SecondOrderTheory> second =
      options.order == 2 ? std::make_unique<SecondOrderTheory>(p) : nullptr;
  if (!options.out.empty()) io::check_output_prefix(options.out);
  warn_if_outside_first_order(p);
  const std::vector<double> spectrum = exact_spectrum(p, omegas);

  std::ostringstream table;
  table << io::metadata_lines(p, model.case_name) << long_time_line(p)
        << "# columns: omega [rad/s], C_x [m^2 s] exact first-order theory, "
           "C_eq1 [m^2 s] the paper's Eq. (1)"
        << (second ? ", C_x2 [m^2 s] second-order theory (docs/model.md section 7)" : "") << "\n"
        << "omega\tC_x\tC_eq1" << (second ? "\tC_x2" : "") << "\n";
  for (size_t k = 0; k < omegas.size(); ++k) {
    table << io::format_number(omegas[k]) << "\t" << io::format_number(spectrum[k]) << "\t"
          << io::format_number(eq1_asymptote(p, omegas[k]));
    if (second) table << "\t" << io::format_number(spectrum[k] * second->ratio(omegas[k]));
    table << "\n";
  }
  if (options.out.empty()) std::cout << table.str();
  else io::write_atomically(options.out + ".tsv", table.str());
  return 0;
}

/// Exit status of a run that finished but is not one stationary process (README).
constexpr int kNotStationary = 3;

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
  double checkpoint_every = 0;  // [s]; 0 = no periodic checkpoints
  std::string resume;           // PREFIX of a run to continue from PREFIX.state
  std::string range;            // FIRST:COUNT of a part of a run
  std::string save_state;       // where to save the finished part
};

/// This process's place among the run's processes (MPI ranks; one without MPI).
const Communicator* communicator = nullptr;
bool writes_outputs() { return communicator == nullptr || communicator->rank() == 0; }

/// Writes PREFIX.tsv, .json (and .png) for a session's result and says what it wrote.
void write_outputs(const RunSession& session, const RunResult& result, const RunOptions& options,
                   const std::string& out) {
  if (!writes_outputs()) return;
  const Parameters& p = session.parameters();
  io::OutputSet outputs;  // the table, the JSON and the picture appear together or not at all
  outputs.add(out + ".tsv", io::run_table(p, session.case_name(), session.request(), result));
  outputs.add(out + ".json", io::run_json(p, session.case_name(), session.request(), result));
  const bool plotted = !options.no_plot && cli::plot({outputs.temporary(out + ".tsv")},
                                                     outputs.add_written_by_other(out + ".png", ".png"), "") == 0;
  if (!plotted) outputs.drop(out + ".png");
  outputs.commit();
  if (!options.no_plot && !plotted) std::cerr << "slidespec: warning: " << out << ".png not drawn\n";
  if (options.quiet) return;
  std::cerr << "slidespec: " << (result.complete ? "wrote " : "interrupted; wrote what accumulated to ")
            << out << ".tsv, .json" << (plotted ? ", .png" : "") << " (" << result.points.size()
            << " points, largest relative error " << io::format_number(result.reached_precision)
            << ", measured mean speed " << io::format_number(result.mean_speed) << " m/s, "
            << result.wall_seconds << " s)\n";
  const RunRequest& request = session.request();
  if (result.complete && result.reached_precision > request.precision && request.duration == 0 &&
      request.realizations == 0)
    std::cerr << "slidespec: warning: the precision " << request.precision
              << " was not reached within the work budget of a sub-band; the table says what was\n";
}

/// Advances a session to its end (or an interrupt), checkpointing to PREFIX.state, and
/// writes its outputs. An interrupted run leaves PREFIX.state for --resume; a finished
/// one removes the checkpoint it no longer needs.
RunResult run_and_write(RunSession& session, const RunOptions& options, const std::string& out) {
  const std::string state_path = out + ".state";
  cli::Progress progress(options.quiet || !writes_outputs());
  RunSession::Control control;
  control.progress = [&](double f, const std::string& what) { progress.update(f, what); };
  control.stop = &stop_requested;
  control.communicator = communicator;
  control.checkpoint_every = options.checkpoint_every;
  control.checkpoint = [&](const RunSession& s) {
    if (writes_outputs()) io::write_atomically(state_path, s.save());
  };
  const bool finished = session.advance(control);
  progress.finish();
  if (writes_outputs()) {
    if (!finished) {
      io::write_atomically(state_path, session.save());
      if (!options.quiet)
        std::cerr << "slidespec: saved the run to " << state_path << "; continue it with: slidespec run --resume "
                  << out << "\n";
    } else if (session.request().realizations > 0 && !options.resume.empty()) {
      // A resumed part of a run (--realizations-range): its state file is what merge
      // reads, so it is left finished rather than removed.
      io::write_atomically(state_path, session.save());
    } else if (options.checkpoint_every > 0 || !options.resume.empty()) {
      std::remove(state_path.c_str());
    }
    if (!options.save_state.empty()) io::write_atomically(options.save_state, session.save());
  }
  const RunResult result = session.result();
  write_outputs(session, result, options, out);
  if (!result.stationary && writes_outputs())
    std::cerr << "slidespec: warning: " << out << ": not stationary (" << result.stationarity
              << "): no spectrum exists here; the table is marked stationary = false (exit status 3)\n";
  return result;
}

/// One parameter set from the start.
RunResult run_and_write(const Parameters& p, const std::string& case_name, const RunOptions& options,
                        const std::string& out) {
  RunSession session(p, options.request, case_name);
  return run_and_write(session, options, out);
}

void catch_stop_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

/// FIRST:COUNT of --realizations-range.
void apply_realization_range(const std::string& range, RunRequest& request) {
  const auto colon = range.find(':');
  std::size_t used_first = 0, used_count = 0;
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    request.first_realization = std::stoull(range.substr(0, colon), &used_first);
    request.realizations = std::stoull(range.substr(colon + 1), &used_count);
  } catch (const std::exception&) {
    used_first = 0;
  }
  if (colon == std::string::npos || used_first != colon || used_count != range.size() - colon - 1 ||
      range[0] == '-' || range[colon + 1] == '-' || request.realizations == 0)
    throw InputError("--realizations-range: expected FIRST:COUNT (whole numbers, COUNT > 0), got '" + range + "'");
}

int command_run(const ModelOptions& model, RunOptions options, const std::function<bool(const char*)>& given) {
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  if (!options.range.empty()) apply_realization_range(options.range, options.request);
  if (!options.resume.empty()) {
    // Continue a saved run: its parameters and request are in the state; options given
    // here must describe the same run (threads and SIMD path may change).
    RunSession session = RunSession::load(io::read_file(options.resume + ".state", "--resume"));
    const bool model_given = given("--case") || given("--set") || given("--params");
    RunRequest request = session.request();
    if (given("--omega-min")) request.omega_min = options.request.omega_min;
    if (given("--omega-max")) request.omega_max = options.request.omega_max;
    if (given("--points")) request.points_per_decade = options.request.points_per_decade;
    if (given("--precision")) request.precision = options.request.precision;
    if (given("--duration")) request.duration = options.request.duration;
    if (given("--realizations") || given("--realizations-range")) {
      request.realizations = options.request.realizations;
      request.first_realization = options.request.first_realization;
    }
    if (given("--seed")) request.seed = options.request.seed;
    const std::string differs =
        session.difference(model_given ? model.build() : session.parameters(), request);
    if (!differs.empty())
      throw InputError("--resume: " + options.resume + ".state is another run (" + differs + ")");
    session.set_execution(options.request.threads, options.request.simd);
    if (options.out == "spectrum") options.out = options.resume;
    io::check_output_prefix(options.out);
    catch_stop_signals();
    const RunResult result = run_and_write(session, options, options.out);
    if (!result.complete && stop_requested) return 128 + stop_signal;
    return result.stationary ? 0 : kNotStationary;
  }
  const Parameters p = model.build();
  RunSession session(p, options.request, model.case_name);  // validates before any work
  io::check_output_prefix(options.out);
  if (!options.save_state.empty()) io::check_output_prefix(options.save_state);
  if (!options.quiet && writes_outputs()) warn_if_outside_first_order(p);
  catch_stop_signals();
  const RunResult result = run_and_write(session, options, options.out);
  if (!result.complete && stop_requested) return 128 + stop_signal;
  return result.stationary ? 0 : kNotStationary;
}

/// Parts of a run split over a job array, as the whole run.
int command_merge(const std::vector<std::string>& paths, RunOptions options) {
  std::vector<RunSession> parts;
  for (const std::string& path : paths) {
    try {
      parts.push_back(RunSession::load(io::read_file(path, "merge")));
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
  }
  io::check_output_prefix(options.out);
  RunSession whole = RunSession::merge(std::move(parts));
  const RunResult result = whole.result();
  write_outputs(whole, result, options, options.out);
  return result.stationary ? 0 : kNotStationary;
}

/// A list of values of one parameter, one run each (all cores, or all ranks, each), and
/// an overlay of their spectra. Every value is validated before the first run starts.
int command_sweep(const ModelOptions& model, const std::string& sweep, RunOptions options) {
  const auto equals = sweep.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == sweep.size())
    throw InputError("sweep: expected KEY=V1,V2,..., got '" + sweep + "'");
  const std::string key = sweep.substr(0, equals);
  std::vector<std::string> values;
  std::stringstream list(sweep.substr(equals + 1));
  for (std::string value; std::getline(list, value, ',');) {
    if (value.empty()) throw InputError("sweep: an empty value in '" + sweep + "'");
    values.push_back(value);
  }
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  std::vector<Parameters> params;
  for (const std::string& value : values) {
    ModelOptions one = model;
    one.overrides.push_back(key + "=" + value);
    params.push_back(one.build());
    RunSession check(params.back(), options.request);  // validates the band for this value
  }
  io::check_output_prefix(options.out);
  catch_stop_signals();
  std::vector<std::string> tables;
  bool stationary = true;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!options.quiet && writes_outputs())
      std::cerr << "slidespec: sweep " << k + 1 << "/" << values.size() << ": " << key << " = " << values[k] << "\n";
    const std::string out = options.out + "_" + key + "=" + values[k];
    RunOptions single = options;
    single.no_plot = true;
    const RunResult result = run_and_write(params[k], model.case_name, single, out);
    tables.push_back(out + ".tsv");
    stationary = stationary && result.stationary;
    if (!result.complete && stop_requested) return 128 + stop_signal;
  }
  const int done = stationary ? 0 : kNotStationary;
  if (options.no_plot || !writes_outputs()) return done;
  const int status = cli::plot(tables, options.out + ".png", model.case_name + ": sweep of " + key);
  if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << options.out << ".png\n";
  return status == 0 ? done : 1;
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
    validate_request(params.back(), options.request);
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
  if (!writes_outputs()) return 0;
  const int status = cli::plot(tables, directory + "/" + figure + ".png", title);
  if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << directory << "/" << figure << ".png\n";
  return status == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef SLIDESPEC_MPI
  cli::MpiWorld mpi(argc, argv);
  if (mpi.size() > 1) communicator = &mpi;
  // Ranks on one machine share its cores.
  const int default_threads =
      std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / mpi.ranks_on_this_node());
#else
  const int default_threads = 0;
#endif
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
  theory_command->add_option("--order", theory_options.order,
                             "2: add C_x2, the second-order theory (poisson renewal, one touching level)");
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
  auto* realizations =
      run_command->add_option("--realizations", request.realizations, "realizations per sub-band");
  auto* range = run_command->add_option("--realizations-range", run_options.range,
                                        "FIRST:COUNT: run only these realizations (a part of a run; see merge)");
  range->excludes(realizations)->excludes(precision);
  run_command->add_option("--seed", request.seed, "random seed (default 1)");
  run_command->add_option("--threads", request.threads, "threads (default: all cores)");
  run_command->add_option("--work-budget", request.work_budget, "most realization-steps the run may plan (default 1e11)");
  run_command->add_option("--simd", run_options.simd, "scalar|sse2|avx2|avx512|auto (default auto)");
  run_command->add_option("--out", run_options.out, "output prefix: PREFIX.tsv, .json, .png (default spectrum)");
  run_command->add_option("--checkpoint-every", run_options.checkpoint_every,
                          "save the run to PREFIX.state every S seconds of wall time")
      ->check(CLI::PositiveNumber);
  run_command->add_option("--resume", run_options.resume, "continue the run saved in PREFIX.state");
  run_command->add_option("--save-state", run_options.save_state, "save the finished run (a part) to FILE");
  run_command->add_flag("--quiet", run_options.quiet, "no progress, no summary");
  run_command->add_flag("--no-plot", run_options.no_plot, "skip PREFIX.png");
  // A resumed run checks what was given against what it saved.
  auto run_given = [&](const char* name) { return run_command->count(name) > 0; };

  ModelOptions sweep_model;
  RunOptions sweep_options;
  std::string sweep_values;
  CLI::App* sweep_command =
      app.add_subcommand("sweep", "one run per value of a parameter, and their spectra in one picture");
  sweep_command->add_option("values", sweep_values, "KEY=V1,V2,... (e.g. alpha=0.1,0.5,1)")->required();
  sweep_model.add_to(*sweep_command);
  sweep_command->add_option("--omega-min", sweep_options.request.omega_min, "lowest omega [rad/s]");
  sweep_command->add_option("--omega-max", sweep_options.request.omega_max, "highest omega [rad/s]");
  sweep_command->add_option("--points", sweep_options.request.points_per_decade, "points per decade");
  sweep_command->add_option("--precision", sweep_options.request.precision, "target relative standard error");
  sweep_command->add_option("--realizations", sweep_options.request.realizations, "realizations per sub-band");
  sweep_command->add_option("--seed", sweep_options.request.seed, "random seed");
  sweep_command->add_option("--threads", sweep_options.request.threads, "threads (default: all cores)");
  sweep_command->add_option("--work-budget", sweep_options.request.work_budget, "most realization-steps a run may plan");
  sweep_command->add_option("--simd", sweep_options.simd, "scalar|sse2|avx2|avx512|auto");
  sweep_command->add_option("--out", sweep_options.out, "output prefix: PREFIX_KEY=V.tsv ..., PREFIX.png");
  sweep_command->add_flag("--quiet", sweep_options.quiet, "no progress, no summary");
  sweep_command->add_flag("--no-plot", sweep_options.no_plot, "skip PREFIX.png");

  std::vector<std::string> merge_parts;
  RunOptions merge_options;
  CLI::App* merge_command =
      app.add_subcommand("merge", "join the parts of a run (--realizations-range, --save-state) into its outputs");
  merge_command->add_option("parts", merge_parts, "state files of the parts")->required();
  merge_command->add_option("--out", merge_options.out, "output prefix (default spectrum)");
  merge_command->add_flag("--quiet", merge_options.quiet, "no summary");
  merge_command->add_flag("--no-plot", merge_options.no_plot, "skip PREFIX.png");

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
  paper_command->add_option("--work-budget", paper_options.request.work_budget, "most realization-steps a run may plan");
  paper_command->add_option("--simd", paper_options.simd, "scalar|sse2|avx2|avx512|auto");
  paper_command->add_flag("--quiet", paper_options.quiet, "no progress, no summary");

  const cli::AnalysisCommands analysis_commands(app);
  cli::require_whole_numbers(app);

  try {
    app.parse(argc, argv);
    cli::check_files(app);
    for (RunOptions* options : {&run_options, &paper_options, &sweep_options})
      if (options->request.threads == 0) options->request.threads = default_threads;
    if (const auto status = analysis_commands.run()) return *status;
    if (*cases_command) return command_cases();
    if (*theory_command) return command_theory(theory_model, theory_options);
    if (*run_command) return command_run(run_model, run_options, run_given);
    if (*merge_command) return command_merge(merge_parts, merge_options);
    if (*sweep_command) return command_sweep(sweep_model, sweep_values, sweep_options);
    if (*plot_command) return command_plot(plot_options);
    if (*paper_command) return command_paper(figure, paper_options, paper_directory);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (writes_outputs()) std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const InputError& e) {
    if (writes_outputs()) std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // Every size is checked against its input first; what remains is a machine too small.
    if (writes_outputs()) std::cerr << "slidespec: error: out of memory: the input asks for more than this machine has\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "slidespec: failed: " << e.what() << "\n";
#ifdef SLIDESPEC_MPI
    // The other ranks may be waiting in a collective this rank will never reach.
    if (mpi.size() > 1) mpi.abort(1);
#endif
    return 1;
  }
  return 0;
}
