// Triangle pairing and surface distances against invariants and known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "core/mesh_topology.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/multires/parametrisation_checks.h"

namespace isoatlas::multires {
namespace {

void expectTriquad(const BaseMesh& base) {
  ASSERT_EQ(base.tiles.size() * 2, base.triangleCount());
  std::vector<int> seen(base.triangleCount(), 0);
  for (const auto& tile : base.tiles) {
    ++seen[tile[0]], ++seen[tile[1]];
    int shared = 0;
    for (const auto a : base.triangles[tile[0]])
      for (const auto b : base.triangles[tile[1]]) shared += a == b;
    EXPECT_EQ(shared, 2) << "a tile's triangles share an edge";
  }
  for (const int s : seen) EXPECT_EQ(s, 1) << "every triangle is in exactly one tile";
}

TEST(TrianglePairing, ClosedMeshIsPairedWithoutSplits) {
  const Mesh dense = test::torusMesh(60, 30);
  BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.03});
  const PairingStats stats = pairTriangles(base, dense);
  EXPECT_EQ(stats.splits, 0u) << "a closed manifold always has a perfect matching";
  expectTriquad(base);
  const MeshTopology quads = analyzeTopology(base.quadMesh());
  EXPECT_TRUE(quads.closed && quads.manifold && quads.oriented) << quads.firstProblem;
  EXPECT_EQ(quads.genus, 1);
}

// A torus grid cut into triangles along one diagonal of each square: the most orthogonal tiles are
// the grid's squares, and the matching finds every one (pairing by anything else takes some
// triangles across a square's side instead).
TEST(TrianglePairing, TilesAreTheMostOrthogonalQuads) {
  constexpr int n = 12, m = 8;
  const Mesh dense = test::torusMesh(n, m);
  BaseMesh base = simplifyStellar(dense, {.vertexRatio = 1});
  ASSERT_EQ(base.vertexCount(), dense.vertexCount());
  const PairingStats stats = pairTriangles(base, dense);
  ASSERT_EQ(stats.splits, 0u);
  ASSERT_EQ(stats.tiles, std::size_t(n * m));
  for (const auto& tile : base.tiles) {
    std::vector<std::uint32_t> shared;
    for (const auto a : base.triangles[tile[0]])
      for (const auto b : base.triangles[tile[1]])
        if (a == b) shared.push_back(a);
    ASSERT_EQ(shared.size(), 2u);
    // The shared edge is the square's diagonal: its ends differ in both grid directions.
    const int di = int(shared[0] / m) - int(shared[1] / m), dj = int(shared[0] % m) - int(shared[1] % m);
    EXPECT_TRUE(di != 0 && dj != 0) << "a tile across a square's side";
  }
}

// A tile's chart point, taken to its base triangle and back (BaseMesh::triangleToChart, the inverse
// of chartToTriangle), comes back where it was, on both halves and on the diagonal between them.
TEST(TrianglePairing, ChartPointsComeBackFromTheirTriangles) {
  const Mesh dense = test::torusMesh(60, 30);
  BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.03});
  pairTriangles(base, dense);
  const std::array<std::array<double, 2>, 6> points{{{0.2, 0.7}, {0.7, 0.2}, {0.5, 0.5}, {0.999, 0.001}, {0.001, 0.999}, {0.3, 0.3}}};
  for (std::uint32_t tile = 0; tile < base.tiles.size(); ++tile)
    for (const auto& [u, v] : points) {
      const auto [triangle, bary] = base.chartToTriangle(tile, u, v);
      EXPECT_TRUE(triangle == base.tiles[tile][0] || triangle == base.tiles[tile][1]);
      const auto back = base.triangleToChart(tile, triangle, bary);
      EXPECT_NEAR(back[0], u, 1e-12) << "tile " << tile;
      EXPECT_NEAR(back[1], v, 1e-12) << "tile " << tile;
    }
}

// A wavy sheet with a square hole, plus one lone triangle hung below its bottom border so that the
// triangle count is odd: some triangle must be split on the boundary.
Mesh oddSheet() {
  Mesh dense = test::gridMesh(30, 20, [](int i, int j) { return i >= 10 && i < 14 && j >= 6 && j < 10; });
  auto find = [&](double x, double y) {
    for (std::uint32_t v = 0; v < dense.vertexCount(); ++v)
      if (dense.positions[v].x == x && dense.positions[v].y == y) return v;
    return ~0u;
  };
  const std::uint32_t a = find(15, 0), b = find(16, 0), n = std::uint32_t(dense.vertexCount());
  dense.positions.push_back({15.5, -1, dense.positions[a].z});
  dense.addFace({b, a, n});  // the border runs b -> a on the outside
  return dense;
}

// Distance from p to the nearest boundary edge of a mesh.
double boundaryDistance(const Mesh& m, const Vec3& p) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
  for (std::size_t f = 0; f < m.faceCount(); ++f)
    for (int i = 0; i < 3; ++i) {
      const auto a = m.face(f)[i], b = m.face(f)[(i + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  double best = 1e300;
  for (const auto& [e, c] : count) {
    if (c != 1) continue;
    const Vec3 a = m.positions[e.first], d = m.positions[e.second] - a;
    const double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
    best = std::min(best, norm(a + d * t - p));
  }
  return best;
}

TEST(TrianglePairing, LeftoversAreSplitOnTheBoundary) {
  const Mesh dense = oddSheet();
  const MeshTopology topology = analyzeTopology(dense);
  ASSERT_TRUE(topology.manifold && topology.oriented) << topology.firstProblem;
  // A ratio whose base mesh has an odd triangle count: at least one triangle must be split.
  BaseMesh base;
  for (const double ratio : {0.08, 0.07, 0.09, 0.06, 0.1}) {
    base = simplifyStellar(dense, {.vertexRatio = ratio});
    if (base.triangleCount() % 2 == 1) break;
  }
  ASSERT_EQ(base.triangleCount() % 2, 1u) << "no ratio gave an odd count; pick others";
  const std::size_t before = base.triangleCount();
  const PairingStats stats = pairTriangles(base, dense);
  expectTriquad(base);
  EXPECT_EQ(base.triangleCount(), before + stats.splits);
  EXPECT_GE(stats.splits, 1u);
  test::expectParametrisationInside(dense, base, 1.5);  // grid cells; untangled vertices move about one
  const MeshTopology quads = analyzeTopology(base.quadMesh());
  EXPECT_TRUE(quads.manifold) << quads.firstProblem;
  EXPECT_EQ(quads.boundaryLoops, 2u);
}

TEST(TrianglePairing, SplitVerticesLieOnTheDenseBoundary) {
  const Mesh dense = oddSheet();
  // Several ratios, so that several base meshes with odd counts are paired.
  std::size_t splitVertices = 0;
  for (const double ratio : {0.05, 0.06, 0.07, 0.08, 0.09}) {
    BaseMesh base = simplifyStellar(dense, {.vertexRatio = ratio});
    pairTriangles(base, dense);
    expectTriquad(base);
    for (std::size_t v = 0; v < base.vertexCount(); ++v) {
      if (base.denseVertex[v] >= 0) continue;
      ++splitVertices;
      EXPECT_LT(boundaryDistance(dense, base.positions[v]), 1e-6) << "split vertex " << v;
    }
  }
  EXPECT_GT(splitVertices, 0u);
}

}  // namespace
}  // namespace isoatlas::multires
