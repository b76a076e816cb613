// The simulating commands: run, sweep, merge, paper, and plot (which draws their tables).
// A finished run's state stays on disk until its whole output set is committed: a crash
// or a full disk at any moment after the work leaves a run that `run --resume` finishes.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/analyze.hpp"
#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "cli/sweep.hpp"
#include "io/atomic_file.hpp"
#include "util/suggest.hpp"
#include "io/tables.hpp"
#include "run/session.hpp"
#include "slidespec/simd.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::cli {

namespace {

constexpr int kNotStationary = kNotWhatItClaims;
/// Exit status of a run whose outputs could not all be written (its state is kept).
constexpr int kNotWritten = 1;

std::atomic<bool> stop_requested{false};
std::atomic<int> stop_signal{0};
extern "C" void request_stop(int signal) {
  stop_signal = signal;
  stop_requested = true;
}

void catch_stop_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

/// The request options of the simulating commands, declared once. Help defaults come
/// from RunRequest's own defaults.
struct RequestOptions {
  RunRequest request;
  std::string simd = "auto";

  /// The band, the target, the seed and the execution: every simulating command has them.
  void add_to(CLI::App& command) {
    const RunRequest defaults;
    command.add_option("--omega-min", request.omega_min, with_default("lowest omega [rad/s]", defaults.omega_min));
    command.add_option("--omega-max", request.omega_max, with_default("highest omega [rad/s]", defaults.omega_max));
    command.add_option("--precision", request.precision,
                       with_default("target relative standard error at every point", defaults.precision));
    command.add_option("--seed", request.seed, with_default("random seed", static_cast<double>(defaults.seed)));
    command
        .add_option_function<std::string>(
            "--control-variate",
            [this](const std::string& word) {
              if (word != "shadow" && word != "off")
                throw CLI::ValidationError("--control-variate", "need shadow or off (got " + word + ")");
              request.control_variate = word == "shadow";
            },
            "shadow: each realization's linear shadow as a control variate (docs/run.md); off: without it, "
            "on the forcing control variate alone (default shadow)")
        ->type_name("shadow|off");
    command.add_option("--threads", request.threads, "threads (default, or 0: all cores)");
    command
        .add_option("--work-budget", request.work_budget,
                    with_default("most realization-steps a run may plan", kDefaultWorkBudget))
        ->check(CLI::Validator(
            [](const std::string& text) {
              // 0 reads as "the default budget": refused rather than silently replaced.
              const auto steps = io::parse_number(text);
              return steps && *steps > 0 ? std::string()
                                         : "need a positive number of realization-steps (got " + text + ")";
            },
            "STEPS>0"));
    command.add_option("--simd", simd, simd_path_names() + " (default auto)");
  }
  /// The output grid's density and a fixed count of realizations (run, sweep).
  void add_sampling_to(CLI::App& command) {
    const RunRequest defaults;
    command.add_option("--points", request.points_per_decade,
                       with_default("points per decade", defaults.points_per_decade));
    command.add_option("--realizations", request.realizations, "realizations per sub-band")
        ->excludes(command.get_option("--precision"))
        ->check(CLI::Validator(
            [](std::string& count) {
              // 0 reads as "no fixed count": the run would go to a precision instead.
              return count.find_first_not_of('0') == std::string::npos && !count.empty()
                         ? std::string("need at least 1 (leave the option out to run to a precision)")
                         : std::string();
            },
            "N>0"));
  }
  /// The request with its SIMD path checked on this CPU and its default thread count.
  RunRequest resolved(const Context& context) const {
    RunRequest r = request;
    r.simd = parse_simd_path(simd);
    resolve_simd_path(r.simd);
    if (r.threads == 0) r.threads = context.default_threads;
    return r;
  }
};

/// How one run writes: its outputs, figure, checkpoints and place in a shared bar.
struct RunOptions {
  RunRequest request;
  std::string out = "spectrum";
  bool quiet = false;
  bool no_plot = false;
  double checkpoint_every = 0;  // [s]; 0 = no periodic checkpoints
  std::string resume;           // PREFIX of a run to continue from PREFIX.state
  std::string save_state;       // where to save the finished part
  FigureStyle figure;
  // One bar over several runs (sweep, paper): this run's place in the planned work.
  Progress* shared_progress = nullptr;
  double work_before = 0, work_share = 1;  // fractions of the whole
  std::string progress_prefix;             // "run 2/6, "

