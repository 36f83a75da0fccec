// Image: 8-bit pixels, rows top to bottom, `channels` interleaved (1 grey, 3 RGB, 4 RGBA).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace isoatlas {

struct Image {
  int width = 0, height = 0, channels = 3;
  std::vector<std::uint8_t> pixels;

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, 0) {}
  std::uint8_t* at(int x, int y) { return pixels.data() + (std::size_t(y) * width + x) * channels; }
  const std::uint8_t* at(int x, int y) const { return pixels.data() + (std::size_t(y) * width + x) * channels; }
};

void writePng(const std::string& path, const Image& image);  // throws Error on failure
// A PNG file (checked by its signature: no other format), of at most kMaxPngPixels, checked from
// its header before decoding; throws Error naming the file otherwise. Reads edit-detail's --stamp.
inline constexpr std::int64_t kMaxPngPixels = std::int64_t(1) << 26;
Image readPng(const std::string& path);

}  // namespace isoatlas
