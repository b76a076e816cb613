// slidespec command line: a thin layer over the core library.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <fstream>
#include <filesystem>
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
#include "cli/suggest.hpp"
#include "cli/sweep.hpp"
#include "io/atomic_file.hpp"
#include "io/suggest.hpp"
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

  /// What outputs call the run: "reference + N=5, alpha=3" when keys change the case.
  std::string label(const Parameters& p) const { return io::run_label(case_name, p); }
};

void warn_if_outside_first_order(const Parameters& p) {
  const Landmarks l = landmarks(p);
  if (l.forces_can_stall)
    std::cerr << "slidespec: warning: alpha F_kin >= 2 (F_drive - F_kin): the random forces can "
                 "stall the block; the first-order theory does not hold here (docs/model.md §4.1)\n";
  else if (l.coupling_eps > 0.3)
    std::cerr << "slidespec: warning: eps = " << l.coupling_eps
              << " > 0.3: the first-order theory does not hold here (docs/model.md §4.1)\n";
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
  std::string omega_list;  // "1,2,3" [rad/s], instead of the log grid
  std::string omega_file;  // one omega a line [rad/s], '#' comments
  int order = 1;
  std::string out;
};

/// The frequencies theory is asked for: a list, a file, or the log grid.
std::vector<double> theory_omegas(const TheoryOptions& options) {
  if (options.omega_list.empty() && options.omega_file.empty())
    return log_spaced_omegas(options.omega_min, options.omega_max, options.points_per_decade);
  const bool from_file = !options.omega_file.empty();
  const std::string source = from_file ? options.omega_file : "--omega";
  std::string text = from_file ? io::read_file(options.omega_file, "--omega-file") : options.omega_list;
  std::vector<double> omegas;
  std::istringstream lines(text);
  int line_number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    line = line.substr(0, line.find('#'));
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    for (std::string word; words >> word;) {
      const double omega = io::parse_number(word).value_or(0);
      if (!(omega > 0))
        throw InputError(source + (from_file ? ": line " + std::to_string(line_number) : std::string()) + ": '" + word +
                         "' is not a positive omega in rad/s");
      omegas.push_back(omega);
    }
  }
  if (omegas.empty()) throw InputError(source + ": no omega given");
  return omegas;
}

// The exact mean speed and low-frequency diffusion beyond first order, where computed
// (below the stall boundary, one touching level).
std::string long_time_line(const Parameters& p) {
  if (landmarks(p).forces_can_stall) return "";
  int touching_levels = 0;
  for (int l = 1; l <= p.levels; ++l) touching_levels += p.touches(l) ? 1 : 0;
  if (touching_levels != 1) return "";
  const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
  const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
  return "# beyond first order (docs/model.md §7): mean speed V = " + io::format_number(exact.mean_speed) +
         " m/s, diffusion D = " + io::format_number(exact.diffusion) + " m^2/s (first order " +
         io::format_number(first.diffusion) + "), C_x -> D / (pi omega^2) below v/a\n";
}

int command_theory(const ModelOptions& model, const TheoryOptions& options) {
  const Parameters p = model.build();
  const std::vector<double> omegas = theory_omegas(options);
  if (options.order != 1 && options.order != 2) throw InputError("order: need 1 or 2");
  // Built before any work so that a model it does not cover is refused at once.
  const std::unique_ptr<SecondOrderTheory> second =
      options.order == 2 ? std::make_unique<SecondOrderTheory>(p) : nullptr;
  if (!options.out.empty()) io::check_output_prefix(options.out);
  warn_if_outside_first_order(p);
  const std::vector<double> spectrum = exact_spectrum(p, omegas);

  std::ostringstream table;
  table << io::metadata_lines(p, model.label(p)) << long_time_line(p)
        << "# columns: omega [rad/s], C_x [m^2 s] exact first-order theory, "
           "C_eq1 [m^2 s] the paper's Eq. (1)"
        << (second ? ", C_x2 [m^2 s] second-order theory (docs/model.md §7)" : "") << "\n"
        << "# omega\tC_x\tC_eq1" << (second ? "\tC_x2" : "") << "\n";
  for (size_t k = 0; k < omegas.size(); ++k) {
    table << io::format_number(omegas[k]) << "\t" << io::format_number(spectrum[k]) << "\t"
          << io::format_number(eq1_asymptote(p, omegas[k]));
    if (second) table << "\t" << io::format_number((*second)(omegas[k]));
    table << "\n";
  }
  if (options.out.empty())
    std::cout << table.str();
  else
    io::write_atomically(options.out + ".tsv", table.str());
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
  cli::FigureStyle figure;
  // One bar over several runs (sweep, paper): this run's place in the planned work.
  cli::Progress* shared_progress = nullptr;
  double work_before = 0, work_share = 1;  // fractions of the whole
  std::string progress_prefix;             // "run 2/6, "
};

