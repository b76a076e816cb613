// The PNG writer (src/figure/png.cpp): a file any reader accepts, holding the very pixels
// given. Read back twice: chunk by chunk here (CRCs, zlib's inflate), and by cairo's reader.
#include <cairo.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

#include "figure/png.hpp"

namespace slidespec::figure {
namespace {

std::uint32_t u32_at(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t k = 0; k < 4; ++k) value = value << 8 | static_cast<unsigned char>(bytes[at + k]);
  return value;
}

struct Decoded {
  std::uint32_t width = 0, height = 0, dots_per_metre = 0;
  std::string scanlines;
};

/// Walks the chunks, checking each CRC, and inflates the image data.
Decoded decode(const std::string& png) {
  Decoded decoded;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string compressed;
  std::vector<std::string> types;
  for (std::size_t at = 8; at + 12 <= png.size();) {
    const std::uint32_t length = u32_at(png, at);
    const std::string type = png.substr(at + 4, 4);
    const auto* checked = reinterpret_cast<const Bytef*>(png.data() + at + 4);
    EXPECT_EQ(u32_at(png, at + 8 + length), crc32(0, checked, length + 4)) << "CRC of " << type;
    if (type == "IHDR") {
      decoded.width = u32_at(png, at + 8);
      decoded.height = u32_at(png, at + 12);
      EXPECT_EQ(png[at + 16], 8);  // bits per sample
      EXPECT_EQ(png[at + 17], 2);  // RGB
    }
    if (type == "pHYs") decoded.dots_per_metre = u32_at(png, at + 8);
    if (type == "IDAT") compressed += png.substr(at + 8, length);
    types.push_back(type);
    at += 12 + length;
  }
  EXPECT_FALSE(types.empty());
  if (types.empty()) return decoded;
  EXPECT_EQ(types.front(), "IHDR");
  EXPECT_EQ(types.back(), "IEND");
  decoded.scanlines.resize(static_cast<std::size_t>(decoded.height) * (1 + 3 * decoded.width));
  uLongf size = decoded.scanlines.size();
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(decoded.scanlines.data()), &size,
                       reinterpret_cast<const Bytef*>(compressed.data()), compressed.size()),
            Z_OK);
  EXPECT_EQ(size, decoded.scanlines.size());
  return decoded;
}

/// A test card: stripes of colour and a gradient, so that every row differs.
std::vector<std::uint32_t> test_card(int width, int height) {
  std::vector<std::uint32_t> pixels(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      pixels[static_cast<std::size_t>(y) * width + x] = 0xff000000u | static_cast<std::uint32_t>((x * 7) & 0xff) << 16 |
                                                        static_cast<std::uint32_t>((y * 3) & 0xff) << 8 |
                                                        static_cast<std::uint32_t>((x / 5 + y) % 2 ? 0xff : 0x20);
  return pixels;
}

// Heights on both sides of the split into two halves (64 rows), odd and even.
class PngSizes : public testing::TestWithParam<std::pair<int, int>> {};

TEST_P(PngSizes, HoldsThePixelsGiven) {
  const auto [width, height] = GetParam();
  const std::vector<std::uint32_t> pixels = test_card(width, height);
  const std::string png =
      encode_png(reinterpret_cast<const unsigned char*>(pixels.data()), width, height, width * 4, 150);
  const Decoded decoded = decode(png);
  ASSERT_EQ(decoded.width, static_cast<std::uint32_t>(width));
  ASSERT_EQ(decoded.height, static_cast<std::uint32_t>(height));
  EXPECT_EQ(decoded.dots_per_metre, 5906u);  // 150 dpi
  for (int y = 0; y < height; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * (1 + 3 * width);
    ASSERT_EQ(decoded.scanlines[row], 0) << "row " << y << " filtered";
    for (int x = 0; x < width; ++x) {
      const std::uint32_t pixel = pixels[static_cast<std::size_t>(y) * width + x];
      const auto* rgb = reinterpret_cast<const unsigned char*>(decoded.scanlines.data() + row + 1 + 3 * x);
      ASSERT_EQ(rgb[0], (pixel >> 16) & 0xff) << x << "," << y;
      ASSERT_EQ(rgb[1], (pixel >> 8) & 0xff) << x << "," << y;
      ASSERT_EQ(rgb[2], pixel & 0xff) << x << "," << y;
    }
  }
}

TEST_P(PngSizes, CairosReaderAgrees) {
  const auto [width, height] = GetParam();
  const std::vector<std::uint32_t> pixels = test_card(width, height);
  const std::string png =
      encode_png(reinterpret_cast<const unsigned char*>(pixels.data()), width, height, width * 4, 72);
  cairo_surface_t* image = read_png(png);
  ASSERT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(image), width);
  EXPECT_EQ(cairo_image_surface_get_height(image), height);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  for (int y = 0; y < height; y += 7)
    for (int x = 0; x < width; x += 3)
      ASSERT_EQ(reinterpret_cast<const std::uint32_t*>(data + y * stride)[x] & 0xffffff,
                pixels[static_cast<std::size_t>(y) * width + x] & 0xffffff)
          << x << "," << y;
  cairo_surface_destroy(image);
}

// Noise does not compress: each half's stream spans several of the writer's 64 kB pieces.
TEST(Png, IncompressiblePixelsSurviveWhole) {
  const int width = 300, height = 300;
  std::vector<std::uint32_t> pixels(static_cast<std::size_t>(width) * height);
  std::uint32_t state = 12345;
  for (std::uint32_t& pixel : pixels) pixel = 0xff000000u | ((state = state * 1664525u + 1013904223u) >> 8);
  const std::string png =
      encode_png(reinterpret_cast<const unsigned char*>(pixels.data()), width, height, width * 4, 150);
  EXPECT_GT(png.size(), std::size_t{4} << 16);
  const Decoded decoded = decode(png);
  ASSERT_EQ(decoded.scanlines.size(), static_cast<std::size_t>(height) * (1 + 3 * width));
  for (int y = 0; y < height; y += 17)
    for (int x = 0; x < width; x += 13) {
      const std::uint32_t pixel = pixels[static_cast<std::size_t>(y) * width + x];
      const auto* rgb = reinterpret_cast<const unsigned char*>(decoded.scanlines.data()) +
                        static_cast<std::size_t>(y) * (1 + 3 * width) + 1 + 3 * x;
      ASSERT_EQ(rgb[0], (pixel >> 16) & 0xff) << x << "," << y;
      ASSERT_EQ(rgb[2], pixel & 0xff) << x << "," << y;
    }
}

INSTANTIATE_TEST_SUITE_P(Png, PngSizes,
                         testing::Values(std::make_pair(1, 1), std::make_pair(13, 63), std::make_pair(40, 64),
                                         std::make_pair(33, 131), std::make_pair(1050, 930)));

}  // namespace
}  // namespace slidespec::figure
