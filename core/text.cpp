#include "core/text.h"

#include <stb/stb_truetype.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace isoatlas {
namespace {

struct Font {
  std::vector<unsigned char> bytes;
  stbtt_fontinfo info{};
};

// Fonts stay loaded once read (a plot draws many labels).
const Font& loadFont(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, Font> fonts;
  const std::lock_guard lock(mutex);
  auto it = fonts.find(path);
  if (it != fonts.end()) return it->second;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot read the font (install fonts-dejavu-core, or name a .ttf file)");
  Font font;
  font.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  // stb_truetype trusts the file: its table directory is checked against the file's size first
  // (a plain TrueType or OpenType font; collections are refused).
  const auto& b = font.bytes;
  auto u16 = [&](std::size_t at) { return std::uint32_t(b[at]) << 8 | b[at + 1]; };
  auto u32 = [&](std::size_t at) { return u16(at) << 16 | u16(at + 2); };
  const bool sfnt = b.size() >= 12 && (u32(0) == 0x00010000u || u32(0) == 0x74727565u || u32(0) == 0x4f54544fu);
  const std::size_t tables = sfnt ? u16(4) : 0;
  bool sound = sfnt && 12 + 16 * tables <= b.size();
  for (std::size_t t = 0; sound && t < tables; ++t) {
    const std::uint64_t offset = u32(12 + 16 * t + 8), length = u32(12 + 16 * t + 12);
    sound = offset + length <= b.size();
  }
  if (!sound || !stbtt_InitFont(&font.info, font.bytes.data(), 0)) throw Error(path + ": not a TrueType font");
  return fonts.emplace(path, std::move(font)).first->second;
}

}  // namespace

Image renderText(const std::string& text, int pixelHeight, const std::string& fontPath) {
  require(!text.empty(), "no text to render");
  require(pixelHeight >= 4 && pixelHeight <= 1024, "text height must be 4 to 1024 pixels");
  const Font& font = loadFont(fontPath);
  const float scale = stbtt_ScaleForPixelHeight(&font.info, float(pixelHeight));
  int ascent, descent, gap;
  stbtt_GetFontVMetrics(&font.info, &ascent, &descent, &gap);
  const int baseline = int(std::ceil(ascent * scale));
  // Width: the advances (bytes taken as Latin-1 code points), plus the last glyph's overhang.
  float width = 0;
  for (const unsigned char ch : text) {
    int advance, bearing;
    stbtt_GetCodepointHMetrics(&font.info, ch, &advance, &bearing);
    width += advance * scale;
  }
  Image image(int(std::ceil(width)) + pixelHeight / 4 + 1, baseline + int(std::ceil(-descent * scale)) + 1, 1);
  float x = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const int ch = static_cast<unsigned char>(text[i]);
    int advance, bearing, x0, y0, x1, y1;
    stbtt_GetCodepointHMetrics(&font.info, ch, &advance, &bearing);
    stbtt_GetCodepointBitmapBox(&font.info, ch, scale, scale, &x0, &y0, &x1, &y1);
    const int gx = int(std::lround(x)) + x0, gy = baseline + y0;
    if (x1 > x0 && y1 > y0) {
      std::vector<unsigned char> glyph(std::size_t(x1 - x0) * (y1 - y0));
      stbtt_MakeCodepointBitmap(&font.info, glyph.data(), x1 - x0, y1 - y0, x1 - x0, scale, scale, ch);
      for (int y = 0; y < y1 - y0; ++y)
        for (int gxi = 0; gxi < x1 - x0; ++gxi) {
          const int px = gx + gxi, py = gy + y;
          if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
          std::uint8_t& p = *image.at(px, py);
          p = std::max(p, glyph[std::size_t(y) * (x1 - x0) + gxi]);
        }
    }
    x += advance * scale;
    if (i + 1 < text.size()) x += scale * stbtt_GetCodepointKernAdvance(&font.info, ch, static_cast<unsigned char>(text[i + 1]));
  }
  return image;
}

void drawText(Image& image, int x, int y, const std::string& text, int pixelHeight, std::array<std::uint8_t, 3> colour,
              const std::string& fontPath) {
  const Image mask = renderText(text, pixelHeight, fontPath);
  for (int my = 0; my < mask.height; ++my)
    for (int mx = 0; mx < mask.width; ++mx) {
      const int px = x + mx, py = y + my;
      if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
      const double a = *mask.at(mx, my) / 255.0;
      std::uint8_t* p = image.at(px, py);
      for (int c = 0; c < 3 && c < image.channels; ++c) p[c] = std::uint8_t(std::lround(p[c] * (1 - a) + colour[c] * a));
    }
}

}  // namespace isoatlas