  void add_output_to(CLI::App& command, const std::string& what) {
    command.add_option("--out", out, what);
    command.add_flag("--quiet", quiet, "no progress, no summary");
  }
};

/// Weights the runs of a multi-run command by their planned work and shares one bar.
void share_progress(std::vector<RunOptions>& runs, const std::vector<double>& work, Progress& progress) {
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

/// A sweep's grid point as its keys are typed: "alpha=0.5, N=10".
std::string grid_point(const std::vector<std::pair<std::string, std::string>>& values) {
  std::string shown;
  for (const auto& [key, value] : values) shown += (shown.empty() ? "" : ", ") + key + "=" + value;
  return shown;
}

void warn_if_not_stationary(const RunResult& result, const std::string& out) {
  if (!result.stationary)
    std::cerr << "slidespec: warning: " << out << ": not stationary (" << result.stationarity
              << "): no spectrum exists here; the table is marked stationary = false (exit status 3)\n";
}

/// What a run came to: its result, and whether its whole output set is on disk.
struct RunOutcome {
  RunResult result;
  bool written = true;
};

/// The exit status of a single run's outcome.
int exit_status(const RunOutcome& outcome) {
  if (!outcome.result.complete && stop_requested) return 128 + stop_signal;
  if (!outcome.written) return kNotWritten;
  return outcome.result.stationary ? 0 : kNotStationary;
}

/// A point whose estimate, error or theory is inf or nan claims no number: the run is
/// then marked as not what it claims (stationary = false with the reason, exit status 3).
void mark_if_not_numbers(RunResult& result) {
  for (const RunPoint& point : result.points)
    if (!std::isfinite(point.C_x) || !std::isfinite(point.standard_error) || !std::isfinite(point.theory)) {
      result.stationary = false;
      result.stationarity = "the point at omega = " + io::format_number(point.omega) +
                            " rad/s holds inf or nan: beyond the range of a double";
      return;
    }
}

/// Writes PREFIX.tsv, .json (and the figure) for a session's result as one set and says
/// what it wrote. False, with a message, when any part of the set could not be written
/// (then none of it was: a figure that cannot be drawn keeps the set back too).
bool write_outputs(const Context& context, const RunSession& session, const RunResult& result,
                   const RunOptions& options, const std::string& out) {
  if (!context.writes_outputs()) return true;
  const Parameters& p = session.parameters();
  const std::string figure = options.figure.path(out);
  try {
    io::OutputSet outputs;
    outputs.add(out + ".tsv", io::run_table(p, session.case_name(), session.request(), result));
    outputs.add(out + ".json", io::run_json(p, session.case_name(), session.request(), result));
    if (!options.no_plot) {
      try {
        outputs.add(figure, draw_run_figure(outputs.temporary(out + ".tsv"), options.figure));
      } catch (const io::WriteError&) {
        throw;
      } catch (const std::exception& e) {
        throw std::runtime_error(figure + " not drawn (" + e.what() + ")");
      }
    }
    outputs.commit();
  } catch (const std::exception& e) {
    std::cerr << "slidespec: error: " << e.what() << "\n";
    return false;
  }
  if (options.quiet) return true;
  std::cerr << "slidespec: "
            << (result.complete     ? "wrote "
                : result.stationary ? "interrupted; wrote what accumulated to "
                                    : "stopped; wrote what accumulated to ")
            << out << ".tsv, .json" << (options.no_plot ? "" : ", ." + options.figure.format) << " ("
            << result.points.size() << " points, largest relative error " << io::format_number(result.reached_precision)
            << ", measured mean speed " << io::format_number(result.mean_speed) << " m/s, " << result.wall_seconds
            << " s)\n";
  const RunRequest& request = session.request();
  if (result.complete && result.reached_precision > request.precision && request.duration == 0 &&
      request.realizations == 0)
    std::cerr << "slidespec: warning: the precision " << request.precision
              << " was not reached within the work budget of a sub-band; the table says what was\n";
  return true;
}

/// Advances a session to its end (or an interrupt), checkpointing to PREFIX.state, and
/// writes its outputs. Commit, then forget: the finished run is saved to PREFIX.state
/// before its outputs are written and removed only once all of them are on disk, so a
/// crash or a failed write leaves a state that `run --resume PREFIX` finishes.
RunOutcome run_and_write(const Context& context, RunSession& session, const RunOptions& options,
                         const std::string& out) {
  const std::string state_path = out + ".state";
  const bool writes = context.writes_outputs();
  Progress own_progress(options.quiet || !writes);
  Progress& progress = options.shared_progress ? *options.shared_progress : own_progress;
  RunSession::Control control;
  // The session reports sub-bands as equal shares; weigh each by its planned steps.
  const std::vector<double> band_work = sub_band_work(session.parameters(), session.request());
  control.progress = [&](double f, const std::string& what) {
    progress.update(options.work_before + weighted_fraction(f, band_work) * options.work_share,
                    options.progress_prefix + what);
  };
  control.stop = &stop_requested;
  control.communicator = context.communicator;
  control.checkpoint_every = options.checkpoint_every;
  const auto save = [&](const RunSession& s) {
    if (!writes) return;
    try {
      io::write_atomically(state_path, s.save());
    } catch (const io::WriteError& e) {
      // The atomic write left the previous checkpoint as it was: say so, and how to go on.
      std::error_code ignored;
      if (!std::filesystem::exists(state_path, ignored)) throw;
      throw io::WriteError(std::string(e.what()) + "; " + state_path +
                           " still holds the previous checkpoint, intact: continue it with slidespec run --resume " +
                           out);
    }
  };
  control.checkpoint = save;
  const bool finished = session.advance(control);
  if (!options.shared_progress) progress.finish();
  if (writes) {
    save(session);
    if (!finished && !options.quiet)
      std::cerr << "slidespec: saved the run to " << state_path << "; continue it with: slidespec run --resume " << out
                << (options.save_state.empty() ? "" : " --save-state " + options.save_state) << "\n";
    // merge reads only finished parts; an interrupted one lives on in PREFIX.state alone.
    if (finished && !options.save_state.empty()) io::write_atomically(options.save_state, session.save());
  }
  RunOutcome outcome{session.result(), true};
  mark_if_not_numbers(outcome.result);
  outcome.written = write_outputs(context, session, outcome.result, options, out);
  if (writes && finished) {
    // A part's state and one asked for by --save-state are what merge reads.
    std::error_code ignored;
    const bool part_of_a_run =
        session.request().part ||
        (!options.save_state.empty() && std::filesystem::equivalent(options.save_state, state_path, ignored));
    if (outcome.written && !part_of_a_run)
      io::remove_durably(state_path);
    else if (!outcome.written)
      std::cerr << "slidespec: the finished run is kept in " << state_path
                << "; write its outputs with: slidespec run --resume " << out << (options.no_plot ? " --no-plot" : "")
                << "\n";
  }
  if (writes) warn_if_not_stationary(outcome.result, out);
  return outcome;
}

/// FIRST:COUNT of --realizations-range.
void apply_realization_range(const std::string& range, RunRequest& request) {
  const auto colon = range.find(':');
  std::size_t used_first = 0, used_count = 0;
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    request.first_realization = std::stoull(range.substr(0, colon), &used_first);
    request.realizations = std::stoull(range.substr(colon + 1), &used_count);
    request.part = true;
  } catch (const std::exception&) {
    used_first = 0;
  }
  if (colon == std::string::npos || used_first != colon || used_count != range.size() - colon - 1 || range[0] == '-' ||
      range[colon + 1] == '-' || request.realizations == 0)
    throw InputError("--realizations-range: expected FIRST:COUNT (whole numbers, COUNT > 0), got '" + range + "'");
}

class RunCommand final : public Command {
 public:
  RunCommand(CLI::App& app, const Context& context)
      : Command(app.add_subcommand("run", "simulated spectrum with error bars, beside the theory")), context_(context) {
    CLI::App& c = subcommand();
    model_.add_to(c);
    request_.add_to(c);
    request_.add_sampling_to(c);
    c.add_option("--duration", request_.request.duration, "simulated seconds per realization of the lowest sub-band")
        ->excludes(c.get_option("--precision"));
    c.add_option("--realizations-range", range_,
                 "FIRST:COUNT: run only these realizations (a part of a run; see merge)")
        ->excludes(c.get_option("--realizations"))
        ->excludes(c.get_option("--precision"));
    options_.add_output_to(c, "output prefix: PREFIX.tsv, .json, .png (default spectrum)");
    c.add_option("--checkpoint-every", options_.checkpoint_every,
                 "save the run to PREFIX.state every S seconds of wall time")
        ->check(CLI::Validator(
            [](const std::string& text) {
              const auto seconds = io::parse_number(text);
              return seconds && *seconds > 0 ? std::string() : "need a positive number of seconds (got " + text + ")";
            },
            "S>0"));
    c.add_option("--resume", options_.resume, "continue the run saved in PREFIX.state");
    c.add_option("--save-state", options_.save_state, "save the finished run (a part) to FILE");
    c.add_flag("--no-plot", options_.no_plot, "skip the figure PREFIX.png");
    options_.figure.add_to(c);
  }

