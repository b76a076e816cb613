// `slidespec theory`: the exact first-order spectrum (and the theory beyond it) as a table.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/theory.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

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
    // A solve over millions of blocks takes a minute per 10^7 with nothing to show meanwhile.
    if (const double bytes = exact_spectrum_bytes(p); bytes > 1e9)
      std::cerr << "slidespec: theory: solving the full structure over every block (about "
                << util::format_number(std::ceil(bytes / 1e8) / 10) << " GB and a minute per 10^7 blocks)\n";
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
      // A comma with nothing on one side is a value left out, not a separator to skip.
      std::string compact;
      for (char c : line)
        if (!std::isspace(static_cast<unsigned char>(c))) compact += c;
      if (!compact.empty() &&
          (compact.front() == ',' || compact.back() == ',' || compact.find(",,") != std::string::npos))
        throw InputError(source + (from_file ? ": line " + std::to_string(line_number) : std::string()) +
                         ": an empty value between commas");
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream words(line);
      for (std::string word; words >> word;) {
        std::string problem;
        const double omega = util::parse_decimal(word, problem).value_or(0);
        const std::string where = source + (from_file ? ": line " + std::to_string(line_number) : std::string());
        if (problem.find("smallest normal") != std::string::npos)
          throw InputError(where + ": " + problem + ", not an omega in rad/s");
        if (!(omega > 0)) throw InputError(where + ": '" + word + "' is not a positive omega in rad/s");
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

}  // namespace

std::unique_ptr<Command> make_theory_command(CLI::App& app, const Context&) {
  return std::make_unique<TheoryCommand>(app);
}

}  // namespace slidespec::cli