/// Weights the runs of a multi-run command by their planned work and shares one bar.
void share_progress(std::vector<RunOptions>& runs, const std::vector<double>& work, cli::Progress& progress) {
  double total = 0;
  for (double w : work) total += w;
  double before = 0;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    runs[k].shared_progress = &progress;
    runs[k].work_before = before / total;
    runs[k].work_share = work[k] / total;
    runs[k].progress_prefix = "run " + std::to_string(k + 1) + "/" + std::to_string(runs.size()) + ", ";
    before += work[k];
  }
}

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
  const std::string figure = options.figure.path(out);
  const bool plotted = !options.no_plot && cli::plot({outputs.temporary(out + ".tsv")},
                                                     outputs.add_written_by_other(
                                                         figure, std::filesystem::path(figure).extension().string()),
                                                     "", options.figure) == 0;
  if (!options.no_plot && !plotted) outputs.drop(figure);
  outputs.commit();
  if (!options.no_plot && !plotted) std::cerr << "slidespec: warning: " << figure << " not drawn\n";
  if (options.quiet) return;
  std::cerr << "slidespec: " << (result.complete ? "wrote " : "interrupted; wrote what accumulated to ") << out
            << ".tsv, .json" << (plotted ? ", ." + options.figure.format : "") << " (" << result.points.size()
            << " points, largest relative error " << io::format_number(result.reached_precision)
            << ", measured mean speed " << io::format_number(result.mean_speed) << " m/s, " << result.wall_seconds
            << " s)\n";
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
  cli::Progress own_progress(options.quiet || !writes_outputs());
  cli::Progress& progress = options.shared_progress ? *options.shared_progress : own_progress;
  RunSession::Control control;
  // The session reports sub-bands as equal shares; weigh each by its planned steps.
  const std::vector<double> band_work = cli::sub_band_work(session.parameters(), session.request());
  control.progress = [&](double f, const std::string& what) {
    progress.update(options.work_before + cli::weighted_fraction(f, band_work) * options.work_share,
                    options.progress_prefix + what);
  };
  control.stop = &stop_requested;
  control.communicator = communicator;
  control.checkpoint_every = options.checkpoint_every;
  control.checkpoint = [&](const RunSession& s) {
    if (writes_outputs()) io::write_atomically(state_path, s.save());
  };
  const bool finished = session.advance(control);
  if (!options.shared_progress) progress.finish();
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
  if (colon == std::string::npos || used_first != colon || used_count != range.size() - colon - 1 || range[0] == '-' ||
      range[colon + 1] == '-' || request.realizations == 0)
    throw InputError("--realizations-range: expected FIRST:COUNT (whole numbers, COUNT > 0), got '" + range + "'");
}

