// The theory line of a figure: the exact theory of a table's model, recomputed on a fine
// grid from the parameters in the table's '#' lines; and the figure of a run's table,
// drawn here with cairo (src/figure/).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "cli/plot.hpp"
#include "figure/spectrum_figure.hpp"
#include "figure/text.hpp"
#include "io/table_reader.hpp"
#include "util/numbers.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::cli {

namespace {

// Where log C bends by more than this (decades, second difference) the grid is halved.
constexpr double kBendTolerance = 0.01;
constexpr int kRefinements = 14;
constexpr std::size_t kMostPoints = 40000;

struct TableModel {
  std::optional<Parameters> parameters;
  double omega_low = 0, omega_high = 0;
};

TableModel read_table_model(const std::string& path) {
  TableModel model;
  io::Table table;
  try {
    table = io::read_table(path);
  } catch (const std::runtime_error&) {
    return model;
  }
  for (double omega : table.column("omega")) {
    if (!(omega > 0)) continue;
    model.omega_low = model.omega_low > 0 ? std::min(model.omega_low, omega) : omega;
    model.omega_high = std::max(model.omega_high, omega);
  }
  if (!table.value("N") || !(model.omega_high > 0)) return model;
  const bool has_v = table.value("v").has_value();
  ParameterBuilder builder("reference");
  for (const auto& [key, value] : table.metadata) {
    if (key == "eta1" && has_v) continue;  // derived from v
    try {
      builder.set(key, value);
    } catch (const InputError&) {
      // Not a parameter (seed, omega_c, ...): the table's other facts.
    }
  }
  try {
    model.parameters = builder.build();
  } catch (const InputError&) {
  }
  return model;
}

/// exact_spectrum over `omegas`, half on a second thread: a run's figure waits for this
/// line once the run's threads are done, with both cores free.
std::vector<double> exact_spectrum_on_two_threads(const Parameters& p, const std::vector<double>& omegas) {
  constexpr std::size_t kWorthAThread = 16;  // a solve takes ~10 us, a thread's start ~50 us
  if (omegas.size() < kWorthAThread) return exact_spectrum(p, omegas);
  const std::vector<double> low(omegas.begin(), omegas.begin() + static_cast<std::ptrdiff_t>(omegas.size() / 2));
  const std::vector<double> high(omegas.begin() + static_cast<std::ptrdiff_t>(omegas.size() / 2), omegas.end());
  auto upper = std::async(std::launch::async, [&] { return exact_spectrum(p, high); });
  std::vector<double> values = exact_spectrum(p, low);
  const std::vector<double> rest = upper.get();
  values.insert(values.end(), rest.begin(), rest.end());
  return values;
}

}  // namespace

std::pair<std::vector<double>, std::vector<double>> fine_theory_of_table(const std::string& path) {
  const TableModel model = read_table_model(path);
  if (!model.parameters) return {};
  std::vector<double> omegas =
      log_spaced_omegas(model.omega_low, model.omega_high * (1 + 1e-9), kTheoryPointsPerDecade);
  if (omegas.empty() || omegas.back() < model.omega_high) omegas.push_back(model.omega_high);
  std::vector<double> spectrum = exact_spectrum_on_two_threads(*model.parameters, omegas);
  // Halve the grid where log C bends: a resonance narrower than the base grid is found
  // by its neighbours' curvature and resolved within a few halvings.
  for (int round = 0; round < kRefinements && omegas.size() < kMostPoints; ++round) {
    std::vector<double> added;
    for (std::size_t k = 1; k + 1 < omegas.size(); ++k) {
      if (!(spectrum[k - 1] > 0 && spectrum[k] > 0 && spectrum[k + 1] > 0)) continue;
      const double bend = std::log10(spectrum[k + 1]) - 2 * std::log10(spectrum[k]) + std::log10(spectrum[k - 1]);
      if (std::abs(bend) < kBendTolerance) continue;
      added.push_back(std::sqrt(omegas[k - 1] * omegas[k]));
      added.push_back(std::sqrt(omegas[k] * omegas[k + 1]));
    }
    if (added.empty()) break;
    std::sort(added.begin(), added.end());
    added.erase(std::unique(added.begin(), added.end()), added.end());
    const std::vector<double> values = exact_spectrum_on_two_threads(*model.parameters, added);
    std::vector<std::pair<double, double>> merged;
    for (std::size_t k = 0; k < omegas.size(); ++k) merged.emplace_back(omegas[k], spectrum[k]);
    for (std::size_t k = 0; k < added.size(); ++k) merged.emplace_back(added[k], values[k]);
    std::sort(merged.begin(), merged.end());
    omegas.clear();
    spectrum.clear();
    for (const auto& [omega, value] : merged) {
      if (!omegas.empty() && omega <= omegas.back() * (1 + 1e-12)) continue;
      omegas.push_back(omega);
      spectrum.push_back(value);
    }
  }
  return {omegas, spectrum};
}

