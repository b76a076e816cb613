#include "figure/spectrum_figure.hpp"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "figure/png.hpp"
#include "figure/text.hpp"

namespace slidespec::figure {

namespace {

constexpr double kPointsPerInch = 72;

// Sizes in points, matplotlib's defaults where the matplotlib figures had them.
constexpr double kTickFont = 10, kResidualTickFont = 9, kAxisLabelFont = 12, kResidualLabelFont = 11;
constexpr double kLegendFont = 8.5, kNoteFont = 8, kOmegaCFont = 11;
constexpr double kMajorTick = 3.5, kMinorTick = 2, kTickPad = 3.5, kPad = 4, kPanelGap = 10;
constexpr double kSpineWidth = 0.8, kMajorTickWidth = 0.8, kMinorTickWidth = 0.6, kGridWidth = 0.6;
constexpr double kTheoryWidth = 1.3, kEq1Width = 0.9, kOmegaCWidth = 1.2;
// Markers: radius, edge and error bar widths, half the cap's length.
constexpr double kMarkerRadius = 2, kMarkerEdge = 0.4, kBarWidth = 1.0, kCapHalf = 2;
constexpr double kResidualMarkerRadius = 1.5, kResidualMarkerEdge = 0.3, kResidualBarWidth = 0.8,
                 kResidualCapHalf = 1.5;
// The spectrum takes three quarters of the height the panels share.
constexpr double kSpectrumShare = 0.75;
constexpr double kLeastPanel = 1;  // [pt]
// Labelled ticks at least this many font sizes apart.
constexpr double kTickSpacing = 2.5;
// The residual axis reaches the farthest point and its bar, with room, within these bounds.
constexpr double kResidualRoom = 1.15, kLeastResidualLimit = 0.05, kMostResidualLimit = 1.0;
constexpr double kBandAlpha = 0.18, kLegendAlpha = 0.85;

constexpr Color kBlack{0, 0, 0}, kWhite{1, 1, 1}, kGrid{0.9, 0.9, 0.9}, kNoteGrey{0.3, 0.3, 0.3},
    kOmegaCGrey{0.4, 0.4, 0.4}, kHandleGrey{0.35, 0.35, 0.35};

void set_color(cairo_t* cr, Color color, double alpha = 1) {
  cairo_set_source_rgba(cr, color.red, color.green, color.blue, alpha);
}

void stroke_line(cairo_t* cr, double x0, double y0, double x1, double y1, double width, Color color) {
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1, y1);
  cairo_set_line_width(cr, width);
  set_color(cr, color);
  cairo_stroke(cr);
}

void clip_to(cairo_t* cr, const Box& box) {
  cairo_rectangle(cr, box.left, box.top, box.width, box.height);
  cairo_clip(cr);
}

/// A polyline through the points that map to the page (a value <= 0 breaks it).
void trace(cairo_t* cr, const Scale& x, const Scale& y, const std::vector<double>& xs, const std::vector<double>& ys) {
  bool drawing = false;
  for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
    const double px = x.at(xs[i]), py = y.at(ys[i]);
    if (!std::isfinite(px) || !std::isfinite(py)) {
      drawing = false;
      continue;
    }
    if (drawing)
      cairo_line_to(cr, px, py);
    else
      cairo_move_to(cr, px, py);
    drawing = true;
  }
}

void marker(cairo_t* cr, double x, double y, double radius, double edge, Color fill) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, x, y, radius, 0, 2 * M_PI);
  set_color(cr, fill);
  cairo_fill_preserve(cr);
  cairo_set_line_width(cr, edge);
  set_color(cr, kBlack);
  cairo_stroke(cr);
}

void error_bar(cairo_t* cr, double x, double low, double high, double width, double cap, Color color) {
  if (!std::isfinite(low) || !std::isfinite(high)) return;
  cairo_move_to(cr, x, low);
  cairo_line_to(cr, x, high);
  for (const double end : {low, high}) {
    cairo_move_to(cr, x - cap, end);
    cairo_line_to(cr, x + cap, end);
  }
  cairo_set_line_width(cr, width);
  set_color(cr, color);
  cairo_stroke(cr);
}

/// The lower end of a bar on a log axis: a bar reaching zero or below is drawn a decade long.
double lower_end(double value, double error) { return value - error > 0 ? value - error : value / 10; }