int command_run(const ModelOptions& model, RunOptions options, const std::function<bool(const char*)>& given) {
  options.figure.check();
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
    const std::string differs = session.difference(model_given ? model.build() : session.parameters(), request);
    if (!differs.empty()) throw InputError("--resume: " + options.resume + ".state is another run (" + differs + ")");
    session.set_execution(options.request.threads, options.request.simd);
    if (options.out == "spectrum") options.out = options.resume;
    io::check_output_prefix(options.out);
    catch_stop_signals();
    const RunResult result = run_and_write(session, options, options.out);
    if (!result.complete && stop_requested) return 128 + stop_signal;
    return result.stationary ? 0 : kNotStationary;
  }
  const Parameters p = model.build();
  RunSession session(p, options.request, model.label(p));  // validates before any work
  io::check_output_prefix(options.out);
  // A finished run removes its state, so one left behind is an interrupted run that this
  // run would orphan (and a later --resume would bring back over the new results).
  if (std::error_code ignored; std::filesystem::exists(options.out + ".state", ignored))
    throw InputError("--out: " + options.out + ".state holds an interrupted run; continue it with --resume " +
                     options.out + ", or remove it to start afresh");
  if (!options.save_state.empty()) io::check_output_prefix(options.save_state);
  if (!options.quiet && writes_outputs()) warn_if_outside_first_order(p);
  catch_stop_signals();
  const RunResult result = run_and_write(session, options, options.out);
  if (!result.complete && stop_requested) return 128 + stop_signal;
  return result.stationary ? 0 : kNotStationary;
}

/// Parts of a run split over a job array, as the whole run.
int command_merge(const std::vector<std::string>& paths, RunOptions options) {
  options.figure.check();
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

/// A grid of parameter values (several keys, lists or ranges), one run each (all cores,
/// or all ranks, each), their combined table and an overlay of their spectra. Every run
/// is validated before the first starts.
int command_sweep(const ModelOptions& model, const std::vector<std::string>& words, RunOptions options) {
  options.figure.check();
  const std::vector<cli::SweepAxis> axes = cli::parse_sweep(words);
  const auto grid = cli::sweep_grid(axes);
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  std::vector<Parameters> params;
  std::vector<double> work;
  for (const auto& values : grid) {
    ModelOptions one = model;
    for (const auto& [key, value] : values) one.overrides.push_back(key + "=" + value);
    params.push_back(one.build());
    RunSession check(params.back(), options.request);  // validates the band for these values
    work.push_back(cli::planned_work(params.back(), options.request));
  }
  io::check_output_prefix(options.out);
  catch_stop_signals();
  cli::Progress progress(options.quiet || !writes_outputs());
  std::vector<RunOptions> singles(grid.size(), options);
  share_progress(singles, work, progress);
  std::vector<cli::SweepRun> runs;
  std::vector<std::string> tables;
  bool stationary = true;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    std::string name = options.out, shown;
    for (const auto& [key, value] : grid[k]) {
      name += "_" + key + "=" + value;
      shown += (shown.empty() ? "" : ", ") + key + " = " + value;
    }
    singles[k].no_plot = true;
    if (!options.quiet && writes_outputs() && !isatty(STDERR_FILENO))
      std::cerr << "slidespec: sweep " << k + 1 << "/" << grid.size() << ": " << shown << "\n";
    const std::string label = model.label(params[k]);
    const RunResult result = run_and_write(params[k], label, singles[k], name);
    runs.push_back({grid[k], label, name + ".tsv", result});
    tables.push_back(name + ".tsv");
    stationary = stationary && result.stationary;
    if (!result.complete && stop_requested) break;
  }
  progress.finish();
  // The combined table holds what was run, also when interrupted.
  if (writes_outputs()) {
    io::write_atomically(options.out + ".tsv", cli::sweep_table(axes, runs));
    io::write_atomically(options.out + ".json", cli::sweep_json(axes, runs));
    if (!options.quiet)
      std::cerr << "slidespec: wrote " << options.out << ".tsv, .json (all " << runs.size() << " runs)\n";
  }
  if (runs.size() < grid.size()) return 128 + stop_signal;
  const int done = stationary ? 0 : kNotStationary;
  if (options.no_plot || !writes_outputs()) return done;
  std::string swept;
  for (const cli::SweepAxis& axis : axes) swept += (swept.empty() ? "" : ", ") + axis.key;
  const std::string picture = options.figure.path(options.out);
  const int status = cli::plot(tables, picture, model.case_name + ": sweep of " + swept, options.figure);
  if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << picture << "\n";
  return status == 0 ? done : 1;
}

