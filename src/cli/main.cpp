// slidespec command line: a thin layer over the core library. Each subcommand is an
// object (cli/command.hpp); main parses, checks the chosen command's files, locks its
// output prefixes and maps what it throws to an exit status.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <thread>

#include "cli/command.hpp"
#ifdef SLIDESPEC_MPI
#include "cli/mpi.hpp"
#endif
#include "cli/suggest.hpp"
#include "io/atomic_file.hpp"
#include "slidespec/options.hpp"
#include "slidespec/stepper.hpp"

using namespace slidespec;

namespace {

/// Flushes standard output; throws WriteError when the system refused a byte of it (a full
/// disk, /dev/full), which a buffered stream would otherwise lose silently at exit.
void flush_standard_output() {
  errno = 0;
  std::cout.flush();
  if (std::cout.good() && std::fflush(stdout) == 0 && std::ferror(stdout) == 0) return;
  throw io::WriteError(std::string("cannot write standard output: ") +
                       (errno != 0 ? std::strerror(errno) : "the stream failed"));
}

/// --help and --version: the text CLI11 prints, then exit 1 when it could not be written.
int print_help_or_version(const CLI::App& app, const CLI::Success& success) {
  const int status = app.exit(success);
  try {
    flush_standard_output();
  } catch (const io::WriteError& e) {
    std::cerr << "slidespec: failed: " << e.what() << "\n";
    return 1;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, as a full disk does with
  // ENOSPC, instead of killing the process between a temporary and its rename.
  std::signal(SIGXFSZ, SIG_IGN);
  // A shell script's background job starts with SIGINT ignored: an interrupt must still end
  // the commands that hold nothing to save (analyze, synth, theory), as run's handler does its
  // work, and leave no lock file behind. Their outputs are written as a set or not at all.
  io::remove_locks_on_signals();
  cli::Context context;
#ifdef SLIDESPEC_MPI
  cli::MpiWorld mpi(argc, argv);
  if (mpi.size() > 1) context.communicator = &mpi;
  // Ranks on one machine share its cores.
  context.default_threads = std::max(1, resolve_threads(0) / mpi.ranks_on_this_node());
#endif
  CLI::App app{"slidespec: power spectra of frictional sliding noise (Xu, Zhou, Persson model)"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", SLIDESPEC_VERSION);
  const auto commands = cli::make_commands(app, context);
  cli::require_whole_numbers(app);
  cli::require_decimal_numbers(app);
  cli::declare_option_rules(app);
  const bool speaks = context.writes_outputs();
  try {
    app.parse(argc, argv);
    for (const auto& command : commands) {
      if (!command->subcommand()) continue;
      cli::refuse_empty_values(command->subcommand());
      cli::refuse_repeated_keys(command->subcommand());
      const cli::Files files = command->files();
      cli::check_files(files);
      std::vector<std::string> prefixes;
      for (const cli::NamedFile& prefix : files.prefixes) prefixes.push_back(prefix.path);
      const io::OutputLock lock(speaks ? prefixes : std::vector<std::string>{});
      const int status = command->run();
      flush_standard_output();
      return status;
    }
    if (speaks) std::cout << app.help();  // bare `slidespec`: what it can do
    flush_standard_output();
    return 0;
  } catch (const CLI::Success& e) {  // --help, --version
    return print_help_or_version(app, e);
  } catch (const CLI::ParseError& e) {
    const std::string unknown = cli::unknown_argument(app, argc, argv);
    if (speaks)
      std::cerr << "slidespec: error: " << (unknown.empty() ? cli::worded_parse_error(app, e) : unknown) << "\n";
    return 2;
  } catch (const InputError& e) {
    if (speaks) std::cerr << "slidespec: error: " << worded(e.what(), FrontEnd::command_line) << "\n";
    return 2;
  } catch (const std::exception& e) {
    // Every size is checked against its input first, so running out of memory is a
    // machine too small for the work: a failure while working (1), not bad input (2).
    if (dynamic_cast<const std::bad_alloc*>(&e))
      std::cerr << "slidespec: failed: out of memory: the work needs more than this machine has\n";
    else
      std::cerr << "slidespec: failed: " << worded(e.what(), FrontEnd::command_line) << "\n";
#ifdef SLIDESPEC_MPI
    // The other ranks may be waiting in a collective this rank will never reach.
    if (mpi.size() > 1) mpi.abort(1);
#endif
    return 1;
  }
}