  Files files() const override {
    Files files;
    model_.add_inputs(files);
    const std::string& resume = options_.resume;
    if (!resume.empty()) files.input(resume + ".state", "--resume");
    const std::string out = out_prefix();
    files.outputs_of(out, "--out", {".tsv", ".json", "." + options_.figure.format});
    // A resumed run saves its progress over the state it continues: that is its purpose.
    if (resume.empty() || out != resume) files.output(out + ".state", "--out");
    // Resuming a part whose --save-state was its PREFIX.state names that state twice.
    if (given("--save-state") && (resume.empty() || options_.save_state != resume + ".state"))
      files.output(options_.save_state, "--save-state");
    // A state is an output like the others: F.state is locked as the prefix F, so that no
    // two commands write it at once, nor a part's --save-state the state of a run --out F.
    if (given("--save-state")) files.prefixes.push_back({state_prefix(options_.save_state), "--save-state"});
    return files;
  }

  int run() override {
    RunOptions options = options_;
    options.figure.check();
    options.out = out_prefix();
    options.request = request_.resolved(context_);
    if (!range_.empty()) apply_realization_range(range_, options.request);
    // A part is only of use to merge, which reads the state --save-state writes.
    if (!range_.empty() && options.save_state.empty() && options.resume.empty())
      throw InputError(
          "--realizations-range: a part of a run needs --save-state FILE, the state merge joins (for a "
          "run of its own use --realizations)");
    // Zero would read as "no fixed duration" and run to the precision instead.
    if (given("--duration") && !(options.request.duration > 0))
      throw InputError("--duration: need a positive number of seconds (got " +
                       io::format_number(options.request.duration) + ")");
    if (!options.resume.empty()) return resume(options);
    const Parameters p = model_.build();
    RunSession session(p, options.request, model_.label(p));  // validates before any work
    // A finished run removes its state but for a part, which merge reads, so one left behind
    // is that, or an unfinished run (or one whose outputs were never written) this run would orphan.
    if (std::error_code ignored; std::filesystem::exists(options.out + ".state", ignored)) {
      bool finished_part = false;
      try {
        const RunSession left = RunSession::load(io::read_file(options.out + ".state", "--out"));
        finished_part = left.finished() && left.request().part;
      } catch (const InputError&) {
      }
      throw InputError("--out: " + options.out + ".state holds " +
                       (finished_part ? "a finished part of a run; join it with merge"
                                      : "an interrupted run; continue it with --resume " + options.out) +
                       ", or remove it to start afresh");
    }
    if (given("--save-state") && options.save_state != options.out + ".state")
      refuse_state_of_another_run(options.save_state, nullptr);
    if (context_.writes_outputs()) refuse_state_beyond_free_space(p, options.request, options.out);
    if (!options.quiet && context_.writes_outputs()) warn_if_no_theory_holds(p);
    catch_stop_signals();
    return exit_status(run_and_write(context_, session, options, options.out));
  }

