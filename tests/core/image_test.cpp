#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <utility>

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
