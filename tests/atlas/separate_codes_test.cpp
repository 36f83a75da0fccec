// Quantising the atlas never joins texels it holds apart (atlas/separate_codes.h), on corpus meshes
// whose model files had texels joined by their codes (cow, femur, elephant and bull: level 10 of each
// had an edge of length 0, and its capture, welded by position, was not a manifold): every pair of
// texels that decode to the same place is one place in the atlas too, each moved texel stays within
// its reach of where the atlas has it, and level 10 of the decoded atlas, welded by position, keeps
// every vertex and is a closed manifold.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "atlas/make_atlas.h"
#include "atlas/reconstruct.h"
#include "atlas/separate_codes.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::atlas {
namespace {

TEST(SeparateCodes, TexelsTheAtlasHoldsApartDecodeApartOnCorpusMeshes) {
  std::uint64_t moved = 0;
  for (const char* name : {"cow", "femur", "elephant", "bull"}) {
    const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / (std::string(name) + ".off");
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "run scripts/fetch-data for " << file;
    const Mesh dense = dropUnusedVertices(readMesh(file.string()));  // as `isoatlas build` prepares it
    multires::BaseMesh base = multires::simplifyStellar(dense);  // as `isoatlas build` makes it
    multires::pairTriangles(base, dense);
    ChartStats stats;
    const Atlas atlas = makeAtlas(dense, base, 33, &stats);
    ASSERT_EQ(stats.coincidentTexels, 0u) << name;

    SeparatedTexels separated;
    Atlas kept;  // the decode quantiseAtlas keeps as it moves codes (the model file's error is taken from it)
    const std::vector<QuantisedChart> codes = quantiseAtlas(atlas, base, &separated, &kept);
    EXPECT_EQ(separated.joined, 0u) << name;
    moved += separated.moved;
    Atlas decoded;
    decoded.layout = atlas.layout;
    dequantiseAtlas(codes, base, decoded);
    EXPECT_TRUE(kept.positions == decoded.positions) << name << ": the decode kept is not the codes' decode";
    std::map<std::array<float, 3>, std::size_t> first;
    const std::uint32_t n = atlas.layout.chartSize;
    for (std::uint32_t c = 0; c < atlas.layout.charts; ++c)
      for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
          const std::size_t at = atlas.layout.texel(c, i, j);
          const auto [it, fresh] = first.emplace(decoded.positions[at], at);
          ASSERT_TRUE(fresh || atlas.positions[it->second] == atlas.positions[at])
              << name << ": chart " << c << " texel (" << i << ", " << j << ") decodes onto a texel the atlas holds apart";
          // Off the border (decoded in its own chart's box, and the only texels moved): at most 2 steps
          // (unfolding) and 3 more (separating) from its own code, which is within half a step.
          const bool inside = i > 0 && j > 0 && i + 1 < n && j + 1 < n;
          for (int a = 0; a < 3 && inside; ++a)
            EXPECT_LE(std::abs(double(decoded.positions[at][a]) - atlas.positions[at][a]), 5.5001 * codes[c].step[a] + 1e-7)
                << name << ": chart " << c << " texel (" << i << ", " << j << ")";
        }
    const Mesh level10 = reconstructLevel(base, decoded, 10);
    const Mesh welded = weldIdenticalPositions(level10);
    EXPECT_EQ(welded.vertexCount(), level10.vertexCount()) << name << ": level 10 has vertices at one place";
    const MeshTopology t = analyzeTopology(welded);
    EXPECT_EQ(t.nonManifoldEdges + t.boundaryEdges + t.degenerateFaces, 0u) << name << ": " << t.firstProblem;
  }
  EXPECT_GT(moved, 0u) << "no case needed a texel moved: the test no longer guards the separation";
}

}  // namespace
}  // namespace isoatlas::atlas
