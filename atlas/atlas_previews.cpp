#include "atlas/atlas_previews.h"

#include <algorithm>
#include <limits>

#include "atlas/backfacing_quads.h"

namespace isoatlas::atlas {
namespace {

// Calls visit(pixel index, chart, i, j) for every chart texel.
template <class Visit>
void forChartTexels(const AtlasLayout& l, Visit&& visit) {
  for (std::uint32_t c = 0; c < l.charts; ++c)
    for (std::uint32_t j = 0; j < l.chartSize; ++j)
      for (std::uint32_t i = 0; i < l.chartSize; ++i) visit(l.texel(c, i, j));
}

std::uint8_t byte(double x) { return std::uint8_t(std::clamp(x, 0.0, 1.0) * 255 + 0.5); }

}  // namespace

Image positionPreview(const Atlas& atlas) {
  const AtlasLayout& l = atlas.layout;
  Image image(int(l.width()), int(l.height()), 3);
  std::array<float, 3> lo, hi;
  lo.fill(std::numeric_limits<float>::max()), hi.fill(std::numeric_limits<float>::lowest());
  forChartTexels(l, [&](std::size_t at) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], atlas.positions[at][a]), hi[a] = std::max(hi[a], atlas.positions[at][a]);
  });
  forChartTexels(l, [&](std::size_t at) {
    for (int a = 0; a < 3; ++a)
      image.pixels[at * 3 + a] = byte(hi[a] > lo[a] ? (double(atlas.positions[at][a]) - lo[a]) / (double(hi[a]) - lo[a]) : 0.5);
  });
  return image;
}

Image normalPreview(const Atlas& atlas) {
  Image image(int(atlas.layout.width()), int(atlas.layout.height()), 3);
  forChartTexels(atlas.layout, [&](std::size_t at) {
    const Vec3 n = unpackNormal(atlas.normals[at]);
    for (int a = 0; a < 3; ++a) image.pixels[at * 3 + a] = byte((n[a] + 1) / 2);
  });
  return image;
}

Image backFacingPreview(const Atlas& atlas) {
  Image image = normalPreview(atlas);
  for (std::uint8_t& v : image.pixels) v = std::uint8_t(v / 3);
  const AtlasLayout& l = atlas.layout;
  const bool faces = !atlas.triangleFaceNormals.empty();
  auto mark = [&](std::uint32_t c, std::uint32_t a, std::uint32_t b, std::uint8_t green) {
    for (const auto& [i, j] : {std::array{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}}) {
      const std::size_t at = l.texel(c, i, j) * 3;
      if (image.pixels[at] == 255 && image.pixels[at + 2] == 0 && image.pixels[at + 1] < green) continue;  // red stays over yellow
      image.pixels[at] = 255, image.pixels[at + 1] = green, image.pixels[at + 2] = 0;
    }
  };
  for (std::uint32_t c = 0; c < l.charts; ++c)
    for (std::uint32_t b = 0; b + 1 < l.chartSize; ++b)
      for (std::uint32_t a = 0; a + 1 < l.chartSize; ++a) {
        if (faces ? quadFolds(atlas, c, a, b) : quadFacesBackwards(atlas, c, a, b)) mark(c, a, b, 0);
        else if (faces && quadFacesBackwards(atlas, c, a, b)) mark(c, a, b, 255);
      }
  return image;
}

}  // namespace isoatlas::atlas
