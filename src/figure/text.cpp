#include "figure/text.hpp"

#include <cairo-ft.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace slidespec::figure {

namespace {

// Script sizes and shifts as fractions of the font size, close to TeX's.
constexpr double kScriptScale = 0.7;
constexpr double kSuperscriptRise = 0.45;
constexpr double kSubscriptDrop = 0.18;
// DejaVu Sans's capital height: the middle of a line of digits or capitals.
constexpr double kCapitalHeight = 0.73;

struct Piece {
  std::string text;
  bool italic = false;
  int script = 0;  // +1 superscript, -1 subscript
};

std::vector<Piece> parse(const std::string& markup) {
  std::vector<Piece> pieces(1);
  bool italic = false;
  int script = 0;
  auto start = [&] {
    if (!pieces.back().text.empty()) pieces.emplace_back();
    pieces.back().italic = italic;
    pieces.back().script = script;
  };
  for (std::size_t i = 0; i < markup.size(); ++i) {
    const char c = markup[i];
    if (c == '\\' && i + 1 < markup.size()) {
      pieces.back().text += markup[++i];
    } else if (c == '*') {
      italic = !italic;
      start();
    } else if ((c == '_' || c == '^') && i + 1 < markup.size() && markup[i + 1] == '{') {
      script = c == '^' ? 1 : -1;
      ++i;
      start();
    } else if (c == '}' && script != 0) {
      script = 0;
      start();
    } else {
      pieces.back().text += c;
    }
  }
  return pieces;
}

void use_font(cairo_t* cr, const Piece& piece, double size) {
  cairo_set_font_face(cr, piece.italic ? fonts().italic : fonts().upright);
  cairo_set_font_size(cr, piece.script != 0 ? size * kScriptScale : size);
}

double rise(const Piece& piece, double size) {
  return piece.script > 0 ? kSuperscriptRise * size : piece.script < 0 ? -kSubscriptDrop * size : 0;
}

}  // namespace

namespace {

// Debian's fonts-dejavu-core, read directly: fontconfig's start (3-7 ms) would be most of
// what a figure's text costs.
constexpr const char* kDejaVuDirectory = "/usr/share/fonts/truetype/dejavu/";

/// The face in `file` of DejaVu's directory, else DejaVu Sans in that slant as fontconfig
/// finds it (another system's layout).
cairo_font_face_t* dejavu(const char* file, cairo_font_slant_t slant) {
  static FT_Library library = [] {
    FT_Library opened = nullptr;
    return FT_Init_FreeType(&opened) == 0 ? opened : nullptr;
  }();
  FT_Face face = nullptr;
  if (library != nullptr && FT_New_Face(library, (std::string(kDejaVuDirectory) + file).c_str(), 0, &face) == 0)
    return cairo_ft_font_face_create_for_ft_face(face, 0);  // both live as long as the process
  return cairo_toy_font_face_create("DejaVu Sans", slant, CAIRO_FONT_WEIGHT_NORMAL);
}

}  // namespace

const Fonts& fonts() {
  static const Fonts faces = {dejavu("DejaVuSans.ttf", CAIRO_FONT_SLANT_NORMAL),
                              dejavu("DejaVuSans-Oblique.ttf", CAIRO_FONT_SLANT_OBLIQUE)};
  return faces;
}

std::string literal(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '\\' || c == '*' || c == '_' || c == '^' || c == '}') escaped += '\\';
    escaped += c;
  }
  return escaped;
}

Extent measure(cairo_t* cr, const std::string& markup, double size) {
  Extent extent;
  cairo_save(cr);
  for (const Piece& piece : parse(markup)) {
    if (piece.text.empty()) continue;
    use_font(cr, piece, size);
    cairo_text_extents_t text;
    cairo_text_extents(cr, piece.text.c_str(), &text);
    cairo_font_extents_t font;
    cairo_font_extents(cr, &font);
    extent.width += text.x_advance;
    extent.ascent = std::max(extent.ascent, font.ascent + rise(piece, size));
    extent.descent = std::max(extent.descent, font.descent - rise(piece, size));
  }
  cairo_restore(cr);
  return extent;
}

void draw_text(cairo_t* cr, const std::string& markup, double size, double x, double y, double horizontal,
               Vertical vertical, double angle) {
  const Extent extent = measure(cr, markup, size);
  const double baseline = vertical == Vertical::baseline ? 0
                          : vertical == Vertical::top    ? kCapitalHeight * size
                          : vertical == Vertical::middle ? kCapitalHeight * size / 2
                                                         : -extent.descent;
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, -angle);
  double pen = -horizontal * extent.width;
  for (const Piece& piece : parse(markup)) {
    if (piece.text.empty()) continue;
    use_font(cr, piece, size);
    cairo_move_to(cr, pen, baseline - rise(piece, size));
    cairo_show_text(cr, piece.text.c_str());
    double ignored = 0;
    cairo_get_current_point(cr, &pen, &ignored);
  }
  cairo_restore(cr);
}

}  // namespace slidespec::figure
