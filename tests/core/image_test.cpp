#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

TEST(Image, PngRoundTripIsExact) {
  Image img(17, 9, 3);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = std::uint8_t(i * 37 % 251);
  const std::string path = (test::scratchDir() / "a.png").string();
  writePng(path, img);
  const Image back = readPng(path);
  EXPECT_EQ(back.width, 17);
  EXPECT_EQ(back.height, 9);
  EXPECT_EQ(back.channels, 3);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(Image, EmptyImageIsRefused) { EXPECT_THROW(writePng((test::scratchDir() / "e.png").string(), Image()), Error); }

}  // namespace
}  // namespace isoatlas
