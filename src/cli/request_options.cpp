// The request options of the simulating commands, declared once.
#include "cli/request_options.hpp"

#include "util/numbers.hpp"
#include "slidespec/simd.hpp"

namespace slidespec::cli {

void RequestOptions::add_to(CLI::App& command) {
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
          "shadow: each realization's linear shadow as a control variate (docs/run.md); off: without it, on "
          "the forcing control variate alone (default shadow)")
      ->type_name("shadow|off");
  command.add_option("--threads", request.threads, "threads (default, or 0: all cores)");
  command
      .add_option("--work-budget", request.work_budget,
                  with_default("most realization-steps a run may plan", kDefaultWorkBudget))
      ->check(CLI::Validator(
          [](const std::string& text) {
            // 0 reads as "the default budget": refused rather than silently replaced.
            const auto steps = util::parse_number(text);
            return steps && *steps > 0 ? std::string()
                                       : "need a positive number of realization-steps (got " + text + ")";
          },
          "STEPS>0"));
  command.add_option("--simd", simd, simd_path_names() + " (default auto)");
}

void RequestOptions::add_sampling_to(CLI::App& command) {
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

RunRequest RequestOptions::resolved(const Context& context) const {
  RunRequest r = request;
  r.simd = parse_simd_path(simd);
  resolve_simd_path(r.simd);
  if (r.threads == 0) r.threads = context.default_threads;
  return r;
}

}  // namespace slidespec::cli