 private:
  bool given(const char* name) const { return subcommand().count(name) > 0; }

  /// The prefix whose lock guards a state file: F for F.state, else the name itself.
  static std::string state_prefix(const std::string& path) {
    const std::string suffix = ".state";
    return path.size() > suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0
               ? path.substr(0, path.size() - suffix.size())
               : path;
  }

  /// --save-state FILE would replace a state already there: a finished part (merge's only
  /// copy) or an interrupted run. Allowed only when it holds the very run `resumed` continues.
  static void refuse_state_of_another_run(const std::string& path, const RunSession* resumed) {
    if (std::error_code ignored; !std::filesystem::exists(path, ignored)) return;
    std::string held = "a file that is not a run state";
    try {
      const RunSession there = RunSession::load(io::read_file(path, "--save-state"));
      if (resumed != nullptr && resumed->difference(there.parameters(), there.request()).empty()) return;
      held = there.finished()
                 ? (there.request().part ? "a finished part of a run (join it with merge)" : "a finished run")
                 : "an interrupted run";
    } catch (const InputError&) {
    }
    throw InputError("--save-state: " + path + " already holds " + held +
                     "; choose another file, or remove it to write this run's state there");
  }

  /// A run saves a state of at least (points + 2) doubles per realization of each
  /// sub-band (its own periodogram means, control and speed) before its outputs: refused
  /// at once where even that cannot fit. A run of fixed realizations knows its count; a
  /// run to a precision runs at least its first round of realizations in every sub-band.
  static void refuse_state_beyond_free_space(const Parameters& p, const RunRequest& request, const std::string& out) {
    const double realizations =
        static_cast<double>(request.realizations > 0 ? request.realizations : run_detail::kInitialRealizations);
    double bytes = 0;
    for (const SubBand& band : plan_sub_bands(p, request)) {
      const double points = static_cast<double>(
          log_spaced_omegas(band.omega_low, band.omega_high * (1 + 1e-12), request.points_per_decade).size());
      bytes += realizations * (points + 2) * sizeof(double);
    }
    std::error_code error;
    const std::filesystem::path directory = std::filesystem::absolute(out, error).parent_path();
    const std::filesystem::space_info space = std::filesystem::space(directory, error);
    if (error || static_cast<double>(space.available) >= bytes) return;
    auto megabytes = [](double b) {
      char text[32];
      std::snprintf(text, sizeof text, "%.3g MB", b / 1e6);
      return std::string(text);
    };
    throw InputError("--out " + out + ": the run's state needs at least " + megabytes(bytes) + " and " +
                     directory.string() + " has " + megabytes(static_cast<double>(space.available)) + " free");
  }
  std::string out_prefix() const {
    return !given("--out") && !options_.resume.empty() ? options_.resume : options_.out;
  }