struct PlotOptions {
  std::vector<std::string> tables;
  std::string out;
  std::string title;
  cli::FigureStyle figure;
};

int command_plot(PlotOptions options) {
  options.figure.format = cli::format_of(options.out);
  options.figure.check();
  io::check_output_prefix(options.out);
  return cli::plot(options.tables, options.out, options.title, options.figure);
}

/// The paper's figures: which cases each overlays.
const std::vector<std::pair<std::string, std::vector<std::string>>>& paper_figures() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> figures = {
      {"fig2", {"reference", "fast", "short-renewal", "many-contacts"}},
      {"fig3", {"reference", "medium-noise", "weak-noise"}},
      {"fig6", {}},                                  // a fit to a record through analyze, not runs
      {"hierarchy", {"reference", "hierarchical"}},  // docs/model.md §6, docs/hierarchy.md
  };
  return figures;
}

int command_paper(const std::string& figure, RunOptions options, const std::string& directory,
                  const std::string& record) {
  const auto& figures = paper_figures();
  const auto found = std::find_if(figures.begin(), figures.end(), [&](const auto& f) { return f.first == figure; });
  if (found == figures.end())
    throw InputError("paper: unknown figure '" + figure + "'" +
                     io::did_you_mean(figure, {"fig2", "fig3", "fig6", "hierarchy"}) +
                     " (known: fig2, fig3, fig6, hierarchy)");
  if (!record.empty() && figure != "fig6") throw InputError("paper: --record is for fig6 only");
  if (figure == "fig6") return writes_outputs() ? cli::paper_fig6(record, directory, options.figure, options.quiet) : 0;
  options.figure.check();
  // The paper's Fig. 2 colours, case by case (docs/model.md §2).
  if (figure == "fig2") options.figure.colors = {"#7b2fbe", "#2ca02c", "#d62728", "#e8b800"};
  options.request.simd = parse_simd_path(options.simd);
  resolve_simd_path(options.request.simd);
  io::check_output_prefix(directory + "/" + figure);
  std::vector<Parameters> params;
  std::vector<double> work;
  for (const std::string& name : found->second) {
    params.push_back(ParameterBuilder(name).build());
    validate_request(params.back(), options.request);
    work.push_back(cli::planned_work(params.back(), options.request));
  }
  catch_stop_signals();
  cli::Progress progress(options.quiet || !writes_outputs());
  std::vector<RunOptions> singles(params.size(), options);
  share_progress(singles, work, progress);
  std::vector<std::string> tables;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const std::string out = directory + "/" + figure + "_" + found->second[k];
    singles[k].no_plot = true;
    const RunResult result = run_and_write(params[k], found->second[k], singles[k], out);
    tables.push_back(out + ".tsv");
    if (!result.complete && stop_requested) return 128 + stop_signal;
  }
  progress.finish();
  const std::string title = figure == "hierarchy" ? "flat and two-level contacts (the paper's Fig. 1c)"
                                                  : "Fig. " + figure.substr(3) + " of the paper";
  if (!writes_outputs()) return 0;
  const std::string picture = options.figure.path(directory + "/" + figure);
  const int status = cli::plot(tables, picture, title, options.figure);
  if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << picture << "\n";
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
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", SLIDESPEC_VERSION);

  CLI::App* cases_command = app.add_subcommand("cases", "list the named cases and their parameters");

  ModelOptions theory_model;
  TheoryOptions theory_options;
  CLI::App* theory_command = app.add_subcommand("theory", "exact first-order spectrum C_x(omega) (docs/model.md §4)");
  theory_model.add_to(*theory_command);
  theory_command->add_option("--omega-min", theory_options.omega_min, "lowest omega [rad/s]");
  theory_command->add_option("--omega-max", theory_options.omega_max, "highest omega [rad/s]");
  theory_command->add_option("--points", theory_options.points_per_decade, "points per decade");
  auto* omega_list = theory_command->add_option("--omega", theory_options.omega_list,
                                                "these omegas [rad/s], comma-separated, instead of the log grid");
  theory_command
      ->add_option("--omega-file", theory_options.omega_file,
                   "omegas [rad/s] from a file (one or more a line, '#' comments)")
      ->excludes(omega_list);
  theory_command->add_option(
      "--order", theory_options.order,
      "2: add C_x2, the second-order theory (one touching level; eps <= 0.25 for periodic renewal)");
  theory_command->add_option("--out", theory_options.out, "write PREFIX.tsv instead of stdout");

  ModelOptions run_model;
  RunOptions run_options;
  CLI::App* run_command = app.add_subcommand("run", "simulated spectrum with error bars, beside the theory");
  run_model.add_to(*run_command);
  RunRequest& request = run_options.request;
  run_command->add_option("--omega-min", request.omega_min, "lowest omega [rad/s] (default 0.1)");
  run_command->add_option("--omega-max", request.omega_max, "highest omega [rad/s] (default 1e5)");
  run_command->add_option("--points", request.points_per_decade, "points per decade (default 8)");
  auto* precision = run_command->add_option("--precision", request.precision,
                                            "target relative standard error at every point (default 0.05)");
  auto* duration = run_command->add_option("--duration", request.duration,
                                           "simulated seconds per realization of the lowest sub-band");
  duration->excludes(precision);
  auto* realizations = run_command->add_option("--realizations", request.realizations, "realizations per sub-band");
  auto* range = run_command->add_option("--realizations-range", run_options.range,
                                        "FIRST:COUNT: run only these realizations (a part of a run; see merge)");
  range->excludes(realizations)->excludes(precision);
  run_command->add_option("--seed", request.seed, "random seed (default 1)");
  run_command->add_option("--threads", request.threads, "threads (default, or 0: all cores)");
  run_command->add_option("--work-budget", request.work_budget,
                          "most realization-steps the run may plan (default 1e11)");
  run_command->add_option("--simd", run_options.simd, "scalar|sse2|avx2|avx512|auto (default auto)");
  run_command->add_option("--out", run_options.out, "output prefix: PREFIX.tsv, .json, .png (default spectrum)");
  run_command
      ->add_option("--checkpoint-every", run_options.checkpoint_every,
                   "save the run to PREFIX.state every S seconds of wall time")
      ->check(CLI::Validator(
          [](const std::string& text) {
            const auto seconds = io::parse_number(text);
            return seconds && *seconds > 0 ? std::string() : "need a positive number of seconds (got " + text + ")";
          },
          "S>0"));
  run_command->add_option("--resume", run_options.resume, "continue the run saved in PREFIX.state");
  run_command->add_option("--save-state", run_options.save_state, "save the finished run (a part) to FILE");
  run_command->add_flag("--quiet", run_options.quiet, "no progress, no summary");
  run_command->add_flag("--no-plot", run_options.no_plot, "skip the figure PREFIX.png");
  run_options.figure.add_to(*run_command);
  // A resumed run checks what was given against what it saved.
  auto run_given = [&](const char* name) { return run_command->count(name) > 0; };

  ModelOptions sweep_model;
  RunOptions sweep_options;
  std::vector<std::string> sweep_values;
  CLI::App* sweep_command =
      app.add_subcommand("sweep", "one run per value of a parameter, and their spectra in one picture");
  sweep_command
      ->add_option("values", sweep_values,
                   "KEY=V1,V2,... | KEY=FIRST:LAST:STEP | KEY=FIRST..LAST log|lin K; several keys make a grid "
                   "(e.g. alpha=0.1:1:0.1 N=10..100 log 5)")
      ->required();
  sweep_model.add_to(*sweep_command);
  sweep_command->add_option("--omega-min", sweep_options.request.omega_min, "lowest omega [rad/s]");
  sweep_command->add_option("--omega-max", sweep_options.request.omega_max, "highest omega [rad/s]");
  sweep_command->add_option("--points", sweep_options.request.points_per_decade, "points per decade");
  sweep_command->add_option("--precision", sweep_options.request.precision, "target relative standard error");
  sweep_command->add_option("--realizations", sweep_options.request.realizations, "realizations per sub-band");
  sweep_command->add_option("--seed", sweep_options.request.seed, "random seed");
  sweep_command->add_option("--threads", sweep_options.request.threads, "threads (default, or 0: all cores)");
  sweep_command->add_option("--work-budget", sweep_options.request.work_budget,
                            "most realization-steps a run may plan");
  sweep_command->add_option("--simd", sweep_options.simd, "scalar|sse2|avx2|avx512|auto");
  sweep_command->add_option("--out", sweep_options.out,
                            "output prefix: PREFIX_KEY=V....tsv/.json per run, PREFIX.tsv/.json all runs, PREFIX.png");
  sweep_command->add_flag("--quiet", sweep_options.quiet, "no progress, no summary");
  sweep_command->add_flag("--no-plot", sweep_options.no_plot, "skip the overlay PREFIX.png");
  sweep_options.figure.add_to(*sweep_command);

  std::vector<std::string> merge_parts;
  RunOptions merge_options;
  CLI::App* merge_command =
      app.add_subcommand("merge", "join the parts of a run (--realizations-range, --save-state) into its outputs");
  merge_command->add_option("parts", merge_parts, "state files of the parts")->required();
  merge_command->add_option("--out", merge_options.out, "output prefix (default spectrum)");
  merge_command->add_flag("--quiet", merge_options.quiet, "no summary");
  merge_command->add_flag("--no-plot", merge_options.no_plot, "skip the figure PREFIX.png");
  merge_options.figure.add_to(*merge_command);

  PlotOptions plot_options;
  CLI::App* plot_command = app.add_subcommand("plot", "overlay spectrum tables in one picture");
  plot_command->add_option("tables", plot_options.tables, "TSV files from run or theory")->required();
  plot_command->add_option("-o,--out", plot_options.out, "the figure to write: .png, .pdf or .svg")->required();
  plot_command->add_option("--title", plot_options.title, "title of the picture");
  plot_options.figure.add_size_to(*plot_command);

  std::string figure, paper_directory = ".", paper_record;
  RunOptions paper_options;
  CLI::App* paper_command = app.add_subcommand("paper", "run the paper's cases and draw its figure");
  paper_command->add_option("figure", figure, "fig2 | fig3 | fig6 | hierarchy")->required();
  paper_command->add_option("--out-dir", paper_directory, "directory for the tables and the figure");
  paper_command->add_option("--record", paper_record,
                            "fig6: your own displacement record (as for analyze) instead of a synthetic one");
  paper_command->add_option("--precision", paper_options.request.precision, "target relative standard error");
  paper_command->add_option("--omega-min", paper_options.request.omega_min, "lowest omega [rad/s]");
  paper_command->add_option("--omega-max", paper_options.request.omega_max, "highest omega [rad/s]");
  paper_command->add_option("--seed", paper_options.request.seed, "random seed");
  paper_command->add_option("--threads", paper_options.request.threads, "threads (default, or 0: all cores)");
  paper_command->add_option("--work-budget", paper_options.request.work_budget,
                            "most realization-steps a run may plan");
  paper_command->add_option("--simd", paper_options.simd, "scalar|sse2|avx2|avx512|auto");
  paper_command->add_flag("--quiet", paper_options.quiet, "no progress, no summary");
  paper_options.figure.add_to(*paper_command);

  const cli::AnalysisCommands analysis_commands(app);
  cli::require_whole_numbers(app);

  try {
    app.parse(argc, argv);
    if (app.get_subcommands().empty()) {  // bare `slidespec`: what it can do
      if (writes_outputs()) std::cout << app.help();
      return 0;
    }
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
    if (*paper_command) return command_paper(figure, paper_options, paper_directory, paper_record);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string unknown = cli::unknown_argument(app, argc, argv);
    if (writes_outputs()) std::cerr << "slidespec: error: " << (unknown.empty() ? e.what() : unknown) << "\n";
    return 2;
  } catch (const InputError& e) {
    if (writes_outputs()) std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // Every size is checked against its input first; what remains is a machine too small.
    if (writes_outputs())
      std::cerr << "slidespec: error: out of memory: the input asks for more than this machine has\n";
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
