#include "core/image.h"

#include <stb/stb_image.h>
#include <zlib.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "core/atomic_file.h"
#include "core/deflate.h"
#include "core/error.h"

namespace isoatlas {

namespace {

// Paeth's predictor (the PNG specification's filter type 4) of a byte from its left, upper and
// upper-left neighbours.
std::uint8_t paeth(int left, int up, int upLeft) {
  const int p = left + up - upLeft, toLeft = std::abs(p - left), toUp = std::abs(p - up), toUpLeft = std::abs(p - upLeft);
  return std::uint8_t(toLeft <= toUp && toLeft <= toUpLeft ? left : toUp <= toUpLeft ? up : upLeft);
}

// The image's rows as PNG's filtered scanlines: each row Paeth-filtered, as renders and atlases vary
// smoothly, and so predicted well.
std::vector<std::uint8_t> paethScanlines(const Image& image) {
  const std::size_t stride = std::size_t(image.width) * std::size_t(image.channels), c = std::size_t(image.channels);
  std::vector<std::uint8_t> out((stride + 1) * std::size_t(image.height));
  for (std::size_t y = 0; y < std::size_t(image.height); ++y) {
    const std::uint8_t* row = image.pixels.data() + y * stride;
    const std::uint8_t* up = y ? row - stride : nullptr;
    std::uint8_t* to = out.data() + y * (stride + 1);
    *to++ = 4;
    for (std::size_t i = 0; i < stride; ++i) {
      const int left = i >= c ? row[i - c] : 0, above = up ? up[i] : 0, aboveLeft = up && i >= c ? up[i - c] : 0;
      to[i] = std::uint8_t(row[i] - paeth(left, above, aboveLeft));
    }
  }
  return out;
}

void appendBigEndian(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += char(v >> shift & 0xff);
}
void appendChunk(std::string& out, const char (&type)[5], const std::uint8_t* data, std::size_t size) {
  appendBigEndian(out, std::uint32_t(size));
  const std::size_t start = out.size();
  out.append(type, 4);
  if (size) out.append(reinterpret_cast<const char*>(data), size);
  appendBigEndian(out, std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(out.data() + start), uInt(out.size() - start))));
}

}  // namespace

// Written here around zlib rather than by stb_image_write: its own deflate and its trial of every
// filter on every row were slow on large images (the model's atlases; bench/RESULTS.md).
void writePng(const std::string& path, const Image& image) {
  require(image.width > 0 && image.height > 0 && image.pixels.size() == std::size_t(image.width) * image.height * image.channels,
          path + ": image has no pixels or inconsistent size");
  static constexpr std::uint8_t kColourType[5] = {0, 0, 4, 2, 6};  // grey, grey + alpha, RGB, RGBA by channels
  require(image.channels >= 1 && image.channels <= 4, path + ": an image has 1 to 4 channels");
  const std::vector<std::uint8_t> scanlines = paethScanlines(image);
  const std::vector<std::uint8_t> packed = deflateBytes(scanlines.data(), scanlines.size(), Z_BEST_SPEED, path);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::uint8_t header[13] = {};
  for (int k = 0; k < 4; ++k) {
    header[k] = std::uint8_t(std::uint32_t(image.width) >> (24 - 8 * k));
    header[4 + k] = std::uint8_t(std::uint32_t(image.height) >> (24 - 8 * k));
  }
  header[8] = 8;  // bits a sample; compression, filter method and interlace stay 0
  header[9] = kColourType[image.channels];
  appendChunk(png, "IHDR", header, sizeof header);
  appendChunk(png, "IDAT", packed.data(), packed.size());
  appendChunk(png, "IEND", nullptr, 0);
  writeFileAtomically(path, png);
}

Image readPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": no such file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // stb_image reads every format it knows; a user's picture (edit-detail --stamp) is taken as PNG only.
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) throw Error(path + ": not a PNG file (no PNG signature)");
  if (bytes.size() > std::size_t(std::numeric_limits<int>::max())) throw Error(path + ": too large for a PNG isoatlas reads");
  const auto* begin = reinterpret_cast<const stbi_uc*>(bytes.data());
  int w = 0, h = 0, c = 0;
  // The size from the header, before a pixel is decoded.
  if (!stbi_info_from_memory(begin, int(bytes.size()), &w, &h, &c)) throw Error(path + ": not a readable PNG: " + stbi_failure_reason());
  if (std::int64_t(w) * h > kMaxPngPixels)
    throw Error(path + ": a PNG of " + std::to_string(w) + " x " + std::to_string(h) + " pixels; isoatlas reads at most " +
                std::to_string(kMaxPngPixels) + " pixels");
  unsigned char* data = stbi_load_from_memory(begin, int(bytes.size()), &w, &h, &c, 0);
  if (!data) throw Error(path + ": not a readable PNG: " + stbi_failure_reason());
  Image img(w, h, c);
  std::copy(data, data + img.pixels.size(), img.pixels.begin());
  stbi_image_free(data);
  return img;
}

}  // namespace isoatlas
