// How the simulating commands advance, checkpoint and write one run.
#include "cli/run_and_write.hpp"

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/sweep.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

std::atomic<bool> stop_requested{false};
std::atomic<int> stop_signal{0};
extern "C" void request_stop(int signal) {
  stop_signal = signal;
  stop_requested = true;
}

}  // namespace

void catch_stop_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  // A closed terminal or a dropped ssh session: the run is saved as after an interrupt.
  if (!io::hangups_ignored()) std::signal(SIGHUP, request_stop);
}

void refuse_state_left_at(const std::string& prefix, const std::string& option) {
  // A finished run removes its state but for a part, which merge reads, so one left behind
  // is that, or a run this one would orphan.
  if (std::error_code ignored; !std::filesystem::exists(prefix + ".state", ignored)) return;
  std::string held = "an interrupted run; continue it with --resume " + prefix;
  try {
    const RunSession left = RunSession::load(io::read_file(prefix + ".state", option));
    if (left.finished())
      held = left.request().part ? "a finished part of a run; join it with merge"
                                 : "a finished run whose outputs were not written; write them with --resume " + prefix;
  } catch (const InputError&) {
  }
  throw InputError(option + ": " + prefix + ".state holds " + held + ", or remove it to start afresh");
}

bool stopped_by_signal(const RunResult& result) { return !result.complete && stop_requested; }

bool stop_asked() { return stop_requested; }

int stopped_status() { return 128 + stop_signal; }

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

void warn_if_not_stationary(const RunResult& result, const std::string& out) {
  if (!result.stationary)
    std::cerr << "slidespec: warning: " << out << ": not stationary ("
              << worded(result.stationarity, FrontEnd::command_line)
              << "): no spectrum exists here; the table is marked stationary = false (exit status 3)\n";
}

int exit_status(const RunOutcome& outcome) {
  if (stopped_by_signal(outcome.result)) return stopped_status();
  if (!outcome.written) return kNotWritten;
  return outcome.result.stationary ? 0 : kNotWhatItClaims;
}

void mark_if_not_numbers(RunResult& result) {
  for (const RunPoint& point : result.points)
    if (!std::isfinite(point.C_x) || !std::isfinite(point.standard_error) || !std::isfinite(point.theory)) {
      result.stationary = false;
      result.stationarity = "the point at omega = " + util::format_number(point.omega) +
                            " rad/s holds inf or nan: beyond the range of a double";
      return;
    }
}

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
    std::cerr << "slidespec: error: " << worded(e.what(), FrontEnd::command_line) << "\n";
    return false;
  }
  if (options.quiet) return true;
  std::cerr << "slidespec: "
            << (result.complete     ? "wrote "
                : result.stationary ? "interrupted; wrote what accumulated to "
                                    : "stopped; wrote what accumulated to ")
            << out << ".tsv, .json" << (options.no_plot ? "" : ", ." + options.figure.format) << " ("
            << result.points.size() << " points, "
            << (result.points.empty() ? std::string("none measured yet")
                                      : "largest relative error " + util::format_number(result.reached_precision) +
                                            ", measured mean speed " + util::format_number(result.mean_speed) + " m/s")
            << ", " << result.wall_seconds << " s)\n";
  const RunRequest& request = session.request();
  if (result.complete && result.reached_precision > request.precision && request.duration == 0 &&
      request.realizations == 0)
    std::cerr << "slidespec: warning: the precision " << request.precision
              << " was not reached within the work budget of a sub-band; the table says what was\n";
  return true;
}

namespace {

/// A run resumed from PREFIX.state into another --out has finished there, its outputs
/// written, or was interrupted again and saved as OUT.state: the checkpoint it was resumed
/// from holds no more than they do, and left behind it would refuse the next fresh run at
/// PREFIX. A part's state stays: merge may read it.
void remove_resumed_state(const RunOptions& options, const std::string& out, const std::string& now_in) {
  const std::string state_path = out + ".state";
  if (options.resume.empty()) return;
  const std::string resumed = options.resume + ".state";
  std::error_code ignored;
  if (std::filesystem::equivalent(resumed, state_path, ignored) || !std::filesystem::exists(resumed, ignored)) return;
  io::remove_durably(resumed);
  if (!options.quiet) std::cerr << "slidespec: removed " << resumed << ": its run is now in " << now_in << "\n";
}

}  // namespace

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
      std::cerr << "slidespec: saved the run to " << state_path << "; continue it with: "
                << (options.continue_with.empty()
                        ? "slidespec run --resume " + out +
                              (options.save_state.empty() ? "" : " --save-state " + options.save_state)
                        : options.continue_with)
                << "\n";
    if (!finished && !session.request().part) remove_resumed_state(options, out, state_path);
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
    if (outcome.written && !part_of_a_run) io::remove_durably(state_path);
    if (outcome.written && !session.request().part) remove_resumed_state(options, out, out + "'s outputs");
    if (!outcome.written)
      std::cerr << "slidespec: the finished run is kept in " << state_path
                << "; write its outputs with: slidespec run --resume " << out << (options.no_plot ? " --no-plot" : "")
                << "\n";
  }
  if (writes) warn_if_not_stationary(outcome.result, out);
  return outcome;
}

}  // namespace slidespec::cli