namespace {

/// A run's table with the columns its figure needs.
io::Table read_run_table(const std::string& path) {
  io::Table table = io::read_table(path);
  if (table.column("omega").empty() || table.column("C_x").empty())
    throw std::runtime_error(path + ": no omega and C_x columns");
  return table;
}

/// '0.0005' -> '5e-4', '30' -> '30': plot_spectra.py's short numbers.
std::string short_number(double value) {
  char text[32];
  if (value != 0 && !(std::abs(value) >= 1e-2 && std::abs(value) < 1e4)) {
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(value))));
    double mantissa = value / std::pow(10.0, exponent);
    mantissa = std::round(mantissa * 100) / 100;
    if (std::abs(mantissa) >= 10) return short_number(std::copysign(1.0, value) * std::pow(10.0, exponent + 1));
    std::snprintf(text, sizeof text, "%ge%d", mantissa, exponent);
  } else {
    std::snprintf(text, sizeof text, "%.4g", value);
  }
  return text;
}

/// 'v', '5e-4' -> 'v = 0.5 mm/s': a parameter with its symbol (parameters.def), in the largest
/// unit that keeps its number at 0.1 or above.
std::string parameter_text(const std::string& key, const std::string& value) {
  static const std::map<std::string, std::vector<std::pair<const char*, double>>> unit_ladders = {
      {"N", {{"", 1}}},
      {"M", {{"kg", 1}, {"g", 1e-3}}},
      {"m", {{"kg", 1}, {"g", 1e-3}, {"mg", 1e-6}}},
      {"k0", {{"N/m", 1}}},
      {"k1", {{"N/m", 1}}},
      {"eta0", {{"1/s", 1}}},
      {"eta1", {{"1/s", 1}}},
      {"v", {{"m/s", 1}, {"mm/s", 1e-3}, {"µm/s", 1e-6}}},
      {"a", {{"m", 1}, {"mm", 1e-3}, {"µm", 1e-6}, {"nm", 1e-9}}},
      {"alpha", {{"", 1}}},
      {"F_drive", {{"N", 1}}},
      {"F_kin", {{"N", 1}}},
      {"k_drive", {{"N/m", 1}}}};
  const ParameterInfo* row = find_parameter(key);
  // A level's key (N_2) is not its row's symbol: written as it is.
  const std::string symbol = row && row->key == key ? row->symbol : figure::literal(key);
  const auto style = unit_ladders.find(key);
  const std::optional<double> number = util::parse_number(value);
  if (!number || style == unit_ladders.end()) return symbol + " = " + figure::literal(value);
  auto [unit, size] = style->second.back();
  for (const auto& [candidate, candidate_size] : style->second)
    if (std::abs(*number) >= 0.1 * candidate_size) {
      unit = candidate;
      size = candidate_size;
      break;
    }
  return symbol + " = " + short_number(*number / size) + (*unit ? std::string(" ") + unit : "");
}

/// The legend entry of a single run: its case and the parameters the paper varies, plus
/// those set by --set (named in its label), marked when incomplete or not stationary.
std::string legend_label(const io::Table& table, const std::string& path) {
  std::string name = table.value("case").value_or(std::filesystem::path(path).filename().string());
  std::vector<std::string> keys = {"N", "v", "a", "alpha"};
  if (const std::optional<std::string> label = table.value("label")) {  // "reference + N=5, alpha=3"
    const std::string& text = *label;
    name = text.substr(0, text.find(" + "));
    if (text.find(" + ") != std::string::npos) {
      std::istringstream changes(text.substr(text.find(" + ") + 3));
      for (std::string change; std::getline(changes, change, ',');) {
        std::string key = change.substr(0, change.find('='));
        key.erase(0, key.find_first_not_of(' '));
        key.erase(key.find_last_not_of(' ') + 1);
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
      }
    }
  }
  std::string parameters;
  for (const std::string& key : keys) {
    const std::optional<std::string> value = table.value(key);
    if (!value) continue;
    parameters += (parameters.empty() ? ": " : ", ") + parameter_text(key, *value);
  }
  std::string text = figure::literal(name) + parameters;
  if (table.value("stationary").value_or("").rfind("false", 0) == 0) text += " (NOT STATIONARY: no spectrum)";
  if (table.value("complete") == "false") text += " (incomplete)";
  return text;
}

// The paper's Fig. 2 peak near 4e4 rad/s is absent from the equations as written (docs/model.md §4).
constexpr double kPeakNoteOmega = 1e4;
const char* const kPeakNote =
    "No peak near 4e4 rad/s: the model's equations overdamp the miniblocks (docs/model.md §4)";

