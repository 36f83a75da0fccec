// Rounding positions to the model file's codes folds no texel quads the atlas's own float positions
// do not fold (atlas/unfold_codes.h), on corpus meshes where plain rounding folded more.
#include <gtest/gtest.h>

#include <filesystem>

#include "atlas/backfacing_quads.h"
#include "atlas/make_atlas.h"
#include "atlas/quantised_atlas.h"
#include "core/mesh_io.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::atlas {
namespace {

// Femur folds 2,564 texel quads as the atlas has them, 3,058 rounded to 12 bits plainly; cow 1,268 and
// 1,438. Decoded, the atlas must fold fewer than the float one, and no chart but one in fifty more.
TEST(UnfoldCodes, RoundingFoldsNoMoreTexelQuadsThanTheAtlasOnCorpusMeshes) {
  for (const char* name : {"femur", "cow"}) {
    const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / (std::string(name) + ".off");
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "run scripts/fetch-data for " << file;
    const Mesh dense = dropUnusedVertices(readMesh(file.string()));  // as `isoatlas build` prepares it
    multires::BaseMesh base = multires::simplifyStellar(dense);
    multires::pairTriangles(base, dense);
    const Atlas atlas = makeAtlas(dense, base, 33);
    Atlas decoded;
    decoded.layout = atlas.layout;
    dequantiseAtlas(quantiseAtlas(atlas, base), base, decoded);
    decoded.triangleFaceNormals = atlas.triangleFaceNormals;
    const BackFacingQuads before = countFoldedQuads(atlas), after = countFoldedQuads(decoded);
    EXPECT_LT(after.quads, before.quads) << name << ": rounding folds quads the atlas does not";
    std::uint32_t chartsWorse = 0;
    for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) chartsWorse += after.perChart[c] > before.perChart[c];
    EXPECT_LE(chartsWorse, atlas.layout.charts / 50) << name << ": charts that fold more once rounded, of " << atlas.layout.charts;
  }
}

}  // namespace
}  // namespace isoatlas::atlas
