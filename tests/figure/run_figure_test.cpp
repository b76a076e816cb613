// A run's table as the figure run and merge draw (src/cli/figure.cpp): its legend, theory
// line, Eq. (1) range, footnote and page, read from a table written as a run writes it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli/plot.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {
namespace {

/// A run-like table: the model's metadata, then omega, C_x (the theory plus 1%), stderr,
/// theory and C_eq1 over 0.1 .. 1e5 rad/s.
std::string write_run_table(const std::string& name, const std::string& label, const std::string& extra_lines,
                            const Parameters& p = ParameterBuilder("reference").build()) {
  const std::string path = testing::TempDir() + "/run_figure_" + name + ".tsv";
  std::ofstream out(path);
  out << io::metadata_lines(p, label) << extra_lines << "# omega\tC_x\tstderr\ttheory\tC_eq1\n";
  const double prefactor = landmarks(p).eq1_prefactor;
  for (const double omega : log_spaced_omegas(0.1, 1e5, 8)) {
    const double theory = exact_spectrum(p, {omega})[0];
    out << util::format_number(omega) << "\t" << util::format_number(1.01 * theory) << "\t"
        << util::format_number(0.02 * theory) << "\t" << util::format_number(theory) << "\t"
        << util::format_number(prefactor / std::pow(omega, 4)) << "\n";
  }
  return path;
}

TEST(RunFigure, ShowsTheTableItsTheoryAndItsLandmarks) {
  const std::string path = write_run_table("complete", "reference", "# complete = true\n");
  const cli::RunFigure drawing = cli::run_figure(path, {});
  ASSERT_EQ(drawing.figure.spectra.size(), 1u);
  const figure::Spectrum& s = drawing.figure.spectra[0];
  EXPECT_EQ(s.label, "reference: N = 30, v = 0.5 mm/s, a = 1 mm, *α* = 1");
  EXPECT_EQ(s.omega.size(), 49u);
  EXPECT_NEAR(s.C_x[0] / s.theory[0], 1.01, 1e-9);
  // The theory line is the fine one, as computed for every figure.
  const auto [omegas, spectrum] = cli::fine_theory_of_table(path);
  EXPECT_EQ(s.line_omega, omegas);
  EXPECT_EQ(s.line_C_x, spectrum);
  // Eq. (1) from 5 v/a to omega_c / 3 only.
  const Parameters p = ParameterBuilder("reference").build();
  ASSERT_GE(s.eq1_omega.size(), 2u);
  EXPECT_GE(s.eq1_omega.front(), 5 * p.v / p.a);
  EXPECT_LE(s.eq1_omega.back(), landmarks(p).omega_c / 3);
  EXPECT_LT(s.eq1_omega.front(), 5 * p.v / p.a * std::pow(10.0, 1.0 / 8) * 1.001);
  EXPECT_NEAR(s.resonance, landmarks(p).omega_c, 1e-9 * s.resonance);
  EXPECT_EQ(s.resonance_label, "*ω*_{*c*}");
  // Up to 1e5 rad/s: the footnote on the paper's peak near 4e4 rad/s.
  EXPECT_NE(drawing.figure.footnote.find("4e4 rad/s"), std::string::npos);
  EXPECT_TRUE(drawing.figure.residuals);
  EXPECT_DOUBLE_EQ(drawing.page.width, 7);
  EXPECT_DOUBLE_EQ(drawing.page.height, 6.2);
  EXPECT_DOUBLE_EQ(drawing.page.dpi, 150);
}

TEST(RunFigure, MarksAnInterruptedRunAndTheKeysSet) {
  const std::string path = write_run_table("incomplete", "reference + k0=20000, alpha=2", "# complete = false\n",
                                           ParameterBuilder("reference").set("k0", "20000").set("alpha", "2").build());
  const cli::RunFigure drawing = cli::run_figure(path, {});
  const figure::Spectrum& s = drawing.figure.spectra[0];
  EXPECT_EQ(s.label.rfind("reference: N = 30", 0), 0u) << s.label;
  EXPECT_NE(s.label.find("*k*_{0} = 2e4 N/m"), std::string::npos) << s.label;
  EXPECT_NE(s.label.find("*α* = 2"), std::string::npos) << s.label;
  EXPECT_EQ(s.label.size() - s.label.rfind(" (incomplete)"), std::string(" (incomplete)").size()) << s.label;
}

TEST(RunFigure, NamesASpringsStiffnessWithItsUnit) {
  const std::string path =
      write_run_table("spring", "reference + drive=spring, k_drive=1000", "",
                      ParameterBuilder("reference").set("drive", "spring").set("k_drive", "1000").build());
  const cli::RunFigure drawing = cli::run_figure(path, {});
  const std::string& label = drawing.figure.spectra[0].label;
  EXPECT_NE(label.find("drive = spring, *k*_{drive} = 1000 N/m"), std::string::npos) << label;
}

// Under a spring the block resonates at omega_resonance = sqrt((N k0 + k_drive)/M), and the
// paper's Eq. (1), the constant force's asymptote, does not describe it: not drawn.
TEST(RunFigure, MarksASpringsResonanceAndLeavesOutEq1) {
  const Parameters p = ParameterBuilder("reference").set("drive", "spring").set("k_drive", "1e5").build();
  const std::string path = write_run_table("spring_resonance", "reference + drive=spring, k_drive=1e5", "", p);
  const cli::RunFigure drawing = cli::run_figure(path, {});
  const figure::Spectrum& s = drawing.figure.spectra[0];
  const double resonance = std::sqrt((p.N * p.k0 + p.k_drive) / p.M);
  EXPECT_NEAR(s.resonance, resonance, 1e-9 * resonance);
  EXPECT_GT(s.resonance, 1.1 * landmarks(p).omega_c);
  EXPECT_EQ(s.resonance_label, "*ω*_{res}");
  EXPECT_TRUE(s.eq1_omega.empty());
}

TEST(RunFigure, TakesTheStylesPage) {
  const std::string path = write_run_table("styled", "reference", "");
  cli::FigureStyle style;
  style.format = "svg";
  style.size = "5x4";
  style.dpi = 300;
  const figure::Page page = cli::run_figure(path, style).page;
  EXPECT_EQ(page.format, figure::Format::svg);
  EXPECT_DOUBLE_EQ(page.width, 5);
  EXPECT_DOUBLE_EQ(page.height, 4);
  EXPECT_DOUBLE_EQ(page.dpi, 300);
  style.format = "png";
  style.size = "";
  style.dpi = 100;
  const std::string png = cli::draw_run_figure(path, style);
  ASSERT_GT(png.size(), 24u);
  // IHDR's width and height: 7 x 6.2 in at 100 dpi.
  auto u32 = [&](std::size_t at) {
    std::uint32_t value = 0;
    for (std::size_t k = 0; k < 4; ++k) value = value << 8 | static_cast<unsigned char>(png[at + k]);
    return value;
  };
  EXPECT_EQ(u32(16), 700u);
  EXPECT_EQ(u32(20), 620u);
}

}  // namespace
}  // namespace slidespec
