// Fine detail stamped on a model: only its region changes, by at most its depth and inwards; shared
// borders stay identical (tiles' and detail charts'); every level stays closed, the detail levels
// refining only the stamped tiles; words render with ink.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "atlas/reconstruct.h"
#include "atlas/stamp_detail.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/text.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/atlas/atlas_checks.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"

namespace isoatlas::atlas {
namespace {

const Vec3 kCentre{12.3, 12.5, 12.2};  // test::sphereMesh's, radius 10

struct Sphere {
  multires::BaseMesh base;
  Atlas atlas;
};
const Sphere& sphere() {
  static const Sphere s = [] {
    const Mesh dense = test::sphereMesh();
    Sphere out{multires::simplifyStellar(dense, {.vertexRatio = 0.02}), {}};
    multires::pairTriangles(out.base, dense);
    out.atlas = makeAtlas(dense, out.base, 9);
    return out;
  }();
  return s;
}

// A 24 x 16 image: a bright bar across the middle, dark around it.
Image bar() {
  Image image(24, 16, 1);
  for (int y = 5; y < 11; ++y)
    for (int x = 3; x < 21; ++x) *image.at(x, y) = 255;
  return image;
}

Stamp stampAt(const Vec3& direction, double radius, double depth) {
  return {.image = bar(), .at = kCentre + direction * (10 / norm(direction)), .radius = radius, .depth = depth, .detailSize = 33};
}

// How far below the sphere the chart's cells reach when cut into flat triangles (either diagonal)
// and sampled as a detail chart of `detailSize` samples them.
double deepestFlatCell(const Atlas& atlas, std::uint32_t detailSize) {
  const std::uint32_t n = atlas.layout.chartSize, r = (detailSize - 1) / (n - 1);
  double deepest = 0;
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c)
    for (std::uint32_t j = 0; j + 1 < n; ++j)
      for (std::uint32_t i = 0; i + 1 < n; ++i) {
        const Vec3 corner[4] = {atlas.position(c, i, j), atlas.position(c, i + 1, j), atlas.position(c, i + 1, j + 1),
                                atlas.position(c, i, j + 1)};
        for (int first = 0; first < 4; ++first)  // the triangles of both diagonals
          for (std::uint32_t a = 0; a <= r; ++a)
            for (std::uint32_t b = 0; a + b <= r; ++b) {
              const Vec3 o = corner[first], p = corner[(first + 1) % 4], q = corner[(first + 3) % 4];
              const Vec3 x = o + (p - o) * (double(a) / r) + (q - o) * (double(b) / r);
              deepest = std::max(deepest, 10 - norm(x - kCentre));
            }
      }
  return deepest;
}

TEST(StampDetail, ChangesOnlyItsRegionByAtMostItsDepthInwards) {
  const Sphere& s = sphere();
  Atlas atlas = s.atlas;
  const StampStats stats = stampDetail(s.base, atlas, stampAt({1, 0.3, 0.2}, 4, 0.5));
  EXPECT_GT(stats.texelsChanged, 20u);
  EXPECT_GT(stats.detailTiles, 0u);
  EXPECT_GT(stats.detailTexelsChanged, stats.texelsChanged) << "detail charts are finer";
  EXPECT_NEAR(norm(stats.centre - kCentre), 10, 0.1);
  std::size_t changed = 0;
  for (std::size_t t = 0; t < atlas.positions.size(); ++t) {
    const auto& before = s.atlas.positions[t];
    const auto& after = atlas.positions[t];
    const bool moved = std::memcmp(&before, &after, sizeof before) != 0;
    if (!moved && s.atlas.normals[t] == atlas.normals[t]) continue;
    ++changed;  // moved, or tilted by the stamp's slope at its edge
    const Vec3 b{before[0], before[1], before[2]}, a{after[0], after[1], after[2]};
    EXPECT_LT(norm(b - stats.centre), 4) << "a texel outside the stamp's radius changed";
    EXPECT_LE(norm(a - b), 0.5 + 1e-5) << "moved further than the depth";
    if (moved) {
      EXPECT_LT(norm(a - kCentre), norm(b - kCentre)) << "an engraving moves inwards";
    }
  }
  EXPECT_EQ(changed, stats.texelsChanged);
  // The bar is 18 of 24 pixels wide over a diagonal of 2 x 4 mm: texels on it sink the full depth,
  // below the coarse chart's flat cells (which lie inside the sphere by their chords' sag).
  double deepest = 0;
  for (const DetailChart& d : atlas.details)
    for (std::size_t t = 0; t < d.positions.size(); ++t) {
      const Vec3 p{d.positions[t][0], d.positions[t][1], d.positions[t][2]};
      deepest = std::max(deepest, 10 - norm(p - kCentre));
    }
  EXPECT_GT(deepest, 0.45);
  EXPECT_LT(deepest, 0.5 + deepestFlatCell(s.atlas, 33) + 1e-4);
}

TEST(StampDetail, BordersStayIdenticalAndEveryLevelClosed) {
  const Sphere& s = sphere();
  Atlas atlas = s.atlas;
  // Across several tiles, so that detail charts meet each other and tiles without one.
  stampDetail(s.base, atlas, stampAt({0.2, -1, 0.4}, 6, 0.6));
  ASSERT_GT(atlas.details.size(), 1u);
  EXPECT_GT(test::expectIdenticalBorders(s.base, atlas, true), 0u);
  const int coarseTop = maxLevel(atlas.layout.chartSize), top = maxLevel(atlas);
  ASSERT_EQ(coarseTop, 6);
  ASSERT_EQ(top, 10);
  std::size_t previous = 0;
  for (int level = 0; level <= top; ++level) {
    const Mesh m = reconstructLevel(s.base, atlas, level);
    const MeshTopology t = analyzeTopology(m);
    ASSERT_TRUE(t.closed && t.manifold && t.oriented) << "level " << level << ": " << t.firstProblem;
    EXPECT_EQ(t.genus, 0);
    EXPECT_GT(m.faceCount(), previous);
    previous = m.faceCount();
    if (level > coarseTop) {
      // Only the detail tiles refine: the rest keep the coarse top level's triangles (their fans
      // to finer sides add a few).
      const std::size_t coarseFaces = (s.base.tiles.size() - atlas.details.size()) * 2 * 64;
      const std::size_t detailFaces = atlas.details.size() * (level % 2 ? 4 : 2) * (std::size_t(1) << level / 2 * 2);
      EXPECT_GE(m.faceCount(), coarseFaces + detailFaces);
      EXPECT_LT(m.faceCount(), coarseFaces + detailFaces + s.base.tiles.size() * 64);
    }
  }
}

// Tiles reconstructed apart (close-ups draw a few) give exactly their share of the whole level's
// faces, corner positions and order alike, at a level of the charts and at the detail charts' top.
TEST(StampDetail, TilesReconstructedApartAreTheirShareOfTheLevel) {
  const Sphere& s = sphere();
  Atlas atlas = s.atlas;
  stampDetail(s.base, atlas, stampAt({0.2, -1, 0.4}, 6, 0.6));
  using Face = std::array<double, 9>;
  auto faces = [](const Mesh& m) {
    std::vector<Face> out;
    for (std::size_t f = 0; f < m.faceCount(); ++f) {
      const auto c = m.face(f);
      Face face;
      for (int k = 0; k < 3; ++k)
        for (int x = 0; x < 3; ++x) face[std::size_t(3 * k + x)] = m.positions[c[std::size_t(k)]][x];
      out.push_back(face);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  for (const int level : {3, maxLevel(atlas)}) {
    std::vector<std::uint32_t> even, odd;
    for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) (c % 2 ? odd : even).push_back(c);
    std::vector<Face> apart = faces(reconstructTiles(s.base, atlas, level, even));
    const std::vector<Face> other = faces(reconstructTiles(s.base, atlas, level, odd));
    ASSERT_FALSE(apart.empty() || other.empty());
    apart.insert(apart.end(), other.begin(), other.end());
    std::sort(apart.begin(), apart.end());
    EXPECT_EQ(apart, faces(reconstructLevel(s.base, atlas, level))) << "level " << level;
  }
  EXPECT_THROW(reconstructTiles(s.base, atlas, 2, {atlas.layout.charts}), Error);
}

TEST(StampDetail, ASecondStampAddsToTheDetailCharts) {
  const Sphere& s = sphere();
  Atlas once = s.atlas;
  stampDetail(s.base, once, stampAt({1, 0.3, 0.2}, 4, 0.5));
  Atlas twice = once;
  stampDetail(s.base, twice, stampAt({1, 0.3, 0.2}, 4, 0.5));
  ASSERT_EQ(twice.details.size(), once.details.size());
  double deeper = 0;
  for (std::size_t k = 0; k < once.details.size(); ++k)
    for (std::size_t t = 0; t < once.details[k].positions.size(); ++t) {
      const auto& a = once.details[k].positions[t];
      const auto& b = twice.details[k].positions[t];
      deeper = std::max(deeper, norm(Vec3{a[0], a[1], a[2]} - Vec3{b[0], b[1], b[2]}));
    }
  EXPECT_GT(deeper, 0.4);
  Stamp other = stampAt({1, 0.3, 0.2}, 4, 0.5);
  other.detailSize = 17;
  EXPECT_THROW(stampDetail(s.base, twice, other), Error) << "detail charts of two sizes";
}

TEST(StampDetail, RefusesBadStamps) {
  const Sphere& s = sphere();
  Atlas atlas = s.atlas;
  Stamp bad = stampAt({1, 0, 0}, 4, 0.5);
  bad.detailSize = 9;  // not finer than the charts
  EXPECT_THROW(stampDetail(s.base, atlas, bad), Error);
  bad = stampAt({1, 0, 0}, 0, 0.5);
  EXPECT_THROW(stampDetail(s.base, atlas, bad), Error);
  bad = stampAt({1, 0, 0}, 4, 0);
  EXPECT_THROW(stampDetail(s.base, atlas, bad), Error);
  bad = stampAt({1, 0, 0}, 4, 5);  // deeper than wide
  EXPECT_THROW(stampDetail(s.base, atlas, bad), Error);
  bad.image = {};
  EXPECT_THROW(stampDetail(s.base, atlas, bad), Error);
}

TEST(StampDetail, DetailChartsRoundTripThroughTheModelFile) {
  const Sphere& s = sphere();
  Model model{.chartSize = 9, .base = s.base, .atlas = s.atlas, .dense = {}};
  model.base.denseTriangle.clear(), model.base.denseBary.clear();
  stampDetail(model.base, model.atlas, stampAt({0.2, -1, 0.4}, 6, 0.6));
  const std::string path = (test::scratchDir() / "stamped.isoatlas").string();
  writeModel(path, model);
  const Model back = readModel(path);
  ASSERT_EQ(back.atlas.details.size(), model.atlas.details.size());
  for (std::size_t k = 0; k < back.atlas.details.size(); ++k) {
    EXPECT_EQ(back.atlas.details[k].tile, model.atlas.details[k].tile);
    EXPECT_EQ(std::memcmp(back.atlas.details[k].positions.data(), model.atlas.details[k].positions.data(),
                          model.atlas.details[k].positions.size() * 12), 0);
    EXPECT_EQ(back.atlas.details[k].normals, model.atlas.details[k].normals);
  }
  // The quantised charts come back within the reported error everywhere, stamped corners included
  // (the stamp moved some off their base vertices), and their borders identical.
  double worst = 0;
  for (std::size_t t = 0; t < model.atlas.positions.size(); ++t) {
    const auto &a = model.atlas.positions[t], &b = back.atlas.positions[t];
    worst = std::max(worst, std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]));
  }
  EXPECT_LE(worst, back.quantisationError * (1 + 1e-9));
  EXPECT_LT(back.quantisationError, 1e-2) << "a few 4095ths of a chart (rounded, then moved at most 5 steps), not the stamp's depth";
  test::expectIdenticalBorders(back.base, back.atlas, true);
  // Damaged: refused by section name.
  std::string bytes = test::readBytes(path);
  const std::size_t at = bytes.find("DETL");
  ASSERT_NE(at, std::string::npos);
  bytes[at + 16 + 40] ^= 4;
  test::writeBytes(path, bytes);
  const Error e = test::thrownError([&] { readModel(path); }, "a damaged detail section");
  EXPECT_NE(std::string(e.what()).find("section DETL"), std::string::npos) << e.what();
}

TEST(Text, AWordRendersWithInkInItsBox) {
  const Image one = renderText("I", 40), word = renderText("isoatlas", 40);
  EXPECT_GT(word.width, 4 * one.width);
  EXPECT_EQ(word.height, one.height);
  EXPECT_GE(word.height, 40);
  std::size_t ink = 0;
  for (const std::uint8_t p : word.pixels) ink += p > 128;
  EXPECT_GT(ink, std::size_t(word.width * word.height / 20));
  EXPECT_LT(ink, std::size_t(word.width * word.height / 2));
  EXPECT_THROW(renderText("", 40), Error);
  EXPECT_THROW(renderText("x", 40, "/nonexistent/font.ttf"), Error);
  // A file that is not a font, short or long, is refused before the font parser reads it.
  const auto dir = test::scratchDir();
  test::writeBytes(dir / "short.ttf", "abc");
  test::writeBytes(dir / "long.ttf", std::string("\0\x01\0\0\xff\xff", 6) + std::string(200, 'x'));
  EXPECT_THROW(renderText("x", 40, (dir / "short.ttf").string()), Error);
  EXPECT_THROW(renderText("x", 40, (dir / "long.ttf").string()), Error);
}

}  // namespace
}  // namespace isoatlas::atlas
