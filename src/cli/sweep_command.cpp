// `slidespec sweep`: one run per point of a grid of parameter values, their combined table
// and an overlay of their spectra.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "cli/request_options.hpp"
#include "cli/run_and_write.hpp"
#include "cli/sweep.hpp"
#include "io/atomic_file.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

namespace {

/// A sweep's grid point as its keys are typed: "alpha=0.5, N=10".
std::string grid_point(const std::vector<std::pair<std::string, std::string>>& values) {
  std::string shown;
  for (const auto& [key, value] : values) shown += (shown.empty() ? "" : ", ") + key + "=" + value;
  return shown;
}

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
        if (context_.writes_outputs()) refuse_state_left_at(run_prefix(values), "--out");
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
      runs.push_back({grid[k], label, name + ".tsv", params[k], outcome.result});
      tables.push_back(name + ".tsv");
      stationary = stationary && outcome.result.stationary;
      written = written && outcome.written;
      // Interrupted in any run, the last one included: the sweep is not done.
      interrupted = stopped_by_signal(outcome.result);
      if (interrupted) break;
    }
    progress.finish();
    // The combined table holds what was run, also when interrupted; its figure, drawn only
    // for a whole sweep, belongs to the same set, so an old figure never stays beside it.
    int figure_status = 0;
    if (writes) {
      io::OutputSet combined;
      combined.add(options.out + ".tsv", sweep_table(axes, runs));
      combined.add(options.out + ".json", sweep_json(axes, runs));
      const std::string picture = options.figure.path(options.out);
      if (!options.no_plot) {
        const std::string temporary =
            combined.add_written_by_other(picture, std::filesystem::path(picture).extension().string());
        if (!interrupted && written) figure_status = plot(tables, temporary, figure_title(axes), options.figure);
        if (interrupted || !written || figure_status != 0) combined.drop(picture);
      }
      combined.commit();
      if (!options.quiet)
        std::cerr << "slidespec: wrote " << options.out << ".tsv, .json"
                  << (options.no_plot || interrupted || !written ? ""
                      : figure_status == 0                       ? ", ." + options.figure.format
                                                                 : " (the figure failed: none written)")
                  << " (all " << runs.size() << " runs)\n";
    }
    if (interrupted) return stopped_status();
    if (!written || figure_status != 0) return kNotWritten;
    return stationary ? 0 : kNotWhatItClaims;
  }

 private:
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
};

}  // namespace

std::unique_ptr<Command> make_sweep_command(CLI::App& app, const Context& context) {
  return std::make_unique<SweepCommand>(app, context);
}

}  // namespace slidespec::cli
