#include "figure/png.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <memory>
#include <stdexcept>
#include <vector>

namespace slidespec::figure {

namespace {

// zlib's fastest level on unfiltered rows: for a figure (runs of white, lines, text) the
// smallest of the fast choices measured, ~115 kB for a run's figure at 150 dpi; the
// default level would take four times as long.
constexpr int kCompressionLevel = 1;
constexpr unsigned char kNoFilter = 0;
// Below this many rows one thread compresses the whole image.
constexpr int kRowsWorthAThread = 64;

void put_u32(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xff));
}

void put_chunk(std::string& out, const char* type, const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.append(type, 4);
  out.append(data);
  const auto* checked = reinterpret_cast<const Bytef*>(out.data() + start);
  put_u32(out, static_cast<std::uint32_t>(crc32(0, checked, static_cast<uInt>(out.size() - start))));
}

/// Rows [first, last) as PNG scanlines: a filter byte, then red, green, blue per pixel.
/// Not cleared first: every byte is written.
struct Scanlines {
  std::unique_ptr<unsigned char[]> bytes;
  std::size_t size;
};

Scanlines scanlines(const unsigned char* pixels, int width, int stride, int first, int last) {
  const auto row_bytes = 1 + 3 * static_cast<std::size_t>(width);
  Scanlines rows{std::make_unique_for_overwrite<unsigned char[]>(row_bytes * static_cast<std::size_t>(last - first)),
                 row_bytes * static_cast<std::size_t>(last - first)};
  unsigned char* out = rows.bytes.get();
  for (int y = first; y < last; ++y) {
    const auto* source = reinterpret_cast<const std::uint32_t*>(pixels + static_cast<std::ptrdiff_t>(y) * stride);
    *out++ = kNoFilter;
    for (int x = 0; x < width; ++x) {
      const std::uint32_t pixel = source[x];
      *out++ = static_cast<unsigned char>(pixel >> 16);
      *out++ = static_cast<unsigned char>(pixel >> 8);
      *out++ = static_cast<unsigned char>(pixel);
    }
  }
  return rows;
}

/// One part of a zlib stream split as pigz splits it: the first part carries the zlib
/// header and ends on a byte boundary (a sync flush), a last part is raw deflate ending the
/// stream. The checksum of the whole is appended by the caller.
std::string deflate_part(const Scanlines& data, bool first, bool last) {
  z_stream stream{};
  if (deflateInit2(&stream, kCompressionLevel, Z_DEFLATED, first ? 15 : -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("encode_png: zlib failed to start");
  stream.next_in = data.bytes.get();
  stream.avail_in = static_cast<uInt>(data.size);
  // In pieces: a figure compresses ~25-fold, so a buffer of deflateBound (the input's size)
  // would mostly be memory cleared and never written.
  std::string compressed;
  unsigned char piece[1 << 16];
  int status = Z_OK;
  do {
    stream.next_out = piece;
    stream.avail_out = sizeof piece;
    status = deflate(&stream, last ? Z_FINISH : Z_SYNC_FLUSH);
    if (status == Z_BUF_ERROR) status = Z_OK;  // the flush had ended on a full piece: nothing more
    compressed.append(reinterpret_cast<const char*>(piece), sizeof piece - stream.avail_out);
  } while (status == Z_OK && stream.avail_out == 0);
  deflateEnd(&stream);
  if (status != (last ? Z_STREAM_END : Z_OK)) throw std::runtime_error("encode_png: zlib failed");
  return compressed;
}

/// A part of the scanlines compressed, with the checksum and length of what it holds.
struct Part {
  std::string compressed;
  uLong checksum;
  std::size_t length;
};

Part compress_rows(const unsigned char* pixels, int width, int stride, int first, int last, bool first_part,
                   bool last_part) {
  const Scanlines rows = scanlines(pixels, width, stride, first, last);
  return {deflate_part(rows, first_part, last_part), adler32(1, rows.bytes.get(), static_cast<uInt>(rows.size)),
          rows.size};
}

}  // namespace

std::string encode_png(const unsigned char* pixels, int width, int height, int stride, double dots_per_inch) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("encode_png: empty image");
  // Two halves on two threads: the run's cores are free when its figure is drawn.
  const bool split = height >= kRowsWorthAThread;
  const int middle = split ? height / 2 : height;
  std::future<Part> lower;
  if (split) lower = std::async(std::launch::async, compress_rows, pixels, width, stride, middle, height, false, true);
  const Part upper = compress_rows(pixels, width, stride, 0, middle, true, !split);
  std::string stream = upper.compressed;
  if (split) {
    const Part rest = lower.get();
    stream += rest.compressed;
    put_u32(stream, static_cast<std::uint32_t>(
                        adler32_combine(upper.checksum, rest.checksum, static_cast<z_off_t>(rest.length))));
  }

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put_u32(header, static_cast<std::uint32_t>(width));
  put_u32(header, static_cast<std::uint32_t>(height));
  header.append({8, 2, 0, 0, 0});  // 8 bits per sample, RGB, deflate, adaptive filters, no interlace
  put_chunk(png, "IHDR", header);
  std::string physical;
  const auto dots_per_metre = static_cast<std::uint32_t>(std::lround(dots_per_inch / 0.0254));
  put_u32(physical, dots_per_metre);
  put_u32(physical, dots_per_metre);
  physical.push_back(1);  // the unit is the metre
  put_chunk(png, "pHYs", physical);
  put_chunk(png, "IDAT", stream);
  put_chunk(png, "IEND", "");
  return png;
}

cairo_surface_t* read_png(const std::string& png) {
  struct Reading {
    const std::string* bytes;
    std::size_t at;
  } reading{&png, 0};
  return cairo_image_surface_create_from_png_stream(
      [](void* closure, unsigned char* data, unsigned int length) {
        auto* r = static_cast<Reading*>(closure);
        if (r->at + length > r->bytes->size()) return CAIRO_STATUS_READ_ERROR;
        std::copy_n(r->bytes->data() + r->at, length, data);
        r->at += length;
        return CAIRO_STATUS_SUCCESS;
      },
      &reading);
}

}  // namespace slidespec::figure