struct Range {
  double low = std::numeric_limits<double>::infinity(), high = -std::numeric_limits<double>::infinity();
  void add(double value) {
    if (!(value > 0) || !std::isfinite(value)) return;
    low = std::min(low, value);
    high = std::max(high, value);
  }
  bool empty() const { return !(high >= low); }
};

double line_height(cairo_t* cr, double size) {
  const Extent extent = measure(cr, "0", size);
  return extent.ascent + extent.descent;
}

/// The ticks of an axis along one edge of a panel: marks outward, labels beyond them.
enum class Edge { left, bottom };

void draw_ticks(cairo_t* cr, const Box& box, const Scale& scale, Edge edge, const std::vector<Tick>& ticks,
                const std::vector<double>& minor, double font, bool labelled) {
  auto mark = [&](double value, double length, double width) {
    const double at = scale.at(value);
    if (edge == Edge::left)
      stroke_line(cr, box.left, at, box.left - length, at, width, kBlack);
    else
      stroke_line(cr, at, box.bottom(), at, box.bottom() + length, width, kBlack);
  };
  for (const double value : minor) mark(value, kMinorTick, kMinorTickWidth);
  for (const Tick& tick : ticks) {
    mark(tick.value, kMajorTick, kMajorTickWidth);
    if (!labelled) continue;
    const double at = scale.at(tick.value);
    if (edge == Edge::left)
      draw_text(cr, tick.label, font, box.left - kMajorTick - kTickPad, at, 1, Vertical::middle);
    else
      draw_text(cr, tick.label, font, at, box.bottom() + kMajorTick + kTickPad, 0.5, Vertical::top);
  }
}

void draw_grid(cairo_t* cr, const Box& box, const Scale& x, const std::vector<Tick>& x_ticks, const Scale& y,
               const std::vector<Tick>& y_ticks) {
  for (const Tick& tick : x_ticks)
    stroke_line(cr, x.at(tick.value), box.top, x.at(tick.value), box.bottom(), kGridWidth, kGrid);
  for (const Tick& tick : y_ticks)
    stroke_line(cr, box.left, y.at(tick.value), box.right(), y.at(tick.value), kGridWidth, kGrid);
}

