// `slidespec run`: one simulated spectrum, fresh, resumed from its state, or one part of a
// run split over a job array (--realizations-range, joined by merge).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/command.hpp"
#include "cli/request_options.hpp"
#include "cli/run_and_write.hpp"
#include "io/atomic_file.hpp"
#include "util/numbers.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::cli {

namespace {

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
              const auto seconds = util::parse_number(text);
              return seconds && *seconds > 0 ? std::string() : "need a positive number of seconds (got " + text + ")";
            },
            "S>0"));
    c.add_option("--resume", options_.resume, "continue the run saved in PREFIX.state")
        ->transform(CLI::Validator(
            [](std::string& prefix) {
              // The state's own name (PREFIX.state) means its run as PREFIX does.
              prefix = state_prefix(prefix);
              return std::string();
            },
            ""));
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
    const bool own_state = given("--save-state") && options_.save_state == out + ".state";
    if ((resume.empty() || out != resume) && !own_state) files.output(out + ".state", "--out");
    // Resuming a part whose --save-state was its PREFIX.state names that state twice.
    if (given("--save-state") && (resume.empty() || options_.save_state != resume + ".state"))
      files.output(options_.save_state, "--save-state");
    // A state is an output like the others: F.state is locked as the prefix F, so that no
    // two commands write it at once, nor a part's --save-state the state of a run --out F.
    if (given("--save-state")) files.prefixes.push_back({state_prefix(options_.save_state), "--save-state"});
    // The state resumed is this run's until it ends: a second command resuming it too
    // would spend the work twice and remove it under the first.
    if (!resume.empty() && out != resume) files.prefixes.push_back({resume, "--resume"});
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
                       util::format_number(options.request.duration) + ")");
    if (!options.resume.empty()) return resume(options);
    const Parameters p = model_.build();
    RunSession session(p, options.request, model_.label(p));  // validates before any work
    refuse_state_left_at(options.out, "--out");
    if (given("--save-state") && options.save_state != options.out + ".state")
      refuse_state_of_another_run(options.save_state, nullptr);
    if (context_.writes_outputs()) refuse_state_beyond_free_space(p, options.request, options.out);
    // A warning, not progress: --quiet keeps it, as it keeps a run's stationarity warning.
    if (context_.writes_outputs()) warn_if_no_theory_holds(p);
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

  /// A run saves its state before its outputs: refused at once where even the least state
  /// it can save cannot fit.
  static void refuse_state_beyond_free_space(const Parameters& p, const RunRequest& request, const std::string& out) {
    const double bytes = least_state_bytes(p, request);
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
    if (model_given)
      if (const std::string differs = session.difference(model_.build(), session.request()); !differs.empty())
        throw InputError("--resume: " + options.resume + ".state holds a run" +
                         (session.case_name().empty() ? "" : " of case '" + session.case_name() + "'") +
                         " whose parameters differ (" + differs +
                         "); a resumed run takes its case and parameters from its state: leave --case, --set and "
                         "--params out");
    const std::string differs = session.difference(session.parameters(), request);
    if (!differs.empty()) throw InputError("--resume: " + options.resume + ".state is another run (" + differs + ")");
    if (given("--save-state") && options.save_state != options.resume + ".state" &&
        options.save_state != options.out + ".state")
      refuse_state_of_another_run(options.save_state, &session);
    // Continued under another prefix, the run saves its state there: never over another's.
    if (options.out != options.resume) refuse_state_left_at(options.out, "--out");
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

}  // namespace

std::unique_ptr<Command> make_run_command(CLI::App& app, const Context& context) {
  return std::make_unique<RunCommand>(app, context);
}

}  // namespace slidespec::cli
