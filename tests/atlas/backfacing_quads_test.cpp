// The fold measure of the drawn atlas (atlas/backfacing_quads.h) against charts turned by hand.
#include <gtest/gtest.h>

#include "atlas/atlas_previews.h"
#include "atlas/backfacing_quads.h"
#include "atlas/make_atlas.h"
#include "core/error.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::atlas {
namespace {

Atlas torusAtlas(const multires::BaseMesh*& baseOut) {
  static const Mesh dense = test::torusMesh(48, 24);
  static multires::BaseMesh base = [] {
    multires::BaseMesh b = multires::simplifyStellar(dense, {.vertexRatio = 0.04});
    multires::pairTriangles(b, dense);
    return b;
  }();
  baseOut = &base;
  return makeAtlas(dense, base, 17);
}

void setPosition(Atlas& atlas, std::uint32_t c, std::uint32_t i, std::uint32_t j, const Vec3& p) {
  atlas.positions[atlas.layout.texel(c, i, j)] = {float(p.x), float(p.y), float(p.z)};
}

// A chart with none, mirrored in u: every one of its quads then faces into the torus; nothing else changes.
TEST(BackFacingQuads, EveryQuadOfAMirroredChartTurns) {
  const multires::BaseMesh* base = nullptr;
  Atlas atlas = torusAtlas(base);
  const std::uint32_t n = atlas.layout.chartSize;
  const BackFacingQuads before = countBackFacingQuads(atlas);
  EXPECT_EQ(before.total, std::uint64_t(atlas.layout.charts) * (n - 1) * (n - 1));
  EXPECT_LT(before.quads, before.total / 20) << "most of the torus's quads follow its surface";
  std::uint32_t c = 0;
  while (c < atlas.layout.charts && before.perChart[c] > 0) ++c;
  ASSERT_LT(c, atlas.layout.charts) << "no chart without turned quads";
  const Atlas original = atlas;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) setPosition(atlas, c, i, j, original.position(c, n - 1 - i, j));
  const BackFacingQuads mirrored = countBackFacingQuads(atlas);
  EXPECT_EQ(mirrored.perChart[c], std::uint64_t(n - 1) * (n - 1));
  EXPECT_EQ(mirrored.quads, before.quads + std::uint64_t(n - 1) * (n - 1));
  EXPECT_EQ(mirrored.charts, before.charts + 1);
  EXPECT_EQ(mirrored.worstChart, c);
  const Vec3 centre = atlas.position(c, n / 2, n / 2);
  EXPECT_TRUE(mirrored.worstChartCentre.x == centre.x && mirrored.worstChartCentre.y == centre.y && mirrored.worstChartCentre.z == centre.z);
  EXPECT_EQ(countFoldedQuads(atlas).perChart[c], std::uint64_t(n - 1) * (n - 1)) << "it folds against its faces too";
  // The picture of where: every texel of the mirrored chart red; elsewhere red only at the corners
  // of the quads that fold, yellow at the other corners of those facing against the shading normals.
  const Image picture = backFacingPreview(atlas);
  auto colour = [&](std::uint32_t chart, std::uint32_t i, std::uint32_t j, std::uint8_t green) {
    const std::size_t at = atlas.layout.texel(chart, i, j) * 3;
    return picture.pixels[at] == 255 && picture.pixels[at + 1] == green && picture.pixels[at + 2] == 0;
  };
  for (std::uint32_t d = 0; d < atlas.layout.charts; ++d)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        bool folds = false, faces = false;  // a corner of a quad that folds, that faces backwards
        for (std::uint32_t b = j > 0 ? j - 1 : 0; b <= std::min(j, n - 2); ++b)
          for (std::uint32_t a = i > 0 ? i - 1 : 0; a <= std::min(i, n - 2); ++a)
            folds |= quadFolds(atlas, d, a, b), faces |= quadFacesBackwards(atlas, d, a, b);
        EXPECT_EQ(colour(d, i, j, 0), folds) << "chart " << d << " texel " << i << ", " << j;
        EXPECT_EQ(colour(d, i, j, 255), faces && !folds) << "chart " << d << " texel " << i << ", " << j;
        if (d == c) {
          EXPECT_TRUE(folds);
        }
      }
}

