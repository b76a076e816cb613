// The theory line of a figure: the exact theory of a table's model, recomputed on a fine
// grid from the parameters in the table's '#' lines.
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "cli/plot.hpp"
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
  std::ifstream in(path);
  TableModel model;
  ParameterBuilder builder("reference");
  bool named_model = false, has_v = false;
  std::vector<std::pair<std::string, std::string>> metadata;
  std::size_t omega_column = 0;  // by name in the column line ("# omega<TAB>C_x...")
  for (std::string line; std::getline(in, line);) {
    if (line.find('\t') != std::string::npos && line.find_first_of("0123456789") != 0 &&
        line.find("omega") != std::string::npos) {
      std::istringstream names(line.rfind("#", 0) == 0 ? line.substr(1) : line);
      std::size_t index = 0;
      for (std::string name; names >> name; ++index)
        if (name == "omega") omega_column = index;
      continue;
    }
    if (line.rfind("#", 0) == 0) {
      const auto equals = line.find(" = ");
      if (equals == std::string::npos) continue;
      std::string key = line.substr(1, equals - 1);
      key.erase(0, key.find_first_not_of(' '));
      std::string value = line.substr(equals + 3);
      value = value.substr(0, value.find("  #"));
      metadata.emplace_back(key, value);
      named_model |= key == "N";
      has_v |= key == "v";
      continue;
    }
    std::istringstream fields(line);
    double omega = 0;
    for (std::size_t index = 0; index <= omega_column; ++index)
      if (!(fields >> omega)) omega = 0;
    if (!(omega > 0)) continue;
    model.omega_low = model.omega_low > 0 ? std::min(model.omega_low, omega) : omega;
    model.omega_high = std::max(model.omega_high, omega);
  }
  if (!named_model || !(model.omega_high > 0)) return model;
  for (const auto& [key, value] : metadata) {
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

}  // namespace

std::pair<std::vector<double>, std::vector<double>> fine_theory_of_table(const std::string& path) {
  const TableModel model = read_table_model(path);
  if (!model.parameters) return {};
  std::vector<double> omegas =
      log_spaced_omegas(model.omega_low, model.omega_high * (1 + 1e-9), kTheoryPointsPerDecade);
  if (omegas.empty() || omegas.back() < model.omega_high) omegas.push_back(model.omega_high);
  std::vector<double> spectrum = exact_spectrum(*model.parameters, omegas);
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
    const std::vector<double> values = exact_spectrum(*model.parameters, added);
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

}  // namespace slidespec::cli
