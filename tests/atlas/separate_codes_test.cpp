// Quantising the atlas never joins texels it holds apart (atlas/separate_codes.h), on corpus meshes
// whose model files had texels joined by their codes (cow, femur, elephant and bull: level 10 of each
// had an edge of length 0, and its capture, welded by position, was not a manifold): every pair of
// texels that decode to the same place is one place in the atlas too, each moved texel stays within
// its reach of where the atlas has it, and level 10 of the decoded atlas, welded by position, keeps
// every vertex and is a closed manifold; on small meshes kept whole, where texels join across borders,
// side codes move too.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "atlas/make_atlas.h"
#include "atlas/reconstruct.h"
#include "atlas/separate_codes.h"
#include "atlas/tile_sides.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::atlas {
namespace {

// One case: the mesh's atlas quantised; every pair of texels decoding to one place is one place in
// the atlas, each texel within reach of where the atlas has it, and level 10 welds into a closed
// manifold. Returns what the separation moved.
SeparatedTexels expectSeparated(const std::string& name, bool whole) {
  const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / (name + ".off");
  const Mesh dense = dropUnusedVertices(triangulated(readMesh(file.string())));  // as `isoatlas build` prepares it
  // as `isoatlas build` makes it: simplified, or the mesh its own base (a small one's default)
  multires::BaseMesh base = multires::simplifyStellar(dense, {.targetVertices = whole ? dense.vertexCount() : 0});
  multires::pairTriangles(base, dense);
  ChartStats stats;
  const Atlas atlas = makeAtlas(dense, base, 33, &stats);
  EXPECT_EQ(stats.coincidentTexels, 0u) << name;

  SeparatedTexels separated;
  Atlas kept;  // the decode quantiseAtlas keeps as it moves codes (the model file's error is taken from it)
  const std::vector<QuantisedChart> codes = quantiseAtlas(atlas, base, &separated, &kept);
  EXPECT_EQ(separated.joined, 0u) << name;
  Atlas decoded;
  decoded.layout = atlas.layout;
  dequantiseAtlas(codes, base, decoded);
  EXPECT_TRUE(kept.positions == decoded.positions) << name << ": the decode kept is not the codes' decode";
  const auto across = sidesAcross(base);
  std::map<std::array<float, 3>, std::size_t> first;
  const std::uint32_t n = atlas.layout.chartSize;
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t at = atlas.layout.texel(c, i, j);
        const auto [it, fresh] = first.emplace(decoded.positions[at], at);
        EXPECT_TRUE(fresh || atlas.positions[it->second] == atlas.positions[at])
            << name << ": chart " << c << " texel (" << i << ", " << j << ") decodes onto a texel the atlas holds apart";
        if (!fresh && atlas.positions[it->second] != atlas.positions[at]) return separated;
        // Off the border (decoded in its own chart's box): at most 2 steps (unfolding) and 4 more
        // (separating) from its own code, which is within half a step. On a side (not a corner):
        // 4 steps (separating) and a half, of the chart whose code both copies decode from, this
        // one's or the one's across.
        const bool onI = i == 0 || i + 1 == n, onJ = j == 0 || j + 1 == n;
        if (onI && onJ) continue;  // a corner: its base vertex
        double reach = 6.5;
        std::array<float, 3> step = codes[c].step;
        if (onI || onJ) {
          reach = 4.5;
          const int side = j == 0 ? 0 : i + 1 == n ? 1 : j + 1 == n ? 2 : 3;
          const std::uint32_t other = across[c][side].tile;
          for (int a = 0; a < 3 && other != kNoTile; ++a) step[a] = std::max(step[a], codes[other].step[a]);
        }
        for (int a = 0; a < 3; ++a)
          EXPECT_LE(std::abs(double(decoded.positions[at][a]) - atlas.positions[at][a]), (reach + 1e-4) * step[a] + 1e-7)
              << name << ": chart " << c << " texel (" << i << ", " << j << ")";
      }
  const Mesh level10 = reconstructLevel(base, decoded, 10);
  const Mesh welded = weldIdenticalPositions(level10);
  EXPECT_EQ(welded.vertexCount(), level10.vertexCount()) << name << ": level 10 has vertices at one place";
  const MeshTopology t = analyzeTopology(welded);
  EXPECT_EQ(t.nonManifoldEdges + t.boundaryEdges + t.degenerateFaces, 0u) << name << ": " << t.firstProblem;
  return separated;
}

TEST(SeparateCodes, TexelsTheAtlasHoldsApartDecodeApartOnCorpusMeshes) {
  if (!std::filesystem::exists(std::filesystem::path(ISOATLAS_DATA) / "meshes" / "cow.off")) GTEST_SKIP() << "run scripts/fetch-data";
  std::uint64_t moved = 0;
  for (const char* name : {"cow", "femur", "elephant", "bull"}) moved += expectSeparated(name, false).moved;
  EXPECT_GT(moved, 0u) << "no case needed a texel moved: the test no longer guards the separation";
}

// Kept whole (as `isoatlas build` keeps a mesh of at most 100 vertices), mpi's and mpi_triang's sliver
// tiles have sides shorter than their codes' steps: texels on both sides of a border join, and only
// their side codes can move (mpi's level 10 had 306 non-manifold edges while they stayed).
TEST(SeparateCodes, SideCodesMoveApartOnSmallMeshesKeptWhole) {
  if (!std::filesystem::exists(std::filesystem::path(ISOATLAS_DATA) / "meshes" / "mpi.off")) GTEST_SKIP() << "run scripts/fetch-data";
  for (const char* name : {"mpi", "mpi_triang"}) EXPECT_GT(expectSeparated(name, true).movedOnSides, 0u) << name;
}

}  // namespace
}  // namespace isoatlas::atlas
