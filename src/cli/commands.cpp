// The model commands (cases, theory), the options they share with the simulating
// commands, and the list of every command.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/analyze.hpp"
#include "cli/command.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::cli {

void ModelOptions::add_to(CLI::App& command) {
  command.add_option("--case", case_name, "named case (see 'slidespec cases')");
  command.add_option("--set", overrides, "override a parameter, KEY=VALUE (repeatable)");
  command.add_option("--params", parameter_file, "JSON file of parameter overrides");
}

Parameters ModelOptions::build() const {
  ParameterBuilder builder(case_name);
  if (!parameter_file.empty())
    for (const auto& assignment : read_parameter_file(parameter_file)) builder.set(assignment);
  for (const auto& assignment : overrides) builder.set(assignment);
  return builder.build();
}

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

class CasesCommand final : public Command {
 public:
  explicit CasesCommand(CLI::App& app)
      : Command(app.add_subcommand("cases", "list the named cases and their parameters")) {}

  int run() override {
    for (const Case& c : cases()) {
      const Parameters p = ParameterBuilder(c.name).build();
      std::cout << c.name << "\t" << c.description << "\n ";
      for (const auto& [key, value] : describe(p)) std::cout << " " << key << "=" << value;
      std::cout << "\n";
    }
    return 0;
  }
};

// The exact mean speed and low-frequency diffusion beyond first order, where computed
// (below the stall boundary, one touching level).
std::string long_time_line(const Parameters& p) {
  if (p.drive == Drive::spring) return "";  // V = v and D = 0 exactly: in the metadata lines
  if (landmarks(p).forces_can_stall) return "";
  int touching_levels = 0;
  for (int l = 1; l <= p.levels; ++l) touching_levels += p.touches(l) ? 1 : 0;
  if (touching_levels != 1) return "";
  const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
  const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
  return "# beyond first order (docs/model.md §7): mean speed V = " + util::format_number(exact.mean_speed) +
         " m/s, diffusion D = " + util::format_number(exact.diffusion) + " m^2/s (first order " +
         util::format_number(first.diffusion) + "), C_x -> D / (pi omega^2) below v/a\n";
}

class TheoryCommand final : public Command {
 public:
  explicit TheoryCommand(CLI::App& app)
      : Command(app.add_subcommand("theory", "exact first-order spectrum C_x(omega) (docs/model.md §4)")) {
    CLI::App& c = subcommand();
    model_.add_to(c);
    const RunRequest defaults;
    c.add_option("--omega-min", omega_min_, with_default("lowest omega [rad/s]", defaults.omega_min));
    c.add_option("--omega-max", omega_max_, with_default("highest omega [rad/s]", defaults.omega_max));
    c.add_option("--points", points_per_decade_, with_default("points per decade", defaults.points_per_decade));
    auto* omega_list =
        c.add_option("--omega", omega_list_, "these omegas [rad/s], comma-separated, instead of the log grid");
    c.add_option("--omega-file", omega_file_, "omegas [rad/s] from a file (one or more a line, '#' comments)")
        ->excludes(omega_list);
    c.add_option("--order", order_,
                 "2: add C_x2, the theory beyond first order that theory_kind names (the second order, or the "
                 "quasi-static spectrum beyond its limit; one touching level, a constant force)");
    c.add_option("--out", out_, "write PREFIX.tsv instead of stdout");
  }

  Files files() const override {
    Files files;
    model_.add_inputs(files);
    if (!omega_file_.empty()) files.input(omega_file_, "--omega-file");
    if (subcommand().count("--out") > 0) files.outputs_of(out_, "--out", {".tsv"});
    return files;
  }

