// The theory line of a figure (src/cli/figure.cpp): the exact theory of a table's model on
// at least 64 points per decade, refined until the resonance at omega_c is drawn at its
// true height. The true peak is found here independently, by golden-section search.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "cli/plot.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {
namespace {

std::string write_table(const Parameters& p, const std::string& label, double omega_min, double omega_max) {
  const std::string path = testing::TempDir() + "/figure_test_" + std::to_string(p.N) + ".tsv";
  std::ofstream out(path);
  out << io::metadata_lines(p, label) << "# omega\tC_x\n";
  for (double omega : log_spaced_omegas(omega_min, omega_max, 8))
    out << util::format_number(omega) << "\t" << util::format_number(exact_spectrum(p, {omega})[0]) << "\n";
  return path;
}

/// The largest C_x near omega_c, by golden-section search on log omega.
double true_peak(const Parameters& p, double omega_c) {
  double low = std::log(omega_c * 0.9), high = std::log(omega_c * 1.1);
  const double golden = (std::sqrt(5.0) - 1) / 2;
  auto value = [&](double u) { return exact_spectrum(p, {std::exp(u)})[0]; };
  for (int k = 0; k < 200; ++k) {
    const double a = high - golden * (high - low), b = low + golden * (high - low);
    (value(a) > value(b) ? high : low) = value(a) > value(b) ? b : a;
  }
  return value(0.5 * (low + high));
}

TEST(FigureTheory, FineGridAndResolvedResonance) {
  for (const char* n : {"30", "100"}) {
    const Parameters p = ParameterBuilder("reference").set("N", n).build();
    const std::string path = write_table(p, "reference", 0.1, 1e5);
    const auto [omegas, spectrum] = cli::fine_theory_of_table(path);
    ASSERT_FALSE(omegas.empty());
    EXPECT_NEAR(omegas.front(), 0.1, 1e-9);
    EXPECT_NEAR(omegas.back(), 1e5, 1e-4);
    // At least 64 points in every decade.
    for (double decade = -1; decade < 5; ++decade) {
      const auto count = std::count_if(omegas.begin(), omegas.end(), [&](double w) {
        return w >= std::pow(10.0, decade) && w < std::pow(10.0, decade + 1);
      });
      EXPECT_GE(count, 64) << "decade 1e" << decade << " (N = " << n << ")";
    }
    // The drawn peak is the true one: within 1% of its height.
    const double omega_c = landmarks(p).omega_c;
    const double drawn = *std::max_element(
        spectrum.begin() + (std::lower_bound(omegas.begin(), omegas.end(), omega_c / 1.2) - omegas.begin()),
        spectrum.begin() + (std::lower_bound(omegas.begin(), omegas.end(), omega_c * 1.2) - omegas.begin()));
    EXPECT_NEAR(drawn / true_peak(p, omega_c), 1.0, 0.01) << "N = " << n;
    // Every value is the exact theory at its omega.
    for (std::size_t k = 0; k < omegas.size(); k += 97)
      EXPECT_DOUBLE_EQ(spectrum[k], exact_spectrum(p, {omegas[k]})[0]);
    std::remove(path.c_str());
  }
}

TEST(FigureTheory, TablesWithoutAModelGetNoLine) {
  const std::string path = testing::TempDir() + "/figure_test_plain.tsv";
  std::ofstream(path) << "# omega\tC_x\n1\t1e-10\n10\t1e-14\n";
  EXPECT_TRUE(cli::fine_theory_of_table(path).first.empty());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace slidespec