void draw_frame(cairo_t* cr, const Box& box) {
  cairo_rectangle(cr, box.left, box.top, box.width, box.height);
  cairo_set_line_width(cr, kSpineWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
  set_color(cr, kBlack);
  cairo_stroke(cr);
}

void dashed(cairo_t* cr, double on, double off) {
  const double pattern[] = {on, off};
  cairo_set_dash(cr, pattern, 2, 0);
}

/// One legend row: what its handle shows.
struct LegendEntry {
  std::string text;
  bool marker = false, line = false, dashed = false;
  Color color;
};

std::vector<LegendEntry> legend_entries(const SpectrumFigure& figure) {
  std::vector<LegendEntry> entries;
  bool any_eq1 = false, any_line = false;
  for (const Spectrum& s : figure.spectra) {
    entries.push_back({s.label, true, !s.line_omega.empty(), false, s.color});
    any_eq1 |= s.eq1_omega.size() >= 2;
    any_line |= !s.line_omega.empty();
  }
  entries.push_back({"simulation, ±1 stderr", true, false, false, kHandleGrey});
  if (any_line) entries.push_back({figure.line_label, false, true, false, kHandleGrey});
  if (any_eq1) entries.push_back({"Eq. (1)", false, true, true, kBlack});
  return entries;
}

/// The legend where it hides the fewest drawn points of the spectrum's panel (matplotlib's
/// "best", over the same nine places).
void draw_legend(cairo_t* cr, const SpectrumFigure& figure, const Layout& layout) {
  const std::vector<LegendEntry> entries = legend_entries(figure);
  const double font = kLegendFont, border = 0.4 * font, spacing = 0.5 * font, handle = 2 * font,
               handle_pad = 0.8 * font, outside = 0.5 * font;
  double text_width = 0;
  for (const LegendEntry& entry : entries) text_width = std::max(text_width, measure(cr, entry.text, font).width);
  const double row = line_height(cr, font);
  const double width = 2 * border + handle + handle_pad + text_width;
  const double height = 2 * border + entries.size() * row + (entries.size() - 1) * spacing;
  const Box& panel = layout.spectrum;
  // matplotlib's order: upper right, upper left, lower left, lower right, then the middles
  // of the right and left edges, of the bottom and top, and the centre.
  const double left = panel.left + outside, right = panel.right() - outside - width;
  const double top = panel.top + outside, bottom = panel.bottom() - outside - height;
  const double middle_x = panel.left + (panel.width - width) / 2, middle_y = panel.top + (panel.height - height) / 2;
  const Box corners[] = {
      {right, top, width, height},       {left, top, width, height},       {left, bottom, width, height},
      {right, bottom, width, height},    {right, middle_y, width, height}, {left, middle_y, width, height},
      {middle_x, bottom, width, height}, {middle_x, top, width, height},   {middle_x, middle_y, width, height}};
  auto covered = [&](const Box& box) {
    std::size_t count = 0;
    auto count_in = [&](const std::vector<double>& xs, const std::vector<double>& ys) {
      for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
        const double x = layout.omega.at(xs[i]), y = layout.C_x.at(ys[i]);
        count += x >= box.left && x <= box.right() && y >= box.top && y <= box.bottom();
      }
    };
    for (const Spectrum& s : figure.spectra) {
      count_in(s.omega, s.C_x);
      count_in(s.line_omega, s.line_C_x);
      count_in(s.eq1_omega, s.eq1_C_x);
      // A line crossing the box counts as one point hidden, as in matplotlib.
      const double omega_c = s.resonance > 0 ? layout.omega.at(s.resonance) : NAN;
      count += omega_c >= box.left && omega_c <= box.right();
    }
    return count;
  };
  const Box* best = &corners[0];
  for (const Box& box : corners)
    if (covered(box) < covered(*best)) best = &box;

  cairo_rectangle(cr, best->left, best->top, best->width, best->height);
  set_color(cr, kWhite, kLegendAlpha);
  cairo_fill(cr);
  double y = best->top + border;
  for (const LegendEntry& entry : entries) {
    const double middle = y + row / 2, x = best->left + border;
    if (entry.line) {
      const double from = entry.marker ? x + handle / 2 : x;
      if (entry.dashed) dashed(cr, 3.7 * kEq1Width, 1.6 * kEq1Width);
      stroke_line(cr, from, middle, x + handle, middle, entry.dashed ? kEq1Width : kTheoryWidth, entry.color);
      cairo_set_dash(cr, nullptr, 0, 0);
    }
    if (entry.marker)
      marker(cr, entry.line ? x + handle / 4 : x + handle / 2, middle, kMarkerRadius, kMarkerEdge, entry.color);
    set_color(cr, kBlack);
    draw_text(cr, entry.text, font, x + handle + handle_pad, middle, 0, Vertical::middle);
    y += row + spacing;
  }
}

double residual_of(const Spectrum& s, std::size_t i) { return s.C_x[i] / s.theory[i] - 1; }
double relative_error_of(const Spectrum& s, std::size_t i) { return std::abs(s.standard_error[i]) / s.theory[i]; }
bool has_residual(const Spectrum& s, std::size_t i) {
  return i < s.theory.size() && s.theory[i] > 0 && i < s.standard_error.size() && std::isfinite(residual_of(s, i)) &&
         std::isfinite(relative_error_of(s, i));
}

void draw_residuals(cairo_t* cr, const SpectrumFigure& figure, const Layout& layout) {
  const Box& box = layout.residuals;
  const Scale& x = layout.omega;
  const Scale& y = layout.residual;
  cairo_save(cr);
  clip_to(cr, box);
  for (const Spectrum& s : figure.spectra) {
    // The +-2 stderr band, joined point to point as matplotlib's fill_between.
    bool first = true;
    for (std::size_t i = 0; i < s.omega.size(); ++i)
      if (has_residual(s, i)) {
        (first ? cairo_move_to : cairo_line_to)(cr, x.at(s.omega[i]), y.at(2 * relative_error_of(s, i)));
        first = false;
      }
    for (std::size_t i = s.omega.size(); i-- > 0;)
      if (has_residual(s, i)) cairo_line_to(cr, x.at(s.omega[i]), y.at(-2 * relative_error_of(s, i)));
    cairo_close_path(cr);
    set_color(cr, s.color, kBandAlpha);
    cairo_fill(cr);
  }
  stroke_line(cr, box.left, y.at(0), box.right(), y.at(0), kSpineWidth, kBlack);
  for (const Spectrum& s : figure.spectra)
    for (std::size_t i = 0; i < s.omega.size(); ++i) {
      if (!has_residual(s, i)) continue;
      const double residual = residual_of(s, i), error = relative_error_of(s, i);
      error_bar(cr, x.at(s.omega[i]), y.at(residual - error), y.at(residual + error), kResidualBarWidth,
                kResidualCapHalf, s.color);
      marker(cr, x.at(s.omega[i]), y.at(residual), kResidualMarkerRadius, kResidualMarkerEdge, s.color);
    }
  cairo_restore(cr);
  set_color(cr, kNoteGrey);
  draw_text(cr, "band: ±2 stderr", kNoteFont, box.left + 0.01 * box.width, box.top + 0.05 * box.height, 0,
            Vertical::top);
}

