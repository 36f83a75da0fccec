// One line of text rendered with a TrueType font through stb_truetype: DejaVu Sans from Debian's
// fonts-dejavu-core unless another .ttf is named. For plot labels and for words stamped on a surface.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "core/image.h"

namespace isoatlas {

inline constexpr const char* kDefaultFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// A grey image (one channel, 255 = ink) just holding the line at `pixelHeight` pixels from the
// ascender to the descender. Throws Error(BadInput) when the font cannot be read or the text is empty.
Image renderText(const std::string& text, int pixelHeight, const std::string& fontPath = kDefaultFont);

// The line drawn into an RGB image, its top-left at (x, y), blended by coverage; clipped.
void drawText(Image& image, int x, int y, const std::string& text, int pixelHeight, std::array<std::uint8_t, 3> colour,
              const std::string& fontPath = kDefaultFont);

}  // namespace isoatlas
