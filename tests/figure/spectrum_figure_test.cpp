// The spectrum figure drawn with cairo (src/figure/): every mark lands where the axes say
// its value belongs. The expected pixel of a value is computed here from the panels' boxes
// and ranges with the axis mapping written out again, and the PNG is read back by cairo.
#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "figure/axes.hpp"
#include "figure/png.hpp"
#include "figure/spectrum_figure.hpp"

namespace slidespec::figure {
namespace {

constexpr double kDpi = 150;

double theory_at(double omega) { return 1e-10 / (omega * omega); }

// Points off the theory by these fractions: above, below, far enough apart to tell.
const std::vector<double> kOmegas = {1, 2, 5, 10, 20, 50, 100};
const std::vector<double> kOffsets = {0.5, -0.3, 0.5, -0.3, 0.5, -0.3, 0.5};

SpectrumFigure known_figure() {
  Spectrum s;
  s.label = "known: *α* = 1";
  for (std::size_t i = 0; i < kOmegas.size(); ++i) {
    s.omega.push_back(kOmegas[i]);
    s.theory.push_back(theory_at(kOmegas[i]));
    s.C_x.push_back(theory_at(kOmegas[i]) * (1 + kOffsets[i]));
    // Bars reaching past the marker, so that its own fill is told from the bar's colour.
    s.standard_error.push_back(0.1 * s.C_x.back());
  }
  for (double decade = 0; decade <= 2.0001; decade += 0.01) {
    s.line_omega.push_back(std::pow(10.0, decade));
    s.line_C_x.push_back(theory_at(s.line_omega.back()));
  }
  SpectrumFigure figure;
  figure.spectra.push_back(s);
  return figure;
}

/// A PNG read back by cairo.
class Image {
 public:
  explicit Image(const std::string& png) : surface_(read_png(png)) {}
  ~Image() { cairo_surface_destroy(surface_); }
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  bool valid() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  /// The colour at a point given in points from the page's top left.
  Color at(double x_points, double y_points) const {
    const int x = static_cast<int>(std::floor(x_points * kDpi / 72));
    const int y = static_cast<int>(std::floor(y_points * kDpi / 72));
    const unsigned char* row = cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    const std::uint32_t pixel = reinterpret_cast<const std::uint32_t*>(row)[x];
    return {((pixel >> 16) & 0xff) / 255.0, ((pixel >> 8) & 0xff) / 255.0, (pixel & 0xff) / 255.0};
  }

