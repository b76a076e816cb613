// Labels with the little mathematics a spectrum's figure needs: italic symbols, sub- and
// superscripts. Markup: *...* italic, _{...} subscript, ^{...} superscript, \ takes the
// next character as written ("reference: N = 30, *α* = 1", "*C*_{*x*} (m² s)", "10^{−8}").
#pragma once

#include <cairo.h>

#include <string>

namespace slidespec::figure {

/// The faces every label is set in (DejaVu Sans, upright and oblique), made once per process.
struct Fonts {
  cairo_font_face_t* upright;
  cairo_font_face_t* italic;
};
const Fonts& fonts();

/// `text` with every markup character escaped, to be set as written (a file name).
std::string literal(const std::string& text);

/// How much room a label takes [pt]: its advance, and how far it reaches above and below
/// its baseline.
struct Extent {
  double width = 0, ascent = 0, descent = 0;
};
Extent measure(cairo_t* cr, const std::string& markup, double size);

/// Where a label's anchor sits on it: horizontally 0 left, 0.5 centre, 1 right;
/// vertically by the baseline, the top of capitals, their middle, or the lowest descent.
enum class Vertical { baseline, top, middle, bottom };

/// Sets `markup` at `size` points, its anchor at (x, y), turned by `angle` radians
/// (counter-clockwise), in the current source colour.
void draw_text(cairo_t* cr, const std::string& markup, double size, double x, double y, double horizontal,
               Vertical vertical, double angle = 0);

}  // namespace slidespec::figure