  /// Continues a saved run: its parameters and request are in the state; options given
  /// here must describe the same run (threads and SIMD path may change).
  int resume(RunOptions& options) {
    // The budget bounds the plan a fresh run makes; a resumed run continues the plan it has.
    if (given("--work-budget"))
      throw InputError("--work-budget: a resumed run continues the plan it started with; leave --work-budget out");
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
      request.part = options.request.part;
    }
    if (given("--seed")) request.seed = options.request.seed;
    if (given("--control-variate")) request.control_variate = options.request.control_variate;
    const std::string differs = session.difference(model_given ? model_.build() : session.parameters(), request);
    if (!differs.empty()) throw InputError("--resume: " + options.resume + ".state is another run (" + differs + ")");
    if (given("--save-state") && options.save_state != options.resume + ".state" &&
        options.save_state != options.out + ".state")
      refuse_state_of_another_run(options.save_state, &session);
    session.set_execution(options.request.threads, options.request.simd);
    catch_stop_signals();
    return exit_status(run_and_write(context_, session, options, options.out));
  }

  const Context& context_;
  ModelOptions model_;
  RequestOptions request_;
  RunOptions options_;
  std::string range_;
};

/// Parts of a run split over a job array, as the whole run.
class MergeCommand final : public Command {
 public:
  MergeCommand(CLI::App& app, const Context& context)
      : Command(app.add_subcommand("merge",
                                   "join the parts of a run (--realizations-range, --save-state) into its outputs")),
        context_(context) {
    CLI::App& c = subcommand();
    c.add_option("parts", parts_, "state files of the parts")->required();
    c.add_option("--out", options_.out, "output prefix (default spectrum)");
    c.add_flag("--quiet", options_.quiet, "no summary");
    c.add_flag("--no-plot", options_.no_plot, "skip the figure PREFIX.png");
    options_.figure.add_to(c);
  }

  Files files() const override {
    Files files;
    for (const std::string& path : parts_) files.input(path, "merge");
    files.outputs_of(options_.out, "--out", {".tsv", ".json", "." + options_.figure.format});
    return files;
  }

  int run() override {
    options_.figure.check();
    std::vector<RunSession> parts;
    for (const std::string& path : parts_) {
      try {
        parts.push_back(RunSession::load(io::read_file(path, "merge")));
      } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
      }
    }
    RunSession whole = RunSession::merge(std::move(parts));
    RunOutcome outcome{whole.result(), true};
    mark_if_not_numbers(outcome.result);
    outcome.written = write_outputs(context_, whole, outcome.result, options_, options_.out);
    if (context_.writes_outputs()) warn_if_not_stationary(outcome.result, options_.out);
    return exit_status(outcome);
  }

 private:
  const Context& context_;
  std::vector<std::string> parts_;
  RunOptions options_;
};

