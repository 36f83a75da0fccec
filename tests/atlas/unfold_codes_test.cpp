// Rounding positions to the model file's codes, nudged (atlas/unfold_codes.h), folds fewer texel
// quads than the atlas's own float positions, on corpus meshes where plain rounding folded more, and
// more in hardly any chart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "atlas/backfacing_quads.h"
#include "atlas/make_atlas.h"
#include "atlas/quantised_atlas.h"
#include "atlas/unfold_codes.h"
#include "core/mesh_io.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::atlas {
namespace {

struct Built {
  multires::BaseMesh base;
  Atlas atlas;
};
// The base mesh and atlas `isoatlas build` makes of data/meshes/NAME.off (chart 33), made once; nullopt
// without the data.
const std::optional<Built>& build(const std::string& name) {
  static std::map<std::string, std::optional<Built>> made;
  if (const auto it = made.find(name); it != made.end()) return it->second;
  std::optional<Built>& b = made[name];
  const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / (name + ".off");
  if (!std::filesystem::exists(file)) return b;
  const Mesh dense = dropUnusedVertices(readMesh(file.string()));  // as `isoatlas build` prepares it
  b = Built{multires::simplifyStellar(dense), {}};
  multires::pairTriangles(b->base, dense);
  b->atlas = makeAtlas(dense, b->base, 33);
  return b;
}

std::uint64_t foldedQuads(const Built& b, const std::vector<QuantisedChart>& codes) {
  Atlas decoded;
  decoded.layout = b.atlas.layout;
  dequantiseAtlas(codes, b.base, decoded);
  decoded.triangleFaceNormals = b.atlas.triangleFaceNormals;
  return countFoldedQuads(decoded).quads;
}

// Femur folds 2,564 texel quads as the atlas has them, 3,058 rounded to 12 bits plainly; cow 1,268 and
// 1,438. Decoded, the atlas must fold fewer than the float one, and no chart but one in fifty more.
TEST(UnfoldCodes, RoundingFoldsNoMoreTexelQuadsThanTheAtlasOnCorpusMeshes) {
  for (const char* name : {"femur", "cow"}) {
    const std::optional<Built>& b = build(name);
    if (!b) GTEST_SKIP() << "run scripts/fetch-data for data/meshes/" << name << ".off";
    const Atlas& atlas = b->atlas;
    Atlas decoded;
    decoded.layout = atlas.layout;
    dequantiseAtlas(quantiseAtlas(atlas, b->base), b->base, decoded);
    decoded.triangleFaceNormals = atlas.triangleFaceNormals;
    const BackFacingQuads before = countFoldedQuads(atlas), after = countFoldedQuads(decoded);
    EXPECT_LT(after.quads, before.quads) << name << ": rounding folds quads the atlas does not";
    std::uint32_t chartsWorse = 0;
    for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) chartsWorse += after.perChart[c] > before.perChart[c];
    EXPECT_LE(chartsWorse, atlas.layout.charts / 50) << name << ": charts that fold more once rounded, of " << atlas.layout.charts;
  }
}

// The nudge's own promises, on codes jittered by a step (which folds the femur's small triangles):
// border codes stay, no code moves more than two steps along an axis, fewer quads fold, and the count
// it returns is the texels whose codes changed.
TEST(UnfoldCodes, NudgesOnlyInnerCodesAndAtMostTwoSteps) {
  const std::optional<Built>& b = build("femur");
  if (!b) GTEST_SKIP() << "run scripts/fetch-data for data/meshes/femur.off";
  std::vector<QuantisedChart> codes = quantiseAtlas(b->atlas, b->base);
  const std::uint32_t n = b->atlas.layout.chartSize;
  std::uint32_t seed = 12345;
  for (QuantisedChart& q : codes)
    for (std::uint32_t j = 1; j + 1 < n; ++j)
      for (std::uint32_t i = 1; i + 1 < n; ++i)
        for (int a = 0; a < 3; ++a) {
          seed = seed * 1664525u + 1013904223u;
          auto& v = q.positions[std::size_t(j) * n + i][std::size_t(a)];
          v = std::uint16_t(std::clamp(int(v) + int(seed >> 30) - 1, 0, int(kLargestPositionCode)));  // -1, 0, 1 or 2
        }
  const std::vector<QuantisedChart> jittered = codes;
  Atlas decoded, again;
  decoded.layout = again.layout = b->atlas.layout;
  dequantiseAtlas(codes, b->base, decoded);
  const std::uint64_t moved = unfoldRoundedTexels(b->atlas, codes, decoded);
  dequantiseAtlas(codes, b->base, again);
  EXPECT_TRUE(decoded.positions == again.positions) << "the decode it keeps is not the codes' decode";
  std::uint64_t changed = 0;
  for (std::size_t c = 0; c < codes.size(); ++c)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto &now = codes[c].positions[std::size_t(j) * n + i], &was = jittered[c].positions[std::size_t(j) * n + i];
        changed += now != was;
        const bool border = i == 0 || j == 0 || i + 1 == n || j + 1 == n;
        if (border) {
          ASSERT_EQ(now, was) << "chart " << c << " border texel (" << i << ", " << j << ") moved";
        }
        for (int a = 0; a < 3; ++a) ASSERT_LE(std::abs(int(now[std::size_t(a)]) - int(was[std::size_t(a)])), 2) << "chart " << c;
      }
  EXPECT_EQ(moved, changed);
  EXPECT_GT(moved, 0u);
  EXPECT_LT(foldedQuads(*b, codes), foldedQuads(*b, jittered));
}

}  // namespace
}  // namespace isoatlas::atlas
