// The options the model-facing commands share, analyze and synth as commands, and the
// list of every command.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cli/analyze.hpp"
#include "cli/analyze_many.hpp"
#include "cli/command.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"
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

namespace {

/// analyze and synth, whose options and work live in AnalysisCommands: the files they
/// name, read from their parsed options.
class AnalysisCommand final : public Command {
 public:
  AnalysisCommand(CLI::App& subcommand, std::shared_ptr<const AnalysisCommands> commands)
      : Command(&subcommand), commands_(std::move(commands)) {}

  Files files() const override {
    Files files;
    const CLI::App& c = subcommand();
    if (c.get_name() == "analyze" && many_records(given("file"))) {
      many_files(files);
    } else if (c.get_name() == "analyze") {
      for (const std::string& path : given("file")) files.input(path, "analyze");
      files.outputs_of(one("--out", "analysis"), "--out", {".tsv", ".json", "." + one("--format", "png")});
    } else {
      for (const std::string& path : given("--params")) files.json_input(path, "--params");
      files.outputs_of(one("--out", "record"), "--out", {".csv"});
    }
    return files;
  }

  int run() override {
    // A sampling interval of 0 reads as "from the time column": refused when given.
    for (const std::string& dt : given("--dt"))
      if (const auto seconds = util::parse_number(dt); !seconds || !(*seconds > 0) || !std::isnormal(*seconds))
        throw InputError("--dt: need a positive sampling interval in seconds, at least " +
                         util::format_number(std::numeric_limits<double>::min()) + " (got " + dt + ")");
    return commands_->run().value_or(0);
  }

 private:
  /// analyze A B C: each record's outputs and the combined table. A record that cannot be
  /// read is not refused here but reported as the records are analysed, and the rest go on;
  /// the records that can are inputs, which no output may replace.
  void many_files(Files& files) const {
    const std::string out = one("--out", "analysis");
    const std::vector<std::string> records = expand_record_paths(given("file"));
    const std::vector<std::string> prefixes = record_prefixes(out, records);
    for (std::size_t k = 0; k < records.size(); ++k) {
      std::error_code ignored;
      if (std::filesystem::is_regular_file(records[k], ignored) && access(records[k].c_str(), R_OK) == 0)
        files.input(records[k], "analyze");
      files.outputs_of(prefixes[k], "--out", {".tsv", ".json", "." + one("--format", "png")});
    }
    files.outputs_of(out, "--out", {".tsv", ".json"});
  }

  std::vector<std::string> given(const std::string& name) const {
    const CLI::Option* option = subcommand().get_option_no_throw(name);
    return option == nullptr || option->count() == 0 ? std::vector<std::string>{} : option->results();
  }
  std::string one(const std::string& name, const std::string& fallback) const {
    const auto values = given(name);
    return values.empty() ? fallback : values.back();
  }

  std::shared_ptr<const AnalysisCommands> commands_;
};

}  // namespace

void add_analysis_commands(CLI::App& app, const Context&, std::vector<std::unique_ptr<Command>>& commands) {
  const auto analysis = std::make_shared<const AnalysisCommands>(app);
  for (const char* name : {"analyze", "synth"})
    commands.push_back(std::make_unique<AnalysisCommand>(*app.get_subcommand(name), analysis));
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
  add_analysis_commands(app, context, commands);
  return commands;
}

}  // namespace slidespec::cli