/// A grid of parameter values (several keys, lists or ranges), one run each (all cores,
/// or all ranks, each), their combined table and an overlay of their spectra. Every run
/// is validated before the first starts.
class SweepCommand final : public Command {
 public:
  SweepCommand(CLI::App& app, const Context& context)
      : Command(app.add_subcommand("sweep", "one run per value of a parameter, and their spectra in one picture")),
        context_(context) {
    CLI::App& c = subcommand();
    c.add_option("values", words_,
                 "KEY=V1,V2,... | KEY=FIRST:LAST:STEP | KEY=FIRST..LAST log|lin K; several keys make a grid "
                 "(e.g. alpha=0.1:1:0.1 N=10..100 log 5)")
        ->required();
    model_.add_to(c);
    request_.add_to(c);
    request_.add_sampling_to(c);
    options_.add_output_to(c,
                           "output prefix: PREFIX_KEY=V....tsv/.json per run, PREFIX.tsv/.json all runs, PREFIX.png");
    c.add_flag("--no-plot", options_.no_plot, "skip the overlay PREFIX.png");
    options_.figure.add_to(c);
  }

  Files files() const override {
    Files files;
    model_.add_inputs(files);
    files.outputs_of(options_.out, "--out", {".tsv", ".json", "." + options_.figure.format});
    for (const auto& values : sweep_grid(parse_sweep(words_)))
      files.outputs_of(run_prefix(values), "--out", {".tsv", ".json", ".state"});
    return files;
  }

  int run() override {
    RunOptions options = options_;
    options.figure.check();
    const std::vector<SweepAxis> axes = parse_sweep(words_);
    const auto grid = sweep_grid(axes);
    options.request = request_.resolved(context_);
    std::vector<Parameters> params;
    std::vector<double> work;
    for (const auto& values : grid) {
      ModelOptions one = model_;
      for (const auto& [key, value] : values) one.overrides.push_back(key + "=" + value);
      // Swept across drives, a spring's stiffness belongs to the spring's runs alone.
      if (std::find(values.begin(), values.end(), std::pair<std::string, std::string>("drive", "force")) !=
          values.end())
        std::erase_if(one.overrides, [](const std::string& change) { return change.rfind("k_drive=", 0) == 0; });
      try {
        params.push_back(one.build());
        RunSession check(params.back(), options.request);  // validates the band for these values
        work.push_back(planned_work(params.back(), options.request));
      } catch (const InputError& e) {
        throw InputError("sweep run " + grid_point(values) + ": " + e.what());
      }
    }
    catch_stop_signals();
    const bool writes = context_.writes_outputs();
    if (writes && !options.no_plot) start_plotter();
    Progress progress(options.quiet || !writes);
    std::vector<RunOptions> singles(grid.size(), options);
    share_progress(singles, work, progress);
    std::vector<SweepRun> runs;
    std::vector<std::string> tables;
    bool stationary = true, written = true, interrupted = false;
    for (std::size_t k = 0; k < grid.size(); ++k) {
      const std::string name = run_prefix(grid[k]);
      const std::string shown = grid_point(grid[k]);
      singles[k].no_plot = true;
      if (!options.quiet && writes && !isatty(STDERR_FILENO))
        std::cerr << "slidespec: sweep " << k + 1 << "/" << grid.size() << ": " << shown << "\n";
      const std::string label = model_.label(params[k]);
      RunSession session(params[k], singles[k].request, label);
      const RunOutcome outcome = run_and_write(context_, session, singles[k], name);
      runs.push_back({grid[k], label, name + ".tsv", outcome.result});
      tables.push_back(name + ".tsv");
      stationary = stationary && outcome.result.stationary;
      written = written && outcome.written;
      // Interrupted in any run, the last one included: the sweep is not done.
      interrupted = !outcome.result.complete && stop_requested;
      if (interrupted) break;
    }
    progress.finish();
    // The combined table holds what was run, also when interrupted.
    if (writes) {
      io::OutputSet combined;
      combined.add(options.out + ".tsv", sweep_table(axes, runs));
      combined.add(options.out + ".json", sweep_json(axes, runs));
      combined.commit();
      if (!options.quiet)
        std::cerr << "slidespec: wrote " << options.out << ".tsv, .json (all " << runs.size() << " runs)\n";
    }
    if (interrupted) return 128 + stop_signal;
    if (!written) return kNotWritten;
    const int done = stationary ? 0 : kNotStationary;
    if (options.no_plot || !writes) return done;
    std::string swept;
    for (const SweepAxis& axis : axes) swept += (swept.empty() ? "" : ", ") + axis.key;
    const std::string picture = options.figure.path(options.out);
    const int status = plot(tables, picture, model_.case_name + ": sweep of " + swept, options.figure);
    if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << picture << "\n";
    return status == 0 ? done : 1;
  }

 private:
  std::string run_prefix(const std::vector<std::pair<std::string, std::string>>& values) const {
    std::string name = options_.out;
    for (const auto& [key, value] : values) name += "_" + key + "=" + value;
    return name;
  }

