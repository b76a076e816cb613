// The figures: a run's (run, merge) drawn here with cairo (src/figure/), the others by
// tools/plot_spectra.py (matplotlib, Debian's python3-matplotlib); both with the exact
// theory computed here on a fine grid for every table that names its model parameters.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "figure/spectrum_figure.hpp"

namespace slidespec::cli {

/// How a figure is written: format, size and resolution, and colours per table.
struct FigureStyle {
  std::string format = "png";       ///< png | pdf | svg
  std::string size;                 ///< "WxH" in inches; empty: the tool's default
  double dpi = 150;                 ///< dots per inch (PNG; PDF and SVG are vector)
  std::vector<std::string> colors;  ///< matplotlib colours, one per table; empty: the cycle
  std::string layout;               ///< the plotter's --layout (drives); empty: the standard figure

  /// --format, --size, --dpi on a command that writes PREFIX.<format>.
  void add_to(CLI::App& command);
  /// --size, --dpi only (the format comes from the output's extension).
  void add_size_to(CLI::App& command);
  /// Throws InputError for an unknown format, a malformed size, a dpi out of 10..2400 or a
  /// PNG of more than 32767 pixels a side (cairo's limit).
  void check() const;
  /// PREFIX.<format>.
  std::string path(const std::string& prefix) const { return prefix + "." + format; }
};

/// Throws InputError for a title that does not fit on one line above a figure of the
/// style's width (a longer one would be cut off, or fail to rasterize at all).
void check_title(const std::string& title, const FigureStyle& style);

/// The format of a figure path by its extension (png, pdf, svg); InputError otherwise.
std::string format_of(const std::string& path);

/// Starts the plotting process now, so that the interpreter and matplotlib load while the
/// caller simulates; the next plot() hands it its tables. A plotter never handed work
/// ends when this process does.
void start_plotter();

/// Draws `tables` into `out` (with the plotter start_plotter started, else a new one) and
/// returns 0 when drawn, 2 for bad input (the tool's own one-line message on stderr), or 1
/// for a plotter that could not start, failed or was killed (a message naming it).
int plot(const std::vector<std::string>& tables, const std::string& out, const std::string& title,
         const FigureStyle& style = {});

/// What the figure of a run's table (run, merge) shows, and its page: the style's format,
/// size and resolution (7x6.2 in with the residual panel, 7x5 without).
struct RunFigure {
  figure::SpectrumFigure figure;
  figure::Page page;
};
RunFigure run_figure(const std::string& table, const FigureStyle& style);

/// The figure of a run's table, drawn here (src/figure/): the bytes of the file. Throws
/// std::runtime_error when it cannot be drawn.
std::string draw_run_figure(const std::string& table, const FigureStyle& style);

/// Points per decade of the theory line at least (more where it bends: resonances).
inline constexpr int kTheoryPointsPerDecade = 96;

/// The exact theory of a table's model on a grid fine enough to resolve its resonances,
/// over the table's omega range: omegas and C_x. Empty when the table names no model.
std::pair<std::vector<double>, std::vector<double>> fine_theory_of_table(const std::string& path);

}  // namespace slidespec::cli
