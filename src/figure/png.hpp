// A PNG from a drawn image, written here rather than by cairo: cairo's writer compresses at
// zlib's default level, which alone would take longer than drawing the whole figure.
#pragma once

#include <cairo.h>

#include <cstdint>
#include <string>

namespace slidespec::figure {

/// The bytes of an 8-bit RGB PNG of an opaque image held as cairo's ARGB32 or RGB24 rows
/// (native-endian 32-bit pixels, `stride` bytes apart); the alpha byte is ignored.
/// `dots_per_inch` is stored (pHYs), so viewers and word processors size it right.
std::string encode_png(const unsigned char* pixels, int width, int height, int stride, double dots_per_inch);

/// A PNG read back by cairo's own reader (the caller destroys the surface; its status says
/// whether the bytes were a PNG): what the tests and the benchmark check a written figure by.
cairo_surface_t* read_png(const std::string& png);

}  // namespace slidespec::figure