  const Context& context_;
  ModelOptions model_;
  RequestOptions request_;
  RunOptions options_;
  std::vector<std::string> words_;
};

class PlotCommand final : public Command {
 public:
  explicit PlotCommand(CLI::App& app) : Command(app.add_subcommand("plot", "overlay spectrum tables in one picture")) {
    CLI::App& c = subcommand();
    c.add_option("tables", tables_, "TSV files from run or theory")->required();
    c.add_option("-o,--out", out_, "the figure to write: .png, .pdf or .svg")->required();
    c.add_option("--title", title_, "title of the picture");
    figure_.add_size_to(c);
  }

  Files files() const override {
    Files files;
    for (const std::string& path : tables_) files.input(path, "plot");
    files.output(out_, "--out");
    files.prefixes.push_back({out_, "--out"});
    return files;
  }

  int run() override {
    figure_.format = format_of(out_);
    figure_.check();
    check_title(title_, figure_);
    io::check_output_prefix(out_);
    return plot(tables_, out_, title_, figure_);
  }

 private:
  std::vector<std::string> tables_;
  std::string out_, title_;
  FigureStyle figure_;
};

/// One run of a paper figure: its tables' name, the named case and changes to it.
struct PaperRun {
  std::string name;
  std::string case_name;
  std::vector<std::string> changes;  ///< KEY=VALUE
};

/// The paper's figures (and the drives figure, docs/model.md §9): the runs each overlays.
const std::vector<std::pair<std::string, std::vector<PaperRun>>>& paper_figures() {
  // The drives: N = 12 at alpha = 0.4 pulled by a constant force and by springs whose
  // omega_s = k_drive v / (F_drive - F_kin) is 0.1, 1 and 10 rad/s; and §8's stall example,
  // which a constant force stalls for good, under a spring.
  const std::vector<std::string> flat = {"N=12", "alpha=0.4"};
  auto with = [](std::vector<std::string> base, std::initializer_list<const char*> more) {
    base.insert(base.end(), more.begin(), more.end());
    return base;
  };
  static const std::vector<std::pair<std::string, std::vector<PaperRun>>> figures = {
      {"fig2",
       {{"reference", "reference", {}},
        {"fast", "fast", {}},
        {"short-renewal", "short-renewal", {}},
        {"many-contacts", "many-contacts", {}}}},
      {"fig3",
       {{"reference", "reference", {}}, {"medium-noise", "medium-noise", {}}, {"weak-noise", "weak-noise", {}}}},
      {"fig6", {}},  // a fit to a record through analyze, not runs
      {"hierarchy", {{"reference", "reference", {}}, {"hierarchical", "hierarchical", {}}}},  // docs/hierarchy.md
      {"drives",
       {{"force", "reference", flat},
        {"spring1e3", "reference", with(flat, {"drive=spring", "k_drive=1e3"})},
        {"spring1e4", "reference", with(flat, {"drive=spring", "k_drive=1e4"})},
        {"spring1e5", "reference", with(flat, {"drive=spring", "k_drive=1e5"})},
        {"stall_spring", "reference", {"N=7", "F_drive=8", "F_kin=6", "a=3e-4", "drive=spring", "k_drive=1e4"}}}},
  };
  return figures;
}

class PaperCommand final : public Command {
 public:
  PaperCommand(CLI::App& app, const Context& context)
      : Command(app.add_subcommand("paper", "run the paper's cases and draw its figure")), context_(context) {
    CLI::App& c = subcommand();
    c.add_option("figure", figure_, "fig2 | fig3 | fig6 | hierarchy | drives")->required();
    c.add_option("--out-dir", directory_, "directory for the tables and the figure");
    c.add_option("--record", record_, "fig6: your own displacement record (as for analyze) instead of a synthetic one");
    request_.add_to(c);
    c.add_flag("--quiet", options_.quiet, "no progress, no summary");
    options_.figure.add_to(c);
  }

  Files files() const override {
    Files files;
    const auto& cases = found()->second;
    if (!record_.empty()) files.input(record_, "--record");
    const std::string prefix = directory_ + "/" + figure_;
    if (figure_ == "fig6") {
      files.outputs_of(prefix, "--out-dir", {".tsv", ".json", "." + options_.figure.format});
      if (record_.empty()) files.outputs_of(prefix + "_record", "--out-dir", {".csv"});
    } else {
      files.outputs_of(prefix, "--out-dir", {"." + options_.figure.format});
    }
    for (const PaperRun& run : cases)
      files.outputs_of(prefix + "_" + run.name, "--out-dir", {".tsv", ".json", ".state"});
    return files;
  }