  int run() override {
    const Parameters p = model_.build();
    const std::vector<double> omegas = theory_omegas();
    check_theory_omegas(p, omegas);
    if (order_ != 1 && order_ != 2) throw InputError("order: need 1 or 2");
    // Built before any work so that a model it does not cover is refused at once.
    const BeyondFirstOrder beyond = order_ == 2 ? theory_beyond_first_order(p) : BeyondFirstOrder{};
    const std::function<double(double)>& second = beyond.C_x;
    const bool quasi_static = beyond.quasi_static;
    if (!out_.empty()) io::check_output_prefix(out_);
    warn_if_no_theory_holds(p);
    const std::vector<double> spectrum = exact_spectrum(p, omegas);

    std::ostringstream table;
    const bool spring = p.drive == Drive::spring;
    table << io::metadata_lines(p, model_.label(p)) << long_time_line(p)
          << "# columns: omega [rad/s], C_x [m^2 s] exact first-order theory, "
             "C_eq1 [m^2 s] the paper's Eq. (1)"
          << (quasi_static ? ", C_x2 [m^2 s] the quasi-static spectrum (docs/model.md §7.5)"
              : second     ? ", C_x2 [m^2 s] the second-order theory (docs/model.md §7)"
                           : "")
          << (spring ? ", C_F_spring [N^2 s] the spring's force spectrum k_drive^2 C_x" : "") << "\n"
          << "# omega\tC_x\tC_eq1" << (second ? "\tC_x2" : "") << (spring ? "\tC_F_spring" : "") << "\n";
    std::size_t not_numbers = 0;  // values beyond a double's range or not computed (inf, nan)
    double first_omega = 0;
    for (size_t k = 0; k < omegas.size(); ++k) {
      const double eq1 = eq1_asymptote(p, omegas[k]);
      const double c2 = second ? second(omegas[k]) : 0;
      table << util::format_number(omegas[k]) << "\t" << util::format_number(spectrum[k]) << "\t"
            << util::format_number(eq1);
      if (second) table << "\t" << util::format_number(c2);
      if (spring) table << "\t" << util::format_number(spring_force_spectrum(p, spectrum[k]));
      table << "\n";
      if (!std::isfinite(spectrum[k]) || !std::isfinite(eq1) || !std::isfinite(c2)) {
        if (not_numbers++ == 0) first_omega = omegas[k];
      }
    }
    if (out_.empty())
      std::cout << table.str();
    else
      io::write_atomically(out_ + ".tsv", table.str());
    if (not_numbers == 0) return 0;
    std::cerr << "slidespec: warning: " << not_numbers
              << " row(s) hold inf or nan (the first at omega = " << util::format_number(first_omega)
              << " rad/s): beyond the range of a double or of the solve; not a spectrum there (exit status 3)\n";
    return kNotWhatItClaims;
  }

 private:
  /// The frequencies theory is asked for: a list, a file, or the log grid.
  std::vector<double> theory_omegas() const {
    if (omega_list_.empty() && omega_file_.empty())
      return log_spaced_omegas(omega_min_, omega_max_, points_per_decade_);
    const bool from_file = !omega_file_.empty();
    const std::string source = from_file ? omega_file_ : "--omega";
    std::string text = from_file ? io::read_file(omega_file_, "--omega-file") : omega_list_;
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte order mark
    // Lines end at LF, CR LF or a CR alone: a '#' comment ends at any of them.
    for (std::size_t at = text.find('\r'); at != std::string::npos; at = text.find('\r', at)) {
      if (at + 1 < text.size() && text[at + 1] == '\n')
        text.erase(at, 1);
      else
        text[at] = '\n';
    }
    std::vector<double> omegas;
    std::istringstream lines(text);
    int line_number = 0;
    for (std::string line; std::getline(lines, line);) {
      ++line_number;
      line = line.substr(0, line.find('#'));
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream words(line);
      for (std::string word; words >> word;) {
        const double omega = util::parse_number(word).value_or(0);
        if (!(omega > 0))
          throw InputError(source + (from_file ? ": line " + std::to_string(line_number) : std::string()) + ": '" +
                           word + "' is not a positive omega in rad/s");
        omegas.push_back(omega);
      }
    }
    if (omegas.empty()) throw InputError(source + ": no omega given");
    return omegas;
  }

  ModelOptions model_;
  double omega_min_ = RunRequest{}.omega_min, omega_max_ = RunRequest{}.omega_max;
  int points_per_decade_ = RunRequest{}.points_per_decade;
  std::string omega_list_;  // "1,2,3" [rad/s], instead of the log grid
  std::string omega_file_;  // one omega a line [rad/s], '#' comments
  int order_ = 1;
  std::string out_;
};

/// analyze and synth, whose options and work live in AnalysisCommands: the files they
/// name, read from their parsed options.
class AnalysisCommand final : public Command {
 public:
  AnalysisCommand(CLI::App& subcommand, std::shared_ptr<const AnalysisCommands> commands)
      : Command(&subcommand), commands_(std::move(commands)) {}

  Files files() const override {
    Files files;
    const CLI::App& c = subcommand();
    if (c.get_name() == "analyze") {
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

std::unique_ptr<Command> make_cases_command(CLI::App& app) { return std::make_unique<CasesCommand>(app); }
std::unique_ptr<Command> make_theory_command(CLI::App& app, const Context&) {
  return std::make_unique<TheoryCommand>(app);
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
