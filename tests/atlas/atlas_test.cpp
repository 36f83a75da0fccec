// The atlas against invariants and analytic truths: packing, shared borders identical texel for
// texel, reconstruction closed and manifold at every level (boundaries kept for open meshes), the
// whole chart within the dense mesh's own error of the true sphere and torus, CGAL's Hausdorff
// distance on shapes of known distance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>

#include "core/distance/mesh_distance.h"
#include "atlas/evaluate_levels.h"
#include "atlas/make_atlas.h"
#include "atlas/reconstruct.h"
#include "atlas/tile_sides.h"
#include "core/error.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/atlas/atlas_checks.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/thread_count.h"

namespace isoatlas::atlas {
namespace {

struct Built {
  Mesh dense;
  multires::BaseMesh base;
  Atlas atlas;
  ChartStats stats;
};

Built build(Mesh dense, double ratio, std::uint32_t chartSize) {
  Built b{std::move(dense), {}, {}, {}};
  b.base = multires::simplifyStellar(b.dense, {.vertexRatio = ratio});
  multires::pairTriangles(b.base, b.dense);
  b.atlas = makeAtlas(b.dense, b.base, chartSize, &b.stats);
  return b;
}

const Built& torus() {
  static const Built b = build(test::torusMesh(48, 24), 0.04, 17);
  return b;
}
const Built& sphere() {
  static const Built b = build(test::sphereMesh(), 0.02, 33);
  return b;
}

// A plane with two square holes: three boundary loops.
const Built& holedPlane() {
  static const Built b = build(test::gridMesh(30, 24, [](int i, int j) {
    return (i >= 6 && i < 10 && j >= 6 && j < 10) || (i >= 18 && i < 23 && j >= 12 && j < 16);
  }), 0.05, 9);
  return b;
}

TEST(PackCharts, FullestGridWithinAspectTwo) {
  EXPECT_EQ(packCharts(375, 33).columns * packCharts(375, 33).rows, 375u);  // 15 x 25
  EXPECT_EQ(packCharts(1, 33).efficiency(), 1.0);
  EXPECT_EQ(packCharts(7, 33).columns * packCharts(7, 33).rows, 8u);  // 7 slots would need 1 x 7
  for (std::uint32_t n = 1; n <= 3000; ++n) {
    const AtlasLayout l = packCharts(n, 17);
    ASSERT_GE(std::uint64_t(l.columns) * l.rows, n);
    ASSERT_LE(l.columns, 2 * l.rows) << n;
    ASSERT_LE(l.rows, 2 * l.columns) << n;
    ASSERT_EQ(l.width(), l.columns * 17);
    // No legal grid has fewer slots (all column counts tried by hand).
    for (std::uint32_t c = 1; c <= n; ++c) {
      const std::uint32_t r = (n + c - 1) / c;
      if (c <= 2 * r && r <= 2 * c) {
        ASSERT_LE(std::uint64_t(l.columns) * l.rows, std::uint64_t(c) * r) << n;
      }
    }
    // The target of 95 %: met for every count from 74 charts on (73 fills 73 of 77 slots).
    if (n >= 74) {
      ASSERT_GE(l.efficiency(), 0.95) << n;
    }
  }
  EXPECT_THROW(packCharts(0, 33), Error);
}

TEST(PackCharts, ChartsDoNotOverlapAndStayInside) {
  const AtlasLayout l = packCharts(53, 5);
  std::vector<int> owner(std::size_t(l.width()) * l.height(), -1);
  for (std::uint32_t c = 0; c < l.charts; ++c)
    for (std::uint32_t j = 0; j < 5; ++j)
      for (std::uint32_t i = 0; i < 5; ++i) {
        const std::size_t at = l.texel(c, i, j);
        ASSERT_LT(at, owner.size());
        ASSERT_EQ(owner[at], -1) << "chart " << c << " overlaps chart " << owner[at];
        owner[at] = int(c);
      }
}

// The charts sample through the parametrisation's exact history: on every shape no texel falls in a
// gap, none lands where another texel of its chart does, and shared border samples agree.
TEST(Atlas, NoFoldedOrGapTexelsOnAnyShape) {
  static const Built genus3 = build(test::tripleTorusMesh(), 0.02, 17);
  static const Built shell = build(test::thinShellMesh(), 0.02, 17);
  ASSERT_EQ(analyzeTopology(genus3.dense).genus, 3);
  // The shell's wall is thinner than the sampling: marching cubes leaves it pierced by dozens of
  // small tunnels between its two sheets.
  ASSERT_GT(analyzeTopology(shell.dense).genus, 20);
  for (const Built* b : {&torus(), &sphere(), &holedPlane(), &genus3, &shell}) {
    SCOPED_TRACE(b == &genus3 ? "genus 3" : b == &shell ? "shell" : b == &torus() ? "torus" : b == &sphere() ? "sphere" : "holed plane");
    EXPECT_EQ(b->stats.coincidentTexels, 0u);
    EXPECT_EQ(b->stats.gapTexels, 0u);
    EXPECT_EQ(b->stats.borderDisagreements, 0u);
    EXPECT_GT(b->stats.meanHistorySteps, 1.0) << "texels walk back through the simplification";
  }
}

// anchor_dense (a CAD part) has dense vertices within 2e-8 of a tile's border, beside the border
// sample at that very place: snapping the texel next to it onto such a vertex made two texels one
// point as floats (5 coincident texels, and level 10 not a manifold). Built as `isoatlas build`
// builds it: none.
TEST(Atlas, ADenseVertexAtATilesBorderJoinsNoTexels) {
  const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / "anchor_dense.off";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "run scripts/fetch-data for " << file;
  const Mesh dense = dropUnusedVertices(readMesh(file.string()));  // as `isoatlas build` prepares it
  multires::BaseMesh base = multires::simplifyStellar(dense);
  multires::pairTriangles(base, dense);
  atlas::ChartStats stats;
  const atlas::Atlas atlas = atlas::makeAtlas(dense, base, 33, &stats);
  EXPECT_GT(stats.snappedTexels, 0u);
  EXPECT_EQ(stats.coincidentTexels, 0u);
  const Mesh level10 = atlas::reconstructLevel(base, atlas, 10);
  EXPECT_EQ(weldIdenticalPositions(level10).vertexCount(), level10.vertexCount());
}

// Texel quads turning against the surface: counted by hand against the true outward normal of the
// sphere and the torus, they are about what the charts report against the dense mesh's normals
// (the two normals differ a little). They come from the map's shear, not from a fold (it is
// one-to-one), and mark where it is most distorted: today about 1 % of the torus's quads, along a
// few tiles' diagonals, which the bound below keeps from growing.
TEST(Atlas, TurnedTexelQuadsAreCountedAndRare) {
  auto outwardSphere = [](const Vec3& p) { return p - Vec3{12.3, 12.5, 12.2}; };
  auto outwardTorus = [](const Vec3& p) {
    const double rho = std::hypot(p.x, p.y);
    return Vec3{p.x - 3 * p.x / rho, p.y - 3 * p.y / rho, p.z};
  };
  for (const auto& [b, outward] : {std::pair{&sphere(), std::function<Vec3(const Vec3&)>(outwardSphere)},
                                   std::pair{&torus(), std::function<Vec3(const Vec3&)>(outwardTorus)}}) {
    const std::uint32_t n = b->atlas.layout.chartSize;
    std::uint64_t turned = 0;
    for (std::uint32_t c = 0; c < b->atlas.layout.charts; ++c)
      for (std::uint32_t j = 0; j + 1 < n; ++j)
        for (std::uint32_t i = 0; i + 1 < n; ++i) {
          const Vec3 p = b->atlas.position(c, i, j);
          const Vec3 normal = cross(b->atlas.position(c, i + 1, j) - p, b->atlas.position(c, i, j + 1) - p);
          turned += dot(normal, outward(p)) < 0;
        }
    EXPECT_NEAR(double(turned), double(b->stats.turnedTexelQuads), 0.02 * double(turned) + 2);
    EXPECT_LT(double(turned), 0.02 * b->atlas.layout.charts * (n - 1) * (n - 1));
  }
}

TEST(Atlas, SharedBordersAreIdenticalTexelForTexel) {
  for (const Built* b : {&torus(), &sphere(), &holedPlane()}) EXPECT_EQ(test::expectIdenticalBorders(b->base, b->atlas), b->stats.sharedSides);
  EXPECT_GT(torus().stats.sharedSides, 0u);
}

TEST(Atlas, ChartsSampleTheDenseSurface) {
  // Every texel is a point of the dense mesh (borders too: their charts agree there), so it lies
  // on the torus within the dense triangles' own distance from it (sampled finely over each).
  const Built& b = torus();
  double sagitta = 0;
  auto offTorus = [](const Vec3& p) { return std::abs(std::hypot(std::hypot(p.x, p.y) - 3, p.z) - 1); };
  for (std::size_t f = 0; f < b.dense.faceCount(); ++f) {
    const auto c = b.dense.face(f);
    for (int u = 0; u <= 16; ++u)
      for (int v = 0; u + v <= 16; ++v)
        sagitta = std::max(sagitta, offTorus(b.dense.positions[c[0]] * ((16.0 - u - v) / 16) + b.dense.positions[c[1]] * (u / 16.0) +
                                             b.dense.positions[c[2]] * (v / 16.0)));
  }
  const std::uint32_t n = b.atlas.layout.chartSize;
  for (std::uint32_t c = 0; c < b.atlas.layout.charts; ++c)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        ASSERT_LE(offTorus(b.atlas.position(c, i, j)), sagitta * 1.01 + 1e-6) << "chart " << c << " (" << i << ", " << j << ")";
        // Normals point away from the torus's core circle.
        const Vec3 p = b.atlas.position(c, i, j);
        const double rho = std::hypot(p.x, p.y);
        const Vec3 outward{p.x - 3 * p.x / rho, p.y - 3 * p.y / rho, p.z};
        ASSERT_GT(dot(b.atlas.normal(c, i, j), outward), 0.8 * norm(outward));
      }
}

TEST(Reconstruct, ClosedAndManifoldAtEveryLevelWithTheRightCounts) {
  for (const Built* b : {&torus(), &sphere()}) {
    const MeshTopology dense = analyzeTopology(b->dense);
    const std::size_t tiles = b->base.tiles.size();
    for (int level = 0; level <= maxLevel(b->atlas.layout.chartSize); ++level) {
      const Mesh m = reconstructLevel(b->base, b->atlas, level);
      const MeshTopology t = analyzeTopology(m);
      ASSERT_TRUE(t.closed && t.manifold && t.oriented) << "level " << level << ": " << t.firstProblem;
      EXPECT_EQ(t.genus, dense.genus) << "level " << level;
      EXPECT_EQ(t.unusedVertices, 0u);
      const std::size_t squares = std::size_t(1) << level / 2 * 2;
      EXPECT_EQ(m.faceCount(), tiles * squares * (level % 2 ? 4 : 2)) << "level " << level;
      EXPECT_EQ(m.normals.size(), m.vertexCount());
    }
  }
}

TEST(Reconstruct, OpenMeshesKeepTheirBoundaries) {
  const Built& b = holedPlane();
  const MeshTopology dense = analyzeTopology(b.dense);
  ASSERT_EQ(dense.boundaryLoops, 3u);
  for (int level = 0; level <= maxLevel(b.atlas.layout.chartSize); ++level) {
    const MeshTopology t = analyzeTopology(reconstructLevel(b.base, b.atlas, level));
    EXPECT_TRUE(t.manifold && t.oriented) << "level " << level << ": " << t.firstProblem;
    EXPECT_EQ(t.boundaryLoops, 3u) << "level " << level;
    EXPECT_EQ(t.euler, dense.euler) << "level " << level;
  }
}

TEST(Reconstruct, TheWholeChartLiesOnTheTrueSphere) {
  // The sphere of sphereMesh: radius 10 about (12.3, 12.5, 12.2). Every vertex of the finest level
  // is a point of the dense mesh, so it lies as close to the true sphere as the dense triangles do.
  const Built& b = sphere();
  const Vec3 centre{12.3, 12.5, 12.2};
  auto off = [&](const Vec3& p) { return std::abs(norm(p - centre) - 10); };
  double denseError = 0;
  for (std::size_t f = 0; f < b.dense.faceCount(); ++f) {
    const auto c = b.dense.face(f);
    const Vec3 &p = b.dense.positions[c[0]], &q = b.dense.positions[c[1]], &r = b.dense.positions[c[2]];
    for (const Vec3& x : {p, q, r, (p + q + r) * (1.0 / 3), (p + q) * 0.5, (q + r) * 0.5, (r + p) * 0.5})
      denseError = std::max(denseError, off(x));
  }
  const Mesh finest = reconstructLevel(b.base, b.atlas, maxLevel(b.atlas.layout.chartSize));
  double worst = 0;
  for (const Vec3& p : finest.positions) worst = std::max(worst, off(p));
  EXPECT_LE(worst, denseError * 1.01 + 1e-5);
  EXPECT_LT(worst, 0.05) << "about the marching-cubes mesh's own error on a radius of 10";
  // The base mesh lies farther off: the levels are not the base mesh.
  double baseWorst = 0;
  for (std::size_t f = 0; f < b.base.triangleCount(); ++f)
    baseWorst = std::max(baseWorst, off(b.base.pointAt(std::uint32_t(f), {1.0 / 3, 1.0 / 3, 1.0 / 3})));
  EXPECT_GT(baseWorst, 10 * worst);
}

// The finest level against the true sphere, within the error its sampling allows, computed by hand:
// a point of a level triangle lies within h / sqrt(3) of a corner (h its longest edge), so it lies
// inside the sphere by at most the dense mesh's own error plus h^2 / (6 R) (the sagitta at that
// distance; 5 R here, for the curvature's second order), and never outside it by more than the
// dense error. Its PSNR follows.
TEST(Reconstruct, FinestLevelIsAsCloseToTheSphereAsItsSpacingAllows) {
  const Built& b = sphere();
  const Vec3 centre{12.3, 12.5, 12.2};
  constexpr double R = 10;
  auto radius = [&](const Vec3& p) { return norm(p - centre); };
  double denseError = 0;
  for (std::size_t f = 0; f < b.dense.faceCount(); ++f) {
    const auto c = b.dense.face(f);
    const Vec3 &p = b.dense.positions[c[0]], &q = b.dense.positions[c[1]], &r = b.dense.positions[c[2]];
    for (const Vec3& x : {p, q, r, (p + q + r) * (1.0 / 3), (p + q) * 0.5, (q + r) * 0.5, (r + p) * 0.5})
      denseError = std::max(denseError, std::abs(radius(x) - R));
  }
  const Mesh finest = reconstructLevel(b.base, b.atlas, maxLevel(b.atlas.layout.chartSize));
  double worst = 0, longest = 0;
  for (std::size_t f = 0; f < finest.faceCount(); ++f) {
    const auto c = finest.face(f);
    const Vec3 &p = finest.positions[c[0]], &q = finest.positions[c[1]], &r = finest.positions[c[2]];
    const double h = std::max({norm(q - p), norm(r - q), norm(p - r)});
    longest = std::max(longest, h);
    for (const Vec3& x : {p, (p + q + r) * (1.0 / 3), (p + q) * 0.5}) {
      const double depth = R - radius(x);
      ASSERT_LE(depth, denseError + h * h / (5 * R) + 1e-9) << "face " << f;
      ASSERT_LE(-depth, denseError + 1e-9) << "face " << f;
      worst = std::max(worst, std::abs(depth));
    }
  }
  const double diagonal = boundingBox(b.dense.positions).diagonal();
  EXPECT_GT(psnrDb(diagonal, worst), 50) << "the sphere of radius 10 at a spacing of " << longest;
}

TEST(Reconstruct, RefusesLevelsBeyondTheChart) {
  EXPECT_EQ(maxLevel(33), 10);
  EXPECT_EQ(maxLevel(3), 2);
  EXPECT_THROW(reconstructLevel(torus().base, torus().atlas, 9), Error);  // 17 texels: levels 0..8
  EXPECT_THROW(reconstructLevel(torus().base, torus().atlas, -1), Error);
}

// Simplification, matching and charting give the same model whatever the thread count (1, 2 or 8).
TEST(Atlas, TheSameModelOnOneTwoOrEightThreads) {
  const Mesh dense = test::tripleTorusMesh();
  auto model = [&] {
    multires::BaseMesh base = multires::simplifyStellar(dense, {.vertexRatio = 0.02});
    multires::pairTriangles(base, dense);
    const Atlas atlas = makeAtlas(dense, base, 9);
    return std::make_pair(base.positions, atlas.positions);
  };
  const auto one = test::onThreads(1, model);
  for (const int threads : {2, 8}) {
    const auto other = test::onThreads(threads, model);
    EXPECT_TRUE(other.first == one.first) << "base vertices on " << threads << " threads";
    EXPECT_TRUE(other.second == one.second) << "atlas texels on " << threads << " threads";
  }
}

// evaluateLevels measures each level while it reconstructs the next beside it: each answers as measured
// alone, in the order asked, on one thread or eight.
TEST(EvaluateLevels, EachLevelAnswersAsMeasuredAlone) {
  const Built& b = torus();
  const std::vector<int> levels{4, 0, 8, 2};
  const auto together = [&] { return evaluateLevels(b.base, b.atlas, b.dense, levels, 5000); };
  const std::vector<LevelFigures> one = test::onThreads(1, together), eight = test::onThreads(8, together);
  ASSERT_EQ(one.size(), levels.size());
  ASSERT_EQ(eight.size(), levels.size());
  const MeshDistances fromDense(b.dense, 5000);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Mesh mesh = reconstructLevel(b.base, b.atlas, levels[i]);
    const Hausdorff alone = fromDense.to(mesh);
    for (const auto* figures : {&one[i], &eight[i]}) {
      EXPECT_EQ(figures->level, levels[i]);
      EXPECT_EQ(figures->triangles, mesh.faceCount());
      EXPECT_EQ(figures->hausdorff, alone.symmetric()) << "level " << levels[i];
      EXPECT_EQ(figures->rms, alone.rms()) << "level " << levels[i];
      EXPECT_TRUE(figures->closed && figures->manifold);
    }
  }
  EXPECT_LT(one[2].hausdorff, one[1].hausdorff);  // level 8 nearer than level 0
}

}  // namespace
}  // namespace isoatlas::atlas
