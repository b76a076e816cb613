// What the simulating commands (run, merge, sweep, paper) share: how one run is advanced,
// checkpointed and written, its exit status, and the stop a signal requests.
// A finished run's state stays on disk until its whole output set is committed: a crash
// or a full disk at any moment after the work leaves a run that `run --resume` finishes.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "cli/progress.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

/// Exit status of a run whose outputs could not all be written (its state is kept).
inline constexpr int kNotWritten = 1;

/// SIGINT and SIGTERM from now on ask the running session to stop at its next check.
void catch_stop_signals();

/// Refuses (InputError naming `option`) to start a run at `prefix` while PREFIX.state holds
/// work left there: an interrupted run, a finished one whose outputs were never written, or
/// a finished part; each says how to go on with it.
void refuse_state_left_at(const std::string& prefix, const std::string& option);
/// Whether a signal stopped the run that came to `result` before its end.
bool stopped_by_signal(const RunResult& result);
/// Whether SIGINT or SIGTERM has asked to stop since catch_stop_signals.
bool stop_asked();
/// The exit status of a command a signal stopped: 128 + the signal.
int stopped_status();

/// How one run writes: its outputs, figure, checkpoints and place in a shared bar.
struct RunOptions {
  RunRequest request;
  std::string out = "spectrum";
  bool quiet = false;
  bool no_plot = false;
  double checkpoint_every = 0;  // [s]; 0 = no periodic checkpoints
  std::string resume;           // PREFIX of a run to continue from PREFIX.state
  std::string save_state;       // where to save the finished part
  std::string continue_with;    // how an interrupted run goes on; "" = slidespec run --resume OUT
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
void share_progress(std::vector<RunOptions>& runs, const std::vector<double>& work, Progress& progress);

/// Says on stderr that the run written to `out` is not stationary, when it is not.
void warn_if_not_stationary(const RunResult& result, const std::string& out);

/// What a run came to: its result, and whether its whole output set is on disk.
struct RunOutcome {
  RunResult result;
  bool written = true;
};

/// The exit status of a single run's outcome.
int exit_status(const RunOutcome& outcome);

/// A point whose estimate, error or theory is inf or nan claims no number: the run is
/// then marked as not what it claims (stationary = false with the reason, exit status 3).
void mark_if_not_numbers(RunResult& result);

/// Writes PREFIX.tsv, .json (and the figure) for a session's result as one set and says
/// what it wrote. False, with a message, when any part of the set could not be written
/// (then none of it was: a figure that cannot be drawn keeps the set back too).
bool write_outputs(const Context& context, const RunSession& session, const RunResult& result,
                   const RunOptions& options, const std::string& out);

/// Advances a session to its end (or an interrupt), checkpointing to PREFIX.state, and
/// writes its outputs. Commit, then forget: the finished run is saved to PREFIX.state
/// before its outputs are written and removed only once all of them are on disk, so a
/// crash or a failed write leaves a state that `run --resume PREFIX` finishes.
RunOutcome run_and_write(const Context& context, RunSession& session, const RunOptions& options,
                         const std::string& out);

}  // namespace slidespec::cli