void draw_spectra(cairo_t* cr, const SpectrumFigure& figure, const Layout& layout) {
  const Scale& x = layout.omega;
  const Scale& y = layout.C_x;
  cairo_save(cr);
  clip_to(cr, layout.spectrum);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const Spectrum& s : figure.spectra) {
    if (!(s.resonance > 0)) continue;
    const double at = x.at(s.resonance);
    dashed(cr, 1 * kOmegaCWidth, 1.65 * kOmegaCWidth);
    stroke_line(cr, at, layout.spectrum.top, at, layout.spectrum.bottom(), kOmegaCWidth,
                figure.spectra.size() == 1 ? kOmegaCGrey : s.color);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  for (const Spectrum& s : figure.spectra) {
    trace(cr, x, y, s.line_omega, s.line_C_x);
    cairo_set_line_width(cr, kTheoryWidth);
    set_color(cr, s.color);
    cairo_stroke(cr);
  }
  for (const Spectrum& s : figure.spectra)
    for (std::size_t i = 0; i < s.omega.size() && i < s.C_x.size(); ++i) {
      const double px = x.at(s.omega[i]), py = y.at(s.C_x[i]);
      if (!std::isfinite(px) || !std::isfinite(py)) continue;
      if (i < s.standard_error.size() && std::isfinite(s.standard_error[i])) {
        const double error = std::abs(s.standard_error[i]);
        error_bar(cr, px, y.at(lower_end(s.C_x[i], error)), y.at(s.C_x[i] + error), kBarWidth, kCapHalf, s.color);
      }
      marker(cr, px, py, kMarkerRadius, kMarkerEdge, s.color);
    }
  // Black on top: Eq. (1) lies on the exact curve, so its own colour would hide it.
  for (const Spectrum& s : figure.spectra) {
    if (s.eq1_omega.size() < 2) continue;
    trace(cr, x, y, s.eq1_omega, s.eq1_C_x);
    dashed(cr, 3.7 * kEq1Width, 1.6 * kEq1Width);
    cairo_set_line_width(cr, kEq1Width);
    set_color(cr, kBlack);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  cairo_restore(cr);
}

/// The omega_c marks' labels on the top edge: a tick up and "ω_c" above it.
void label_omega_c(cairo_t* cr, const SpectrumFigure& figure, const Layout& layout) {
  for (const Spectrum& s : figure.spectra) {
    if (!(s.resonance > 0)) continue;
    const double at = layout.omega.at(s.resonance);
    if (at < layout.spectrum.left || at > layout.spectrum.right()) continue;
    stroke_line(cr, at, layout.spectrum.top, at, layout.spectrum.top - kMajorTick, kMajorTickWidth, kBlack);
    set_color(cr, figure.spectra.size() == 1 ? kOmegaCGrey : s.color);
    draw_text(cr, s.resonance_label, kOmegaCFont, at, layout.spectrum.top - kMajorTick - kTickPad, 0.5,
              Vertical::bottom);
  }
}

struct Ranges {
  Range omega, C_x;
  double residual_reach = 0;
};

Ranges ranges_of(const SpectrumFigure& figure) {
  Ranges ranges;
  for (const Spectrum& s : figure.spectra) {
    for (std::size_t i = 0; i < s.omega.size() && i < s.C_x.size(); ++i) {
      if (!(s.omega[i] > 0 && s.C_x[i] > 0)) continue;
      ranges.omega.add(s.omega[i]);
      ranges.C_x.add(s.C_x[i]);
      if (i < s.standard_error.size() && std::isfinite(s.standard_error[i])) {
        const double error = std::abs(s.standard_error[i]);
        ranges.C_x.add(s.C_x[i] + error);
        ranges.C_x.add(lower_end(s.C_x[i], error));
      }
      if (has_residual(s, i))
        ranges.residual_reach = std::max(ranges.residual_reach, std::abs(residual_of(s, i)) + relative_error_of(s, i));
    }
    for (std::size_t i = 0; i < s.line_omega.size() && i < s.line_C_x.size(); ++i)
      if (s.line_omega[i] > 0) ranges.C_x.add(s.line_C_x[i]);
    for (std::size_t i = 0; i < s.eq1_omega.size() && i < s.eq1_C_x.size(); ++i) ranges.C_x.add(s.eq1_C_x[i]);
  }
  return ranges;
}

/// The ticks of the three axes: labelled, and the minor ones between.
struct Ticks {
  std::vector<Tick> omega, C_x, residual;
  std::vector<double> omega_minor, C_x_minor;
};

Layout lay_out(cairo_t* cr, const SpectrumFigure& figure, const Page& page, const Ranges& ranges, bool residuals,
               Ticks& ticks) {
  const double width = page.width * kPointsPerInch, height = page.height * kPointsPerInch;
  Layout layout;
  layout.omega = Scale::around(ranges.omega.low, ranges.omega.high, true);
  layout.C_x = Scale::around(ranges.C_x.low, ranges.C_x.high, true);
  const double limit =
      std::min(std::max(kResidualRoom * ranges.residual_reach, kLeastResidualLimit), kMostResidualLimit);
  layout.residual = Scale{-limit, limit, 0, 1, false};

  const bool omega_c =
      std::any_of(figure.spectra.begin(), figure.spectra.end(), [](const Spectrum& s) { return s.resonance > 0; });
  const double top = kPad + (omega_c ? kMajorTick + kTickPad + line_height(cr, kOmegaCFont) : 0);
  const double bottom = kPad + (figure.footnote.empty() ? 0 : line_height(cr, kNoteFont) + kPad) +
                        line_height(cr, kAxisLabelFont) + kPad + line_height(cr, kTickFont) + kTickPad + kMajorTick;
  // A page too small for its labels still gets panels (a point or more): it is drawn, if
  // crowded, rather than losing the run's whole output set.
  const double shared = std::max(height - top - bottom - (residuals ? kPanelGap : 0), 2 * kLeastPanel);
  const double spectrum_height = residuals ? kSpectrumShare * shared : shared;
  const double residual_height = residuals ? shared - spectrum_height : 0;

  ticks.C_x = log_ticks(layout.C_x, static_cast<int>(spectrum_height / (kTickSpacing * kTickFont)), ticks.C_x_minor);
  if (residuals)
    // Zero and one tick on either side at least, however low the panel.
    ticks.residual = linear_ticks(layout.residual,
                                  std::max(3, static_cast<int>(residual_height / (kTickSpacing * kResidualTickFont))));
  double widest = 0;
  for (const Tick& tick : ticks.C_x) widest = std::max(widest, measure(cr, tick.label, kTickFont).width);
  for (const Tick& tick : ticks.residual) widest = std::max(widest, measure(cr, tick.label, kResidualTickFont).width);
  const double left = kPad + line_height(cr, kAxisLabelFont) + kPad + widest + kTickPad + kMajorTick;
  const double right = 3 * kPad;
  const double panel_width = std::max(width - left - right, kLeastPanel);
  ticks.omega = log_ticks(layout.omega, static_cast<int>(panel_width / (3 * kTickFont)), ticks.omega_minor);

  layout.spectrum = {left, top, panel_width, spectrum_height};
  layout.residuals = {left, top + spectrum_height + kPanelGap, panel_width, residual_height};
  layout.omega.start = left;
  layout.omega.end = left + panel_width;
  layout.C_x.start = layout.spectrum.bottom();
  layout.C_x.end = layout.spectrum.top;
  layout.residual.start = layout.residuals.bottom();
  layout.residual.end = layout.residuals.top;
  return layout;
}

Layout draw_page(cairo_t* cr, const SpectrumFigure& figure, const Page& page) {
  const Ranges ranges = ranges_of(figure);
  if (ranges.omega.empty() || ranges.C_x.empty()) throw std::runtime_error("nothing to plot: no positive values");
  const bool residuals =
      figure.residuals && std::any_of(figure.spectra.begin(), figure.spectra.end(), [](const Spectrum& s) {
        for (std::size_t i = 0; i < s.omega.size(); ++i)
          if (has_residual(s, i)) return true;
        return false;
      });
  cairo_font_options_t* options = cairo_font_options_create();
  // Unhinted: text is as wide at every resolution, so the layout is the same in PNG and PDF.
  cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);

  Ticks ticks;
  const Layout layout = lay_out(cr, figure, page, ranges, residuals, ticks);
  const double width = page.width * kPointsPerInch, height = page.height * kPointsPerInch;

  set_color(cr, kWhite);
  cairo_paint(cr);
  draw_grid(cr, layout.spectrum, layout.omega, ticks.omega, layout.C_x, ticks.C_x);
  draw_spectra(cr, figure, layout);
  draw_frame(cr, layout.spectrum);
  draw_ticks(cr, layout.spectrum, layout.C_x, Edge::left, ticks.C_x, ticks.C_x_minor, kTickFont, true);
  draw_ticks(cr, layout.spectrum, layout.omega, Edge::bottom, ticks.omega, ticks.omega_minor, kTickFont, !residuals);
  label_omega_c(cr, figure, layout);
  const Box& bottom_panel = residuals ? layout.residuals : layout.spectrum;
  if (residuals) {
    draw_grid(cr, layout.residuals, layout.omega, ticks.omega, layout.residual, ticks.residual);
    draw_residuals(cr, figure, layout);
    draw_frame(cr, layout.residuals);
    draw_ticks(cr, layout.residuals, layout.residual, Edge::left, ticks.residual, {}, kResidualTickFont, true);
    draw_ticks(cr, layout.residuals, layout.omega, Edge::bottom, ticks.omega, ticks.omega_minor, kTickFont, true);
  }
  draw_legend(cr, figure, layout);

  set_color(cr, kBlack);
  const double label_x = kPad + measure(cr, figure.y_label, kAxisLabelFont).ascent;
  draw_text(cr, figure.y_label, kAxisLabelFont, label_x, layout.spectrum.top + layout.spectrum.height / 2, 0.5,
            Vertical::baseline, M_PI / 2);
  if (residuals)
    draw_text(cr, "*C*_{*x*}/theory − 1", kResidualLabelFont, label_x,
              layout.residuals.top + layout.residuals.height / 2, 0.5, Vertical::baseline, M_PI / 2);
  const double below_ticks = bottom_panel.bottom() + kMajorTick + kTickPad + line_height(cr, kTickFont) + kPad;
  draw_text(cr, "*ω* (rad/s)", kAxisLabelFont, bottom_panel.left + bottom_panel.width / 2, below_ticks, 0.5,
            Vertical::top);
  if (!figure.footnote.empty()) {
    set_color(cr, kNoteGrey);
    draw_text(cr, figure.footnote, kNoteFont, 0.01 * width, height - 0.01 * height, 0, Vertical::bottom);
  }
  return layout;
}

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

