// slidespec command line: a thin layer over the core library.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/theory.hpp"

namespace {

using namespace slidespec;

/// The options every model-facing command shares: a case, overrides, a parameter file.
struct ModelOptions {
  std::string case_name = "reference";
  std::vector<std::string> overrides;
  std::string parameter_file;

  void add_to(CLI::App& command) {
    command.add_option("--case", case_name, "named case (see 'slidespec cases')");
    command.add_option("--set", overrides, "override a parameter, KEY=VALUE (repeatable)");
    command.add_option("--params", parameter_file, "JSON file of parameter overrides");
  }

  Parameters build() const {
    ParameterBuilder builder(case_name);
    if (!parameter_file.empty())
      for (const auto& assignment : read_parameter_file(parameter_file)) builder.set(assignment);
    for (const auto& assignment : overrides) builder.set(assignment);
    return builder.build();
  }
};

std::string format_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9e", x);
  return text;
}

std::string header_lines(const Parameters& p) {
  std::ostringstream out;
  out << "# slidespec " << SLIDESPEC_VERSION << "\n";
  for (const auto& [key, value] : describe(p)) out << "# " << key << " = " << value << "\n";
  const Landmarks l = landmarks(p);
  out << "# renewal_rate = " << format_number(l.renewal_rate) << "  # v/a [1/s]\n"
      << "# omega_c = " << format_number(l.omega_c) << "  # sqrt(N k0/M) [rad/s]\n"
      << "# diffusion_D = " << format_number(l.diffusion) << "  # [m^2/s], C_x -> D/(pi omega^2)\n"
      << "# eq1_prefactor = " << format_number(l.eq1_prefactor)
      << "  # [m^2 rad^4/s^3], C_x ~ prefactor/omega^4 for v/a << omega << omega_c\n"
      << "# coupling_eps = " << format_number(l.coupling_eps) << "\n";
  return out.str();
}

void warn_if_outside_first_order(const Parameters& p) {
  const Landmarks l = landmarks(p);
  if (l.forces_can_stall)
    std::cerr << "slidespec: warning: alpha F_kin >= 2 (F_drive - F_kin): the random forces can "
                 "stall the block; the first-order theory does not hold here\n";
  else if (l.coupling_eps > 0.3)
    std::cerr << "slidespec: warning: eps = " << l.coupling_eps
              << " > 0.3: the first-order theory does not hold here\n";
}

int command_cases() {
  for (const Case& c : cases()) {
    const Parameters p = ParameterBuilder(c.name).build();
    std::cout << c.name << "\t" << c.description << "\n ";
    for (const auto& [key, value] : describe(p)) std::cout << " " << key << "=" << value;
    std::cout << "\n";
  }
  return 0;
}

struct TheoryOptions {
  double omega_min = 0.1, omega_max = 1e5;
  int points_per_decade = 8;
  std::string out;
};

int command_theory(const ModelOptions& model, const TheoryOptions& options) {
  const Parameters p = model.build();
  const std::vector<double> omegas =
      log_spaced_omegas(options.omega_min, options.omega_max, options.points_per_decade);
  if (!options.out.empty()) io::check_output_prefix(options.out);
  warn_if_outside_first_order(p);
  const std::vector<double> spectrum = exact_spectrum(p, omegas);

  std::ostringstream table;
  table << header_lines(p) << "# columns: omega [rad/s], C_x [m^2 s] exact first-order theory, "
                              "C_eq1 [m^2 s] the paper's Eq. (1)\n"
        << "omega\tC_x\tC_eq1\n";
  for (size_t k = 0; k < omegas.size(); ++k)
    table << format_number(omegas[k]) << "\t" << format_number(spectrum[k]) << "\t"
          << format_number(eq1_asymptote(p, omegas[k])) << "\n";
  if (options.out.empty()) std::cout << table.str();
  else io::write_atomically(options.out + ".tsv", table.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slidespec: power spectra of frictional sliding noise (Xu, Zhou, Persson model)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SLIDESPEC_VERSION);

  CLI::App* cases_command = app.add_subcommand("cases", "list the named cases and their parameters");

  ModelOptions theory_model;
  TheoryOptions theory_options;
  CLI::App* theory_command =
      app.add_subcommand("theory", "exact first-order spectrum C_x(omega) of MODEL section 4");
  theory_model.add_to(*theory_command);
  theory_command->add_option("--omega-min", theory_options.omega_min, "lowest omega [rad/s]");
  theory_command->add_option("--omega-max", theory_options.omega_max, "highest omega [rad/s]");
  theory_command->add_option("--points", theory_options.points_per_decade, "points per decade");
  theory_command->add_option("--out", theory_options.out, "write PREFIX.tsv instead of stdout");

  try {
    app.parse(argc, argv);
    if (*cases_command) return command_cases();
    if (*theory_command) return command_theory(theory_model, theory_options);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "slidespec: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "slidespec: failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
