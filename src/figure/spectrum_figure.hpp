// The figure of a run's spectrum drawn here, with cairo: the simulated C_x with its error
// bars over the exact theory on log-log axes, the paper's Eq. (1) where it applies, omega_c,
// and under it the residuals against the theory. What it shows is docs/plots.md's.
#pragma once

#include <string>
#include <vector>

#include "figure/axes.hpp"

namespace slidespec::figure {

struct Color {
  double red = 0, green = 0, blue = 0;  ///< each 0..1
};

/// The colour cycle's first: every single run's.
inline constexpr Color kFirstColor{0x1f / 255.0, 0x77 / 255.0, 0xb4 / 255.0};

/// One table on the figure. Omegas in rad/s, spectra in m^2 s.
struct Spectrum {
  std::string label;  ///< its legend entry, as text markup (figure/text.hpp)
  Color color = kFirstColor;
  std::vector<double> omega, C_x, standard_error;  ///< the simulated points
  std::vector<double> theory;                      ///< the table's theory at its points: the residuals' reference
  std::vector<double> line_omega, line_C_x;        ///< the theory as a line, on a fine grid
  std::vector<double> eq1_omega, eq1_C_x;          ///< Eq. (1), where it applies
  /// The block's resonance (omega_c; under a spring omega_resonance), a dotted line
  /// labelled on the top edge; 0 for none.
  double resonance = 0;
  std::string resonance_label = "*ω*_{*c*}";  ///< as text markup
};

enum class Format { png, pdf, svg };

/// The page: its size in inches, and for a PNG its resolution.
struct Page {
  double width = 7, height = 6.2;  ///< [in]
  double dpi = 150;
  Format format = Format::png;

  /// A PNG's size in pixels.
  int pixel_width() const;
  int pixel_height() const;
};

/// What a spectrum figure shows.
struct SpectrumFigure {
  std::vector<Spectrum> spectra;
  bool residuals = true;  ///< C_x/theory - 1 in a panel under the spectrum
  std::string y_label = "*C*_{*x*} (m² s)";
  std::string line_label = "exact first-order theory";  ///< the theory lines' legend entry
  std::string footnote;                                 ///< a line of text under the axes; empty for none
};

/// Where the drawing went, in points from the page's top left: the panels and their scales.
struct Layout {
  Box spectrum, residuals;  ///< residuals.height == 0 without the panel
  Scale omega, C_x, residual;
};

/// A drawn figure: the file's bytes and where things are on it.
struct DrawnFigure {
  std::string bytes;
  Layout layout;
};

/// Draws `figure` on `page`. Throws std::runtime_error when cairo cannot (a page too
/// large for memory, say) or there is nothing to draw (no positive value).
DrawnFigure draw(const SpectrumFigure& figure, const Page& page);

}  // namespace slidespec::figure
