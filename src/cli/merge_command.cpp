// `slidespec merge`: the parts of a run split over a job array, as the whole run.
#include <memory>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/run_and_write.hpp"
#include "io/atomic_file.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

namespace {

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

}  // namespace

std::unique_ptr<Command> make_merge_command(CLI::App& app, const Context& context) {
  return std::make_unique<MergeCommand>(app, context);
}

}  // namespace slidespec::cli