 private:
  cairo_surface_t* surface_;
};

bool close_to(Color a, Color b, double tolerance = 0.04) {
  return std::abs(a.red - b.red) < tolerance && std::abs(a.green - b.green) < tolerance &&
         std::abs(a.blue - b.blue) < tolerance;
}

std::string describe(Color c) {
  return "(" + std::to_string(c.red) + ", " + std::to_string(c.green) + ", " + std::to_string(c.blue) + ")";
}

// The axis mapping, written out: log10 of a value across the box, upward for y.
double x_of(const Layout& layout, double omega) {
  const Box& box = layout.spectrum;
  return box.left + (std::log10(omega) - layout.omega.low) / (layout.omega.high - layout.omega.low) * box.width;
}
double y_of(const Layout& layout, double C_x) {
  const Box& box = layout.spectrum;
  return box.top + (layout.C_x.high - std::log10(C_x)) / (layout.C_x.high - layout.C_x.low) * box.height;
}
double residual_y_of(const Layout& layout, double residual) {
  const Box& box = layout.residuals;
  return box.top + (layout.residual.high - residual) / (layout.residual.high - layout.residual.low) * box.height;
}

class KnownFigure : public testing::Test {
 protected:
  void SetUp() override {
    page_.dpi = kDpi;
    drawn_ = draw(known_figure(), page_);
  }
  Page page_;
  DrawnFigure drawn_;
};

TEST_F(KnownFigure, PngHasThePagesPixels) {
  const Image image(drawn_.bytes);
  ASSERT_TRUE(image.valid());
  EXPECT_EQ(image.width(), 1050);  // 7 in at 150 dpi
  EXPECT_EQ(image.height(), 930);  // 6.2 in
  // The smallest page --size allows is drawn too, crowded: a run's outputs depend on it.
  for (const auto& [width, height, dpi] :
       {std::tuple{5.0, 4.0, 72.0}, std::tuple{3.3, 2.5, 100.0}, std::tuple{0.5, 0.5, 150.0}}) {
    Page page;
    page.width = width;
    page.height = height;
    page.dpi = dpi;
    const Image small(draw(known_figure(), page).bytes);
    ASSERT_TRUE(small.valid());
    EXPECT_EQ(small.width(), std::lround(width * dpi));
    EXPECT_EQ(small.height(), std::lround(height * dpi));
  }
}

TEST_F(KnownFigure, AxesHoldEveryPointWithMargins) {
  const Layout& layout = drawn_.layout;
  EXPECT_LT(layout.omega.low, 0);  // log10 of the smallest omega, 1
  EXPECT_GT(layout.omega.high, 2);
  EXPECT_NEAR(layout.omega.low, -0.1, 1e-9);  // 5% of two decades
  EXPECT_LT(layout.C_x.low, std::log10(0.7 * theory_at(100)));
  EXPECT_GT(layout.C_x.high, std::log10(1.5 * theory_at(1)));
  // The spectrum above the residuals, both across the same width.
  EXPECT_GT(layout.residuals.height, 0);
  EXPECT_LT(layout.spectrum.bottom(), layout.residuals.top);
  EXPECT_DOUBLE_EQ(layout.spectrum.left, layout.residuals.left);
  EXPECT_DOUBLE_EQ(layout.spectrum.width, layout.residuals.width);
  EXPECT_NEAR(layout.spectrum.height / (layout.spectrum.height + layout.residuals.height), 0.75, 1e-9);
  EXPECT_LE(layout.residuals.bottom(), page_.height * 72);
}

TEST_F(KnownFigure, MarkersSitAtTheirValues) {
  const Image image(drawn_.bytes);
  ASSERT_TRUE(image.valid());
  const Layout& layout = drawn_.layout;
  for (std::size_t i = 0; i < kOmegas.size(); ++i) {
    const double C_x = theory_at(kOmegas[i]) * (1 + kOffsets[i]);
    // Beside the centre, inside the marker (radius 2 pt), clear of its bar (1 pt wide).
    const Color seen = image.at(x_of(layout, kOmegas[i]) + 1.3, y_of(layout, C_x));
    EXPECT_TRUE(close_to(seen, kFirstColor)) << "omega " << kOmegas[i] << ": " << describe(seen);
  }
}

TEST_F(KnownFigure, TheoryLinePassesThroughTheTheoryOnly) {
  const Image image(drawn_.bytes);
  ASSERT_TRUE(image.valid());
  const Layout& layout = drawn_.layout;
  // Between the markers, where only the line is drawn.
  for (const double omega : {1.4, 3.2, 7.1, 14.0, 32.0, 71.0}) {
    const double x = x_of(layout, omega), y = y_of(layout, theory_at(omega));
    EXPECT_TRUE(close_to(image.at(x, y), kFirstColor, 0.1)) << "on the line at omega " << omega;
    // A quarter decade above and below: the line is not there.
    for (const double off : {std::pow(10.0, 0.25), std::pow(10.0, -0.25)})
      EXPECT_FALSE(close_to(image.at(x, y_of(layout, theory_at(omega) * off)), kFirstColor, 0.3))
          << "beside the line at omega " << omega;
  }
}

TEST_F(KnownFigure, ResidualsSitAtTheirValues) {
  const Image image(drawn_.bytes);
  ASSERT_TRUE(image.valid());
  const Layout& layout = drawn_.layout;
  // The axis reaches the farthest point with its bar, and room: 1.15 (0.5 + 0.1 * 1.5).
  EXPECT_NEAR(layout.residual.high, 1.15 * 0.65, 1e-9);
  EXPECT_NEAR(layout.residual.low, -layout.residual.high, 1e-12);
  for (std::size_t i = 0; i < kOmegas.size(); ++i) {
    const Color seen = image.at(x_of(layout, kOmegas[i]), residual_y_of(layout, kOffsets[i]));
    EXPECT_TRUE(close_to(seen, kFirstColor)) << "residual at omega " << kOmegas[i] << ": " << describe(seen);
  }
  // The zero line is black, across the panel.
  const Color zero = image.at(x_of(layout, 3.2), residual_y_of(layout, 0));
  EXPECT_LT(zero.red + zero.green + zero.blue, 1.0) << describe(zero);
}

TEST_F(KnownFigure, OmegaCIsADottedGreyLine) {
  SpectrumFigure figure = known_figure();
  figure.spectra[0].resonance = 30;
  const DrawnFigure drawn = draw(figure, page_);
  const Image image(drawn.bytes);
  ASSERT_TRUE(image.valid());
  const double x = x_of(drawn.layout, 30);
  int grey = 0, white = 0;
  for (double y = drawn.layout.spectrum.top + 20; y < drawn.layout.spectrum.top + 60; y += 0.25) {
    const Color seen = image.at(x, y);
    grey += seen.red < 0.6 && seen.red > 0.3;
    white += seen.red > 0.95;
  }
  EXPECT_GT(grey, 10);   // dots
  EXPECT_GT(white, 10);  // and the gaps between them
}

TEST_F(KnownFigure, WithoutTheoryNoResidualPanel) {
  SpectrumFigure figure = known_figure();
  figure.spectra[0].theory.clear();
  const DrawnFigure drawn = draw(figure, page_);
  EXPECT_EQ(drawn.layout.residuals.height, 0);
  EXPECT_GT(drawn.layout.spectrum.height, drawn_.layout.spectrum.height);
}

TEST_F(KnownFigure, SvgAndPdfAreWholeVectorFiles) {
  Page page = page_;
  page.format = Format::svg;
  const std::string svg = draw(known_figure(), page).bytes;
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("width=\"504pt\" height=\"446.4pt\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(svg.find("<image"), std::string::npos) << "a bitmap inside the SVG";
  page.format = Format::pdf;
  const std::string pdf = draw(known_figure(), page).bytes;
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 504 446.4 ]"), std::string::npos);
  EXPECT_NE(pdf.rfind("%%EOF"), std::string::npos);
  EXPECT_GT(pdf.rfind("%%EOF"), pdf.size() - 8);
}

TEST_F(KnownFigure, NothingToDrawIsAnError) {
  SpectrumFigure figure = known_figure();
  for (double& value : figure.spectra[0].C_x) value = -1;
  figure.spectra[0].line_C_x.assign(figure.spectra[0].line_C_x.size(), 0);
  EXPECT_THROW(draw(figure, page_), std::runtime_error);
}

TEST_F(KnownFigure, APageBeyondCairosLimitIsAnError) {
  Page page = page_;
  page.width = 100;
  page.dpi = 400;  // 40000 pixels wide
  EXPECT_THROW(draw(known_figure(), page), std::runtime_error);
}

TEST(FigureAxes, DecadesLabelledWithinTheirNumber) {
  std::vector<double> minor;
  Scale omega;
  omega.low = -1.3;
  omega.high = 5.3;
  omega.logarithmic = true;
  const std::vector<Tick> ticks = log_ticks(omega, 15, minor);
  ASSERT_EQ(ticks.size(), 7u);
  EXPECT_EQ(ticks.front().label, "10^{\u22121}");
  EXPECT_EQ(ticks[1].label, "10^{0}");
  EXPECT_EQ(ticks.back().label, "10^{5}");
  EXPECT_DOUBLE_EQ(ticks.back().value, 1e5);
  EXPECT_NE(std::find(minor.begin(), minor.end(), 2e3), minor.end());  // 2..9 per decade
  EXPECT_NE(std::find(minor.begin(), minor.end(), 9e-1), minor.end());

  Scale spectrum;
  spectrum.low = -41;
  spectrum.high = -7;
  spectrum.logarithmic = true;
  const std::vector<Tick> sparse = log_ticks(spectrum, 9, minor);
  ASSERT_EQ(sparse.size(), 9u);  // every 4th decade, -40 .. -8
  EXPECT_DOUBLE_EQ(sparse.front().value, 1e-40);
  EXPECT_EQ(sparse.back().label, "10^{\u22128}");
  EXPECT_EQ(minor.size(), 35u - 9u);  // the unlabelled decades
}

TEST(FigureAxes, WithinADecadeTheMultiplesAreLabelled) {
  std::vector<double> minor;
  Scale omega;
  omega.low = -1.05;  // 0.089 .. 0.79 rad/s: the first sub-band of an interrupted run
  omega.high = -0.1;
  omega.logarithmic = true;
  const std::vector<Tick> ticks = log_ticks(omega, 15, minor);
  ASSERT_EQ(ticks.size(), 3u);
  EXPECT_EQ(ticks[0].label, "10^{\u22121}");
  EXPECT_EQ(ticks[1].label, "2×10^{\u22121}");
  EXPECT_DOUBLE_EQ(ticks[2].value, 0.5);
  EXPECT_EQ(minor.size(), 5u);  // 9e-2 and 3, 4, 6, 7 x 0.1
}

TEST(FigureAxes, LinearTicksAreRound) {
  const Scale residual{-0.0787, 0.0787, 0, 1, false};
  const std::vector<Tick> ticks = linear_ticks(residual, 3);
  ASSERT_EQ(ticks.size(), 3u);
  EXPECT_EQ(ticks[0].label, "\u22120.05");
  EXPECT_EQ(ticks[1].label, "0.00");
  EXPECT_EQ(ticks[2].label, "0.05");
  const std::vector<Tick> fine = linear_ticks(Scale{-0.6, 0.6, 0, 1, false}, 5);
  ASSERT_EQ(fine.size(), 5u);
  EXPECT_EQ(fine[1].label, "\u22120.25");
}

TEST(FigureAxes, ScaleMapsLogValuesAcrossThePage) {
  Scale scale = Scale::around(1, 100, true, 0);
  scale.start = 100;
  scale.end = 0;  // upward, as a y axis
  EXPECT_DOUBLE_EQ(scale.at(1), 100);
  EXPECT_DOUBLE_EQ(scale.at(10), 50);
  EXPECT_DOUBLE_EQ(scale.at(100), 0);
  EXPECT_TRUE(std::isnan(scale.at(0)));
}

}  // namespace
}  // namespace slidespec::figure
