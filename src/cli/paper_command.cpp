// `slidespec paper`: the runs of one of the paper's figures (and the drives figure), and
// the figure; fig6 analyzes a record instead (cli/analyze_command.cpp).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/analyze_command.hpp"
#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "cli/request_options.hpp"
#include "cli/run_and_write.hpp"
#include "cli/sweep.hpp"
#include "io/atomic_file.hpp"
#include "slidespec/run.hpp"
#include "util/suggest.hpp"

namespace slidespec::cli {

namespace {

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
    std::vector<std::optional<RunSession>> continued;
    for (const PaperRun& run : cases) {
      params.push_back(build_case(run.case_name, run.changes));
      validate_request(params.back(), options.request);
      work.push_back(planned_work(params.back(), options.request));
      continued.push_back(state_left(directory_ + "/" + figure_ + "_" + run.name, params.back(), options.request));
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
      RunSession session =
          continued[k] ? std::move(*continued[k]) : RunSession(params[k], singles[k].request, cases[k].case_name);
      session.set_execution(singles[k].request.threads, singles[k].request.simd);
      const RunOutcome outcome = run_and_write(context_, session, singles[k], out);
      tables.push_back(out + ".tsv");
      written = written && outcome.written;
      if (stopped_by_signal(outcome.result)) return stopped_status();
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
  /// The run an interrupted `paper` left in PREFIX.state, continued where it is this run;
  /// another run's state is refused before any work rather than replaced.
  static std::optional<RunSession> state_left(const std::string& prefix, const Parameters& p,
                                              const RunRequest& request) {
    const std::string path = prefix + ".state";
    if (std::error_code ignored; !std::filesystem::exists(path, ignored)) return std::nullopt;
    std::string differs = "not a run state";
    try {
      RunSession left = RunSession::load(io::read_file(path, "--out-dir"));
      differs = left.difference(p, request);
      if (differs.empty()) return left;
    } catch (const InputError&) {
    }
    throw InputError("--out-dir: " + path + " holds another run (" + differs +
                     "); continue it with slidespec run --resume " + prefix + ", or remove it");
  }

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

std::unique_ptr<Command> make_paper_command(CLI::App& app, const Context& context) {
  return std::make_unique<PaperCommand>(app, context);
}

}  // namespace slidespec::cli