/// A run's table says per point which theory holds (its theory_kind column: 2 second order,
/// 3 quasi-static, both its theory2; 1 the first order; 0 none). The residuals are taken
/// against that theory and left out where none holds; the line is the fine first-order one
/// where that holds, runs through the points' theory2 where a theory beyond it does (the
/// periodic first order's zeros are not the second order's), and breaks where none holds.
/// Returns whether a theory beyond the first order is drawn anywhere.
bool show_only_where_a_theory_holds(const io::Table& table, figure::Spectrum& spectrum) {
  const std::vector<double>& kind = table.column("theory_kind");
  const std::vector<double>& theory2 = table.column("theory2");
  const std::size_t n = spectrum.omega.size();
  if (kind.size() != n || theory2.size() != n) return false;
  auto beyond_first = [&](std::size_t i) { return (kind[i] == 2 || kind[i] == 3) && std::isfinite(theory2[i]); };
  std::vector<std::pair<double, double>> line;
  for (std::size_t j = 0; j < spectrum.line_omega.size(); ++j) {
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (std::fabs(std::log(spectrum.line_omega[j] / spectrum.omega[i])) <
          std::fabs(std::log(spectrum.line_omega[j] / spectrum.omega[nearest])))
        nearest = i;
    if (kind[nearest] == 1) line.emplace_back(spectrum.line_omega[j], spectrum.line_C_x[j]);
  }
  bool any_beyond = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (beyond_first(i)) {
      spectrum.theory[i] = theory2[i];
      line.emplace_back(spectrum.omega[i], theory2[i]);
      any_beyond = true;
    } else if (kind[i] != 1) {
      spectrum.theory[i] = NAN;
      line.emplace_back(spectrum.omega[i], NAN);  // breaks the line
    }
  }
  std::stable_sort(line.begin(), line.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  spectrum.line_omega.clear();
  spectrum.line_C_x.clear();
  for (const auto& [omega, value] : line) spectrum.line_omega.push_back(omega), spectrum.line_C_x.push_back(value);
  return any_beyond;
}

}  // namespace

RunFigure run_figure(const std::string& path, const FigureStyle& style) {
  const io::Table table = read_run_table(path);
  figure::Spectrum spectrum;
  spectrum.label = legend_label(table, path);
  spectrum.omega = table.column("omega");
  spectrum.C_x = table.column("C_x");
  spectrum.standard_error = table.column("stderr");
  spectrum.theory = table.column("theory");
  std::tie(spectrum.line_omega, spectrum.line_C_x) = fine_theory_of_table(path);
  if (spectrum.line_omega.empty()) {  // no model named: the table's own theory column
    spectrum.line_omega = spectrum.omega;
    spectrum.line_C_x = spectrum.theory;
  }
  const bool beyond_first_order = show_only_where_a_theory_holds(table, spectrum);
  // Under a spring the block resonates at omega_resonance, stiffened by k_drive, and the
  // paper's Eq. (1), the constant force's asymptote, lies above its spectrum.
  const std::optional<double> spring_resonance = table.number("omega_resonance");
  const double omega_c = table.number("omega_c").value_or(0);
  spectrum.resonance = spring_resonance.value_or(omega_c);
  if (spring_resonance) spectrum.resonance_label = "*ω*_{res}";
  // Eq. (1) where it applies, v/a << omega << omega_c: from 5 v/a to omega_c/3.
  const std::vector<double>& eq1 = table.column("C_eq1");
  const auto v = table.number("v"), a = table.number("a");
  if (!spring_resonance && !eq1.empty() && v && a && *a > 0 && omega_c > 0)
    for (std::size_t i = 0; i < spectrum.omega.size(); ++i)
      if (spectrum.omega[i] >= 5 * *v / *a && spectrum.omega[i] <= omega_c / 3) {
        spectrum.eq1_omega.push_back(spectrum.omega[i]);
        spectrum.eq1_C_x.push_back(eq1[i]);
      }

  figure::SpectrumFigure drawing;
  if (beyond_first_order) drawing.line_label = "the theory that holds (docs/model.md §7.4)";
  drawing.residuals = !spectrum.theory.empty() && !spectrum.standard_error.empty();
  const double highest = *std::max_element(spectrum.omega.begin(), spectrum.omega.end());
  if (highest > kPeakNoteOmega) drawing.footnote = kPeakNote;
  drawing.spectra.push_back(std::move(spectrum));

  figure::Page page;
  page.height = drawing.residuals ? 6.2 : 5;
  if (!style.size.empty()) std::sscanf(style.size.c_str(), "%lfx%lf", &page.width, &page.height);
  page.dpi = style.dpi;
  page.format = style.format == "pdf"   ? figure::Format::pdf
                : style.format == "svg" ? figure::Format::svg
                                        : figure::Format::png;
  return {std::move(drawing), page};
}

std::string draw_run_figure(const std::string& path, const FigureStyle& style) {
  // The output-set tests (tests/cli/commit_test.sh) stop a run here, its state saved and
  // its outputs not yet written: SLIDESPEC_FIGURE_STALL=FILE writes the pid to FILE and waits.
  if (const char* stall = std::getenv("SLIDESPEC_FIGURE_STALL")) {
    std::ofstream(stall) << getpid() << "\n";
    std::this_thread::sleep_for(std::chrono::minutes(1));
  }
  const RunFigure drawing = run_figure(path, style);
  return figure::draw(drawing.figure, drawing.page).bytes;
}

}  // namespace slidespec::cli
