#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <utility>

#include <zlib.h>

#include "core/error.h"
#include "core/image.h"
#include "core/plot.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

// Read back by stb_image, a decoder that shares no code with the writer: grey, grey and alpha, RGB
// and RGBA, one row and one column, smooth pixels and pixels of five values (every tie of the Paeth predictor).
TEST(Image, PngRoundTripIsExact) {
  for (const int channels : {1, 2, 3, 4})
    for (const auto& [width, height] : {std::pair{17, 9}, std::pair{1, 5}, std::pair{6, 1}}) {
      for (const bool fewValues : {false, true}) {  // few values: the predictor's ties, every way
        Image img(width, height, channels);
        std::mt19937 rng(7);
        for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = std::uint8_t(fewValues ? rng() % 5 : i * 37 % 251);
        const std::string path = (test::scratchDir() / "a.png").string();
        writePng(path, img);
        const Image back = readPng(path);
        EXPECT_EQ(back.width, width);
        EXPECT_EQ(back.height, height);
        EXPECT_EQ(back.channels, channels);
        EXPECT_EQ(back.pixels, img.pixels) << channels << " channels, " << width << " x " << height;
      }
    }
}

// readPng takes PNG only (a user's --stamp picture): other formats stb_image knows are refused by
// their missing signature, and a header asking for more than kMaxPngPixels before any decoding.
TEST(Image, ReadPngTakesPngOnlyWithinItsSize) {
  const auto dir = test::scratchDir();
  Image small(3, 2, 3);
  writePng((dir / "ok.png").string(), small);
  EXPECT_EQ(readPng((dir / "ok.png").string()).width, 3);
  // A 2 x 2 24-bit BMP: stb_image decodes it, readPng must not.
  std::string bmp = "BM";
  auto le32 = [&](std::uint32_t v) { for (int k = 0; k < 4; ++k) bmp += char((v >> (8 * k)) & 0xff); };
  auto le16 = [&](std::uint16_t v) { bmp += char(v & 0xff), bmp += char(v >> 8); };
  le32(70), le32(0), le32(54), le32(40), le32(2), le32(2), le16(1), le16(24), le32(0), le32(16), le32(2835), le32(2835), le32(0), le32(0);
  bmp += std::string(16, '\x7f');
  test::writeBytes(dir / "picture.png", bmp);
  const Error notPng = test::thrownError([&] { readPng((dir / "picture.png").string()); }, "bmp");
  EXPECT_NE(std::string(notPng.what()).find("no PNG signature"), std::string::npos) << notPng.what();
  // The header of a 9000 x 9000 PNG (8.1e7 pixels), its IHDR's CRC right, no pixel data.
  std::string huge = test::readBytes(dir / "ok.png");
  const std::uint32_t side = 9000;
  for (int k = 0; k < 4; ++k) huge[std::size_t(16 + k)] = huge[std::size_t(20 + k)] = char((side >> (8 * (3 - k))) & 0xff);
  const std::uint32_t crc = std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(huge.data() + 12), 17));
  for (int k = 0; k < 4; ++k) huge[std::size_t(29 + k)] = char((crc >> (8 * (3 - k))) & 0xff);
  test::writeBytes(dir / "huge.png", huge);
  const Error tooLarge = test::thrownError([&] { readPng((dir / "huge.png").string()); }, "huge");
  EXPECT_NE(std::string(tooLarge.what()).find("9000 x 9000"), std::string::npos) << tooLarge.what();
}

TEST(Image, EmptyImageIsRefused) { EXPECT_THROW(writePng((test::scratchDir() / "e.png").string(), Image()), Error); }

// A line plot draws each series in its colour at the place its values map to, and still draws axes
// when nothing is finite (an exact model's PSNR) or the values barely differ.
TEST(Plot, SeriesLandWhereTheirValuesSay) {
  const Image plot = linePlot({{"a", {0, 10}, {20, 20}}}, {.width = 400, .height = 300});
  ASSERT_EQ(plot.width, 400);
  // A horizontal line at y = 20 from x = 0 to 10: some row holds many pixels of the first colour.
  int best = 0;
  for (int y = 0; y < plot.height; ++y) {
    int run = 0;
    for (int x = 0; x < plot.width; ++x) {
      const std::uint8_t* p = plot.at(x, y);
      run += p[0] == 31 && p[1] == 119 && p[2] == 180;
    }
    best = std::max(best, run);
  }
  EXPECT_GT(best, 250);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(linePlot({{"exact", {0, 1}, {inf, inf}}}, {.width = 300, .height = 200}).width, 300);
  EXPECT_EQ(linePlot({{"flat", {0, 1}, {1, 1 + 1e-15}}}, {.width = 300, .height = 200}).height, 200);
  EXPECT_THROW(linePlot({{"bad", {0, 1}, {1}}}, {}), Error);
}

}  // namespace
}  // namespace isoatlas
