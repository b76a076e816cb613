// The subcommands of `slidespec`, one object each: a command declares its options on its
// own CLI11 subcommand, names every file it will read and write once parsed, and runs.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "cli/outputs.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

/// Exit status of a result that is not what it claims (not stationary, inf or nan where
/// a number is claimed): the outputs are written and say so (README).
inline constexpr int kNotWhatItClaims = 3;

/// Where this process stands: its place among MPI ranks and the default thread count.
struct Context {
  const Communicator* communicator = nullptr;  ///< null without MPI (one process)
  int default_threads = 0;                     ///< what --threads 0 (or none) means
  /// Only one process writes files and messages (rank 0).
  bool writes_outputs() const { return communicator == nullptr || communicator->rank() == 0; }
};

/// One subcommand. Constructed before parsing (it adds its options to `app`); after
/// parsing, files() names what it will read and write and run() does the work.
class Command {
 public:
  virtual ~Command() = default;
  /// Its CLI11 subcommand: chosen when `*command.subcommand()` is true.
  CLI::App& subcommand() const { return *subcommand_; }
  /// Every file it reads and writes, from its options alone (no work, no file written).
  /// Bad input throws InputError.
  virtual Files files() const { return {}; }
  /// Its exit status; bad input throws InputError.
  virtual int run() = 0;

 protected:
  explicit Command(CLI::App* subcommand) : subcommand_(subcommand) {}

 private:
  CLI::App* subcommand_;
};

/// The options every model-facing command shares: a case, overrides, a parameter file.
struct ModelOptions {
  std::string case_name = "reference";
  std::vector<std::string> overrides;
  std::string parameter_file;

  void add_to(CLI::App& command);
  Parameters build() const;
  /// What outputs call the run: "reference + N=5, alpha=3" when keys change the case.
  std::string label(const Parameters& p) const;
  /// The parameter file, if any, as an input.
  void add_inputs(Files& files) const;
};

/// "HELP (default VALUE)", the value as a user types it (0.1, 1e5): help text built from
/// the same constants the options start from.
std::string with_default(const std::string& help, double value);

/// Warns on stderr where no theory holds (docs/model.md §7.4: stall, eps beyond the limits).
void warn_if_no_theory_holds(const Parameters& p);

/// Every command of `slidespec`, in the order `slidespec --help` lists them.
std::vector<std::unique_ptr<Command>> make_commands(CLI::App& app, const Context& context);

/// One command each, declared on `app`, for make_commands; each lives in its own file
/// (cli/run_command.cpp, ...), as CLI11's subcom_in_files example has it.
std::unique_ptr<Command> make_cases_command(CLI::App& app);
std::unique_ptr<Command> make_theory_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_run_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_sweep_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_merge_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_plot_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_paper_command(CLI::App& app, const Context& context);
std::unique_ptr<Command> make_analyze_command(CLI::App& app);
std::unique_ptr<Command> make_synth_command(CLI::App& app);

}  // namespace slidespec::cli