// An inner texel of a chart with none pushed past its neighbour: only quads at that texel turn.
TEST(BackFacingQuads, ATexelPushedPastItsNeighbourTurnsOnlyTheQuadsAroundIt) {
  const multires::BaseMesh* base = nullptr;
  Atlas atlas = torusAtlas(base);
  const BackFacingQuads before = countBackFacingQuads(atlas);
  std::uint32_t c = 0;
  while (c < atlas.layout.charts && before.perChart[c] > 0) ++c;
  ASSERT_LT(c, atlas.layout.charts);
  const Vec3 a = atlas.position(c, 5, 5), b = atlas.position(c, 7, 5);
  setPosition(atlas, c, 5, 5, b + (b - a) * 0.5);
  const BackFacingQuads turned = countBackFacingQuads(atlas);
  EXPECT_GE(turned.perChart[c], 1u);
  EXPECT_LE(turned.perChart[c], 4u) << "only the four quads at the texel";
  EXPECT_EQ(turned.quads, before.quads + turned.perChart[c]);
}

// makeAtlas keeps the normal of the dense face under each finest triangle, and on the smooth torus
// few quads fold by them. With one chart's reversed by hand (a fold of the dense surface under it),
// every quad of that chart folds, and only the fold measure sees it. With its shading normals
// reversed instead, every quad faces against them and none folds: the picture marks them yellow.
TEST(BackFacingQuads, FoldsAreJudgedByTheDenseFacesUnderTheTriangles) {
  const multires::BaseMesh* base = nullptr;
  Atlas atlas = torusAtlas(base);
  ASSERT_EQ(atlas.triangleFaceNormals.size(), 2 * atlas.normals.size());
  const std::uint32_t n = atlas.layout.chartSize;
  const BackFacingQuads shading = countBackFacingQuads(atlas), folded = countFoldedQuads(atlas);
  EXPECT_LT(folded.quads, folded.total / 20) << "most of the torus's quads follow its faces";
  std::uint32_t c = 0;
  while (c < atlas.layout.charts && (folded.perChart[c] > 0 || shading.perChart[c] > 0)) ++c;
  ASSERT_LT(c, atlas.layout.charts) << "no chart without turned quads";
  const Atlas original = atlas;
  for (std::uint32_t b = 0; b + 1 < n; ++b)
    for (std::uint32_t a = 0; a + 1 < n; ++a)
      for (std::size_t t = 0; t < 2; ++t)
        for (auto& x : atlas.triangleFaceNormals[2 * atlas.layout.texel(c, a, b) + t]) x = std::int16_t(-x);
  const BackFacingQuads shadingAfter = countBackFacingQuads(atlas), foldedAfter = countFoldedQuads(atlas);
  EXPECT_EQ(shadingAfter.quads, shading.quads);
  EXPECT_EQ(foldedAfter.perChart[c], std::uint64_t(n - 1) * (n - 1));
  EXPECT_EQ(foldedAfter.quads, folded.quads + std::uint64_t(n - 1) * (n - 1));
  EXPECT_EQ(foldedAfter.worstChart, c);
  atlas = original;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i)
      for (auto& x : atlas.normals[atlas.layout.texel(c, i, j)]) x = std::int16_t(-x);
  EXPECT_EQ(countBackFacingQuads(atlas).perChart[c], std::uint64_t(n - 1) * (n - 1));
  EXPECT_EQ(countFoldedQuads(atlas).perChart[c], 0u);
  const Image picture = backFacingPreview(atlas);
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t at = atlas.layout.texel(c, i, j) * 3;
      EXPECT_TRUE(picture.pixels[at] == 255 && picture.pixels[at + 1] == 255 && picture.pixels[at + 2] == 0) << i << ", " << j;
    }
}

TEST(BackFacingQuads, FoldsNeedTheDenseFacesNormals) {
  const multires::BaseMesh* base = nullptr;
  Atlas atlas = torusAtlas(base);
  atlas.triangleFaceNormals.clear();  // as read from a model file
  EXPECT_THROW(countFoldedQuads(atlas), Error);
  EXPECT_THROW(quadFolds(atlas, 0, 0, 0), Error);
}

}  // namespace
}  // namespace isoatlas::atlas
