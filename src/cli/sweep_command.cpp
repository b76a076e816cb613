// `slidespec sweep`: one run per point of a grid of parameter values, their combined table
// and an overlay of their spectra.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "cli/request_options.hpp"
#include "cli/run_and_write.hpp"
#include "cli/sweep.hpp"
#include "cli/sweep_continue.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

namespace {

/// A sweep's grid point as its keys are typed: "alpha=0.5, N=10".
std::string grid_point(const std::vector<std::pair<std::string, std::string>>& values) {
  std::string shown;
  for (const auto& [key, value] : values) shown += (shown.empty() ? "" : ", ") + key + "=" + value;
  return shown;
}

/// One run of the grid, checked before the first starts, and what an interrupted sweep
/// left of it.
struct PlannedRun {
  std::vector<std::pair<std::string, std::string>> values;
  std::string prefix;  // PREFIX_KEY=V...
  std::string shown;   // "alpha=0.5, N=10"
  Parameters parameters;
  std::string label;
  double work = 0;
  RunLeft left;
};

/// The continuation tests (tests/cli/sweep_resume_test.sh) interrupt a sweep between two
/// runs: SLIDESPEC_SWEEP_STALL=FILE writes the pid to FILE there and waits for a signal
/// (a minute at most).
void stall_between_runs() {
  const char* stall = std::getenv("SLIDESPEC_SWEEP_STALL");
  if (stall == nullptr) return;
  std::ofstream(stall) << getpid() << "\n";
  for (int k = 0; k < 600 && !stop_asked(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

/// A grid of parameter values (several keys, lists or ranges), one run each (all cores,
/// or all ranks, each), their combined table and an overlay of their spectra. Every run
/// is validated before the first starts. PREFIX.sweep records the sweep until its combined
/// set is whole, so that --resume continues it where a signal cut it.
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
    options_.add_output_to(
        c, "output prefix: PREFIX_KEY=V....tsv/.json per run, PREFIX.tsv/.json all runs, PREFIX.png, PREFIX.sweep");
    c.add_flag("--resume", resume_,
               "continue the interrupted sweep at --out (the same values and options): finished runs are taken from "
               "their outputs, the cut run from its state");
    c.add_flag("--no-plot", options_.no_plot, "skip the overlay PREFIX.png");
    options_.figure.add_to(c);
  }

  Files files() const override {
    Files files;
    model_.add_inputs(files);
    files.outputs_of(options_.out, "--out", {".tsv", ".json", "." + options_.figure.format, ".sweep"});
    for (const auto& values : sweep_grid(parse_sweep(words_)))
      files.outputs_of(run_prefix(values), "--out", {".tsv", ".json", ".state"});
    return files;
  }

  int run() override {
    RunOptions options = options_;
    options.figure.check();
    const std::vector<SweepAxis> axes = parse_sweep(words_);
    options.request = request_.resolved(context_);
    std::vector<PlannedRun> runs = plan(axes, options.request);
    std::vector<Parameters> params;
    for (const PlannedRun& planned : runs) params.push_back(planned.parameters);
    const nlohmann::ordered_json record = sweep_record(model_.case_name, axes, options.request, params);
    const bool writes = context_.writes_outputs();
    if (resume_)
      find_what_is_left(runs, options, record);
    else if (writes)
      refuse_work_left(runs);
    catch_stop_signals();
    if (writes && !options.no_plot) start_plotter();
    if (writes && !resume_) io::write_atomically(options.out + ".sweep", io::json_file_text(record));
    Progress progress(options.quiet || !writes);
    std::vector<RunOptions> singles(runs.size(), options);
    std::vector<double> work;
    for (const PlannedRun& planned : runs) work.push_back(planned.work);
    share_progress(singles, work, progress);
    std::vector<SweepRun> done;
    bool stationary = true, written = true, interrupted = false;
    for (std::size_t k = 0; k < runs.size(); ++k) {
      if (k > 0) stall_between_runs();
      // A signal between two runs: the next one does not start, and --resume starts it.
      if (context_.communicator ? context_.communicator->any(stop_asked()) : stop_asked()) {
        interrupted = true;
        break;
      }
      const RunOutcome outcome = run_one(runs[k], singles[k], k, runs.size());
      done.push_back({runs[k].values, runs[k].label, runs[k].prefix + ".tsv", runs[k].parameters, outcome.result});
      stationary = stationary && outcome.result.stationary;
      written = written && outcome.written;
      // Interrupted in any run, the last one included: the sweep is not done.
      interrupted = stopped_by_signal(outcome.result);
      if (interrupted) break;
    }
    progress.finish();
    const int figure_status = writes ? write_combined(options, axes, done, interrupted || !written) : 0;
    // A signal while the figure is drawn cuts the sweep too: --resume draws it.
    interrupted = interrupted || stop_asked();
    // The record goes once the sweep is whole on disk; until then --resume continues it.
    if (writes && !interrupted && written && figure_status == 0) io::remove_durably(options.out + ".sweep");
    if (interrupted) {
      if (writes && !options.quiet)
        std::cerr << "slidespec: sweep interrupted; continue it with the same command and --resume\n";
      return stopped_status();
    }
    if (!written || figure_status != 0) return kNotWritten;
    return stationary ? 0 : kNotWhatItClaims;
  }

 private:
  /// Every run's parameters and plan, checked before any work (a failing run named).
  std::vector<PlannedRun> plan(const std::vector<SweepAxis>& axes, const RunRequest& request) const {
    std::vector<PlannedRun> runs;
    for (const auto& values : sweep_grid(axes)) {
      ModelOptions one = model_;
      for (const auto& [key, value] : values) one.overrides.push_back(key + "=" + value);
      // Swept across drives, a spring's stiffness belongs to the spring's runs alone.
      if (std::find(values.begin(), values.end(), std::pair<std::string, std::string>("drive", "force")) !=
          values.end())
        std::erase_if(one.overrides, [](const std::string& change) { return change.rfind("k_drive=", 0) == 0; });
      try {
        const Parameters p = one.build();
        RunSession check(p, request);  // validates the band for these values
        runs.push_back(
            {values, run_prefix(values), grid_point(values), p, model_.label(p), planned_work(p, request), {}});
      } catch (const InputError& e) {
        throw InputError("sweep run " + grid_point(values) + ": " + e.what());
      }
    }
    return runs;
  }

  /// A fresh sweep does not start over an unfinished one, nor over a run's state.
  void refuse_work_left(const std::vector<PlannedRun>& runs) const {
    if (std::error_code ignored; std::filesystem::exists(options_.out + ".sweep", ignored))
      throw InputError("--out: " + options_.out +
                       ".sweep holds a sweep not yet written whole (interrupted); continue it with the same command "
                       "and --resume, or remove it and its runs' .state files to start afresh");
    for (const PlannedRun& planned : runs) try {
        refuse_state_left_at(planned.prefix, "--out");
      } catch (const InputError& e) {
        throw InputError("sweep run " + planned.shown + ": " + e.what());
      }
  }

  /// --resume: the record must be this sweep's, and each run's state or outputs this run's.
  void find_what_is_left(std::vector<PlannedRun>& runs, const RunOptions& options,
                         const nlohmann::ordered_json& record) const {
    check_sweep_record(options.out, record);
    int reused = 0, continued = 0;
    for (PlannedRun& planned : runs) {
      planned.left = run_left(planned.prefix, planned.shown, planned.parameters, options.request, planned.label);
      reused += planned.left.from == RunLeft::From::outputs;
      continued += planned.left.from == RunLeft::From::state;
    }
    if (!options.quiet && context_.writes_outputs())
      std::cerr << "slidespec: continuing the sweep " << options.out << ": " << reused << " of " << runs.size()
                << " runs reused from their outputs, " << continued << " continued from their state, "
                << runs.size() - static_cast<std::size_t>(reused + continued) << " to run\n";
  }

  /// Runs (or takes from what was left) run k of n, writing its outputs.
  RunOutcome run_one(const PlannedRun& planned, RunOptions& single, std::size_t k, std::size_t n) const {
    single.no_plot = true;
    single.continue_with = "the same slidespec sweep command with --resume";
    const bool says = !single.quiet && context_.writes_outputs();
    const std::string place =
        "slidespec: sweep " + std::to_string(k + 1) + "/" + std::to_string(n) + ": " + planned.shown;
    if (planned.left.from == RunLeft::From::outputs) {
      if (says) std::cerr << place << ": reused " << planned.prefix << ".tsv, .json (complete, of this sweep)\n";
      single.shared_progress->update(single.work_before + single.work_share, single.progress_prefix + "reused");
      if (context_.writes_outputs()) warn_if_not_stationary(planned.left.result, planned.prefix);
      return {planned.left.result, true};
    }
    if (planned.left.from == RunLeft::From::state) {
      if (says) std::cerr << place << ": continued from " << planned.prefix << ".state\n";
      RunSession session = RunSession::load(io::read_file(planned.prefix + ".state", "--resume"));
      session.set_execution(single.request.threads, single.request.simd);
      single.resume = planned.prefix;
      return run_and_write(context_, session, single, planned.prefix);
    }
    if (says && (!isatty(STDERR_FILENO) || !planned.left.rerun.empty()))
      std::cerr << place << (planned.left.rerun.empty() ? "" : ": run again: " + planned.left.rerun) << "\n";
    RunSession session(planned.parameters, single.request, planned.label);
    return run_and_write(context_, session, single, planned.prefix);
  }

  /// The combined table and JSON of the runs done, and their figure for a whole sweep, as
  /// one set: an old figure never stays beside a new table. Returns the figure's status.
  int write_combined(const RunOptions& options, const std::vector<SweepAxis>& axes, const std::vector<SweepRun>& done,
                     bool cut_short) const {
    std::vector<std::string> tables;
    for (const SweepRun& run : done) tables.push_back(run.table);
    int figure_status = 0;
    io::OutputSet combined;
    combined.add(options.out + ".tsv", sweep_table(axes, done));
    combined.add(options.out + ".json", sweep_json(axes, done));
    const std::string picture = options.figure.path(options.out);
    if (!options.no_plot) {
      const std::string temporary =
          combined.add_written_by_other(picture, std::filesystem::path(picture).extension().string());
      if (!cut_short) figure_status = plot(tables, temporary, figure_title(axes), options.figure);
      cut_short = cut_short || stop_asked();
      if (cut_short || figure_status != 0) combined.drop(picture);
    }
    combined.commit();
    if (!options.quiet)
      std::cerr << "slidespec: wrote " << options.out << ".tsv, .json"
                << (options.no_plot || cut_short ? ""
                    : figure_status == 0         ? ", ." + options.figure.format
                                                 : " (the figure failed: none written)")
                << " (all " << done.size() << " runs)\n";
    return figure_status;
  }

  std::string figure_title(const std::vector<SweepAxis>& axes) const {
    std::string swept;
    for (const SweepAxis& axis : axes) swept += (swept.empty() ? "" : ", ") + axis.key;
    return model_.case_name + ": sweep of " + swept;
  }

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
  bool resume_ = false;
};

}  // namespace

std::unique_ptr<Command> make_sweep_command(CLI::App& app, const Context& context) {
  return std::make_unique<SweepCommand>(app, context);
}

}  // namespace slidespec::cli
