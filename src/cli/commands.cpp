// The options the model-facing commands share, and the list of every command.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "io/tables.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::cli {

void ModelOptions::add_to(CLI::App& command) {
  command.add_option("--case", case_name, "named case (see 'slidespec cases')");
  command.add_option("--set", overrides, "override a parameter, KEY=VALUE (repeatable)");
  command.add_option("--params", parameter_file, "JSON file of parameter overrides");
}

Parameters ModelOptions::build() const { return build_case(case_name, parameter_file, overrides); }

std::string ModelOptions::label(const Parameters& p) const { return io::run_label(case_name, p); }

void ModelOptions::add_inputs(Files& files) const {
  if (!parameter_file.empty()) files.json_input(parameter_file, "--params");
}

std::string with_default(const std::string& help, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  std::string typed = text;
  // 1e+05 and 5e-07 as a user types them: 1e5, 5e-7.
  if (const auto e = typed.find('e'); e != std::string::npos) {
    std::size_t digits = e + 1;
    if (typed[digits] == '+')
      typed.erase(digits, 1);
    else if (typed[digits] == '-')
      ++digits;
    while (typed[digits] == '0' && digits + 1 < typed.size()) typed.erase(digits, 1);
  }
  return help + " (default " + typed + ")";
}

void warn_if_no_theory_holds(const Parameters& p) {
  const TheoryChoice holds = best_theory(p);
  if (holds.kind == TheoryKind::none)
    std::cerr << "slidespec: warning: no theory holds here (theory_kind = none): " << holds.reason << "\n";
}

std::vector<std::unique_ptr<Command>> make_commands(CLI::App& app, const Context& context) {
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(make_cases_command(app));
  commands.push_back(make_theory_command(app, context));
  commands.push_back(make_run_command(app, context));
  commands.push_back(make_sweep_command(app, context));
  commands.push_back(make_merge_command(app, context));
  commands.push_back(make_plot_command(app, context));
  commands.push_back(make_paper_command(app, context));
  commands.push_back(make_analyze_command(app));
  commands.push_back(make_synth_command(app));
  return commands;
}

}  // namespace slidespec::cli