using SurfacePointer = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPointer = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

void check(cairo_status_t status) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cannot draw the figure: ") + cairo_status_to_string(status));
}

}  // namespace

int Page::pixel_width() const { return static_cast<int>(std::lround(width * dpi)); }
int Page::pixel_height() const { return static_cast<int>(std::lround(height * dpi)); }

DrawnFigure draw(const SpectrumFigure& figure, const Page& page) {
  DrawnFigure drawn;
  const double width = page.width * kPointsPerInch, height = page.height * kPointsPerInch;
  SurfacePointer surface(nullptr, cairo_surface_destroy);
  if (page.format == Format::png)
    surface.reset(cairo_image_surface_create(CAIRO_FORMAT_RGB24, page.pixel_width(), page.pixel_height()));
  else if (page.format == Format::pdf)
    surface.reset(cairo_pdf_surface_create_for_stream(append, &drawn.bytes, width, height));
  else
    surface.reset(cairo_svg_surface_create_for_stream(append, &drawn.bytes, width, height));
  check(cairo_surface_status(surface.get()));
  {
    ContextPointer cr(cairo_create(surface.get()), cairo_destroy);
    check(cairo_status(cr.get()));
    if (page.format == Format::png) cairo_scale(cr.get(), page.pixel_width() / width, page.pixel_height() / height);
    drawn.layout = draw_page(cr.get(), figure, page);
    check(cairo_status(cr.get()));
  }
  if (page.format == Format::png) {
    cairo_surface_flush(surface.get());
    drawn.bytes = encode_png(cairo_image_surface_get_data(surface.get()), page.pixel_width(), page.pixel_height(),
                             cairo_image_surface_get_stride(surface.get()), page.dpi);
  } else {
    cairo_surface_finish(surface.get());
    check(cairo_surface_status(surface.get()));
  }
  return drawn;
}

}  // namespace slidespec::figure