  int run() override {
    const auto& cases = found()->second;
    if (!record_.empty() && figure_ != "fig6") throw InputError("paper: --record is for fig6 only");
    // fig6 analyzes a record: the options of the simulating figures would be ignored.
    if (figure_ == "fig6")
      for (const char* name : {"--omega-min", "--omega-max", "--precision", "--seed", "--control-variate", "--threads",
                               "--work-budget", "--simd"})
        if (subcommand().count(name) > 0)
          throw InputError(std::string("paper fig6: ") + name +
                           " does not apply (fig6 analyzes a record, synthetic or --record; it simulates nothing)");
    RunOptions options = options_;
    if (figure_ == "fig6")
      return context_.writes_outputs() ? paper_fig6(record_, directory_, options.figure, options.quiet) : 0;
    options.figure.check();
    // The paper's Fig. 2 colours, case by case (docs/model.md §2).
    if (figure_ == "fig2") options.figure.colors = {"#7b2fbe", "#2ca02c", "#d62728", "#e8b800"};
    options.request = request_.resolved(context_);
    io::check_output_prefix(directory_ + "/" + figure_);
    std::vector<Parameters> params;
    std::vector<double> work;
    for (const PaperRun& run : cases) {
      ParameterBuilder builder(run.case_name);
      for (const std::string& change : run.changes) builder.set(change);
      params.push_back(builder.build());
      validate_request(params.back(), options.request);
      work.push_back(planned_work(params.back(), options.request));
    }
    catch_stop_signals();
    const bool writes = context_.writes_outputs();
    if (writes) start_plotter();
    Progress progress(options.quiet || !writes);
    std::vector<RunOptions> singles(params.size(), options);
    share_progress(singles, work, progress);
    std::vector<std::string> tables;
    bool written = true;
    for (std::size_t k = 0; k < params.size(); ++k) {
      const std::string out = directory_ + "/" + figure_ + "_" + cases[k].name;
      singles[k].no_plot = true;
      RunSession session(params[k], singles[k].request, cases[k].case_name);
      const RunOutcome outcome = run_and_write(context_, session, singles[k], out);
      tables.push_back(out + ".tsv");
      written = written && outcome.written;
      if (!outcome.result.complete && stop_requested) return 128 + stop_signal;
    }
    progress.finish();
    if (!written) return kNotWritten;
    const std::string title = figure_ == "hierarchy" ? "flat and two-level contacts (the paper's Fig. 1c)"
                              : figure_ == "drives"  ? "pulled by a constant force or through a spring"
                                                     : "Fig. " + figure_.substr(3) + " of the paper";
    // The drives have their own layout: C_x, the drive's force, and the stall case.
    if (figure_ == "drives") options.figure.layout = "drives";
    if (!writes) return 0;
    const std::string picture = options.figure.path(directory_ + "/" + figure_);
    const int status = plot(tables, picture, title, options.figure);
    if (status == 0 && !options.quiet) std::cerr << "slidespec: drew " << picture << "\n";
    return status == 0 ? 0 : 1;
  }

 private:
  using Figures = std::vector<std::pair<std::string, std::vector<PaperRun>>>;
  Figures::const_iterator found() const {
    const auto& figures = paper_figures();
    const auto it = std::find_if(figures.begin(), figures.end(), [&](const auto& f) { return f.first == figure_; });
    if (it == figures.end()) {
      std::vector<std::string> names;
      std::string known;
      for (const auto& f : figures) {
        names.push_back(f.first);
        known += (known.empty() ? "" : ", ") + f.first;
      }
      throw InputError("paper: unknown figure '" + figure_ + "'" + util::did_you_mean(figure_, names) +
                       " (known: " + known + ")");
    }
    return it;
  }

  const Context& context_;
  std::string figure_, directory_ = ".", record_;
  RequestOptions request_;
  RunOptions options_;
};

}  // namespace

void add_run_commands(CLI::App& app, const Context& context, std::vector<std::unique_ptr<Command>>& commands) {
  commands.push_back(std::make_unique<RunCommand>(app, context));
  commands.push_back(std::make_unique<SweepCommand>(app, context));
  commands.push_back(std::make_unique<MergeCommand>(app, context));
  commands.push_back(std::make_unique<PlotCommand>(app));
  commands.push_back(std::make_unique<PaperCommand>(app, context));
}

}  // namespace slidespec::cli
