// The specialised halfedge: refinement and coarsening by stellar splits and welds keep the mesh a
// closed manifold of the same genus, neighbours within one level, and the surface on the dense one;
// a weld undone by a split gives the same faces back; patches tile every chart.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "multires/adaptive_mesh.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::multires {
namespace {

struct Fixture {
  Mesh dense = test::torusMesh(64, 32);
  BaseMesh base;
  Fixture() {
    base = simplifyStellar(dense, {.vertexRatio = 0.02});
    pairTriangles(base, dense);
  }
  AdaptiveMesh adaptive(std::uint32_t chart = 17) {
    return AdaptiveMesh(base, chart, [this](const ChartPoint& p) {
      const auto [t, w] = base.chartToTriangle(p.chart, p.u, p.v);
      return densePosition(dense, base.densePoint(t, w));
    });
  }
};

int faceLevel(const AdaptiveMesh& a, FaceH f) {
  int l = 0;
  for (const VertexH v : a.mesh().fv_range(f)) l = std::max(l, a.level(v));
  return l;
}

void expectInvariants(const AdaptiveMesh& a) {
  const StellarMesh& m = a.mesh();
  const MeshTopology t = analyzeTopology(a.triangles());
  ASSERT_TRUE(t.closed && t.manifold && t.oriented) << t.firstProblem;
  EXPECT_EQ(t.genus, 1);
  for (const FaceH f : m.faces()) {
    int interior = 0;
    for (const HalfedgeH h : m.fh_range(f)) interior += a.isInterior(h);
    EXPECT_EQ(interior, 1) << "each face points to one of its own halfedges";
  }
  for (const EdgeH e : m.edges()) {
    const FaceH f0 = m.face_handle(m.halfedge_handle(e, 0)), f1 = m.face_handle(m.halfedge_handle(e, 1));
    ASSERT_LE(std::abs(faceLevel(a, f0) - faceLevel(a, f1)), 1) << "neighbours differ by more than one level";
  }
}

TEST(AdaptiveMesh, BaseTilesHaveTheirDiagonalInterior) {
  Fixture fx;
  const AdaptiveMesh a = fx.adaptive();
  expectInvariants(a);
  std::size_t splittable = 0;
  for (const EdgeH e : a.mesh().edges()) splittable += a.canSplit(e);
  EXPECT_EQ(splittable, fx.base.tiles.size()) << "exactly the tile diagonals";
  EXPECT_EQ(a.patches().size(), fx.base.tiles.size());
}

TEST(AdaptiveMesh, UniformRefinementFollowsTheDenseSurface) {
  Fixture fx;
  AdaptiveMesh a = fx.adaptive(9);  // 8 texels a side: six levels of 4-8 refinement
  for (int level = 0; level < 6; ++level) {
    const std::size_t faces = a.mesh().n_faces();
    std::vector<EdgeH> edges;
    for (const EdgeH e : a.mesh().edges())
      if (a.canSplit(e)) edges.push_back(e);
    for (const EdgeH e : edges) a.split(e);
    a.compact();
    EXPECT_EQ(a.mesh().n_faces(), 2 * faces) << "a uniform 4-8 level doubles the faces";
    expectInvariants(a);
  }
  // Nothing is finer than the chart's texels.
  for (const EdgeH e : a.mesh().edges()) EXPECT_FALSE(a.canSplit(e));
  // Every vertex lies on the dense torus (distance to its tube), within the dense mesh's own error.
  double worst = 0;
  for (const VertexH v : a.mesh().vertices()) {
    const auto p = a.mesh().point(v);
    const double ring = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 3;
    worst = std::max(worst, std::abs(std::sqrt(ring * ring + p[2] * p[2]) - 1));
  }
  EXPECT_LT(worst, 0.01);
}

TEST(AdaptiveMesh, RandomRefineAndWeldKeepOneLevelOfDifference) {
  Fixture fx;
  AdaptiveMesh a = fx.adaptive(33);
  std::mt19937 rng(11);
  int splits = 0, welds = 0;
  for (int round = 0; round < 20; ++round) {
    for (int i = 0; i < 100; ++i) {
      const EdgeH e(int(rng() % a.mesh().n_edges()));
      if (!a.mesh().status(e).deleted() && a.refine(e)) ++splits;
    }
    for (int i = 0; i < 60; ++i) {
      const VertexH v(int(rng() % a.mesh().n_vertices()));
      if (a.canWeld(v)) a.weld(v), ++welds;
    }
    a.compact();
    expectInvariants(a);
  }
  EXPECT_GT(splits, 500);
  EXPECT_GT(welds, 100);
  // Weld everything back: the base mesh returns.
  for (bool any = true; any;) {
    any = false;
    for (const VertexH v : a.mesh().vertices())
      if (a.canWeld(v)) a.weld(v), any = true;
  }
  a.compact();
  EXPECT_EQ(a.mesh().n_vertices(), fx.base.vertexCount());
  EXPECT_EQ(a.mesh().n_faces(), fx.base.triangleCount());
  expectInvariants(a);
}

std::multiset<std::array<double, 9>> facePositions(const AdaptiveMesh& a) {
  std::multiset<std::array<double, 9>> out;
  for (const FaceH f : a.mesh().faces()) {
    std::vector<std::array<double, 3>> c;
    // Rounded: a vertex on a tile side is sampled from either tile's chart, equal up to rounding.
    auto r = [](double x) { return std::round(x * 1e6) / 1e6; };
    for (const VertexH v : a.mesh().fv_range(f))
      c.push_back({r(a.mesh().point(v)[0]), r(a.mesh().point(v)[1]), r(a.mesh().point(v)[2])});
    // The least of the three rotations: canonical even when two corners sit at one place.
    std::array<double, 9> least{};
    for (int k = 0; k < 3; ++k) {
      const auto& a = c[k];
      const auto& b = c[(k + 1) % 3];
      const auto& d = c[(k + 2) % 3];
      const std::array<double, 9> rotated{a[0], a[1], a[2], b[0], b[1], b[2], d[0], d[1], d[2]};
      if (k == 0 || rotated < least) least = rotated;
    }
    out.insert(least);
  }
  return out;
}

TEST(AdaptiveMesh, WeldThenSplitRestoresTheFaces) {
  Fixture fx;
  AdaptiveMesh a = fx.adaptive(17);
  std::mt19937 rng(3);
  for (int i = 0; i < 400; ++i) a.refine(EdgeH(int(rng() % a.mesh().n_edges())));
  int checked = 0;
  for (int i = 0; i < int(a.mesh().n_vertices()) && checked < 30; ++i) {
    const VertexH v(i);
    if (!a.canWeld(v)) continue;
    const auto before = facePositions(a);
    const int level = a.level(v);
    // A split's vertex neighbours the edge's two ends, so the edge that restores v joins two of v's
    // neighbours: only those edges are tried (by position, as facePositions compares).
    auto rounded = [&](VertexH u) {
      const auto p = a.mesh().point(u);
      return std::array<double, 3>{std::round(p[0] * 1e6), std::round(p[1] * 1e6), std::round(p[2] * 1e6)};
    };
    std::set<std::array<double, 3>> ring;
    for (const VertexH u : a.mesh().vv_range(v)) ring.insert(rounded(u));
    a.weld(v);
    // The restored edge is the one splittable edge whose split lands on v's old place.
    bool restored = false;
    for (const EdgeH e : a.mesh().edges())
      if (a.canSplit(e) && ring.count(rounded(a.mesh().from_vertex_handle(a.mesh().halfedge_handle(e, 0)))) &&
          ring.count(rounded(a.mesh().to_vertex_handle(a.mesh().halfedge_handle(e, 0))))) {
        AdaptiveMesh copy = a;
        const VertexH m = copy.split(e);
        if (facePositions(copy) == before) {
          EXPECT_EQ(copy.level(m), level);
          a = std::move(copy);
          restored = true;
          break;
        }
      }
    EXPECT_TRUE(restored) << "vertex " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 30);
}

// Refines tile 0 until every face of chart 0 has level `level` (refine() forces the neighbours),
// one split at a time: a split changes the edges around it.
void refineTile0To(AdaptiveMesh& a, int level) {
  for (bool split = true; split;) {
    split = false;
    for (const HalfedgeH h : a.mesh().halfedges())
      if (!a.mesh().is_boundary(h) && a.isInterior(h) && a.chart(h) == 0 && faceLevel(a, a.mesh().face_handle(h)) < level) {
        a.refine(a.mesh().edge_handle(h));
        split = true;
        break;
      }
  }
}

// The patches of tile 0 (chart size 33: 32 x 32 texels) refined uniformly to level k, worked out by
// hand from the 4-8 pattern: level 1 puts a vertex at the centre (16, 16); level 2 vertices at the
// side midpoints, on the chart's border; level 3 vertices at (8, 8), (24, 8), (8, 24), (24, 24), so
// the chart holds five odd-level vertices and splits into four quadrants of side 16, each holding one
// at its centre (the centre vertex lies on their corners); level 4 adds even levels only; level 5
// repeats level 3 at half the scale in every quadrant: 16 patches of side 8, each around one level-5
// vertex.
TEST(AdaptiveMesh, PatchesOfAUniformlyRefinedTileAreKnown) {
  Fixture fx;
  const struct {
    int level, side, finest;
  } expected[] = {{0, 32, 0}, {1, 32, 1}, {2, 32, 1}, {3, 16, 3}, {4, 16, 3}, {5, 8, 5}};
  for (const auto& e : expected) {
    AdaptiveMesh a = fx.adaptive(33);
    refineTile0To(a, e.level);
    std::set<std::array<int, 4>> got, want;
    for (const Patch& p : a.patches())
      if (p.chart == 0) got.insert({p.u, p.v, p.s, p.c});
    for (int v = 0; v < 32; v += e.side)
      for (int u = 0; u < 32; u += e.side) want.insert({u, v, e.side, e.finest});
    EXPECT_EQ(got, want) << "level " << e.level;
  }
}

// Deeper, uneven refinement: patches still tile every chart exactly once.
TEST(AdaptiveMesh, PatchesTileEveryChart) {
  Fixture fx;
  AdaptiveMesh a = fx.adaptive(33);
  refineTile0To(a, 7);
  const std::vector<Patch> patches = a.patches();
  std::map<std::uint32_t, long> area;
  std::map<std::uint32_t, int> count;
  for (const Patch& p : patches) area[p.chart] += long(p.s) * p.s, ++count[p.chart];
  EXPECT_EQ(area.size(), fx.base.tiles.size());
  for (const auto& [chart, covered] : area) EXPECT_EQ(covered, 32 * 32) << "chart " << chart;
  EXPECT_GE(count[0], 16);
}

TEST(AdaptiveMesh, ChartSizesBeyondTheHalfedgeUvAreRefused) {
  Fixture fx;
  EXPECT_THROW(fx.adaptive(257), Error);  // its last texel, 256, does not fit 8 bits
  EXPECT_THROW(fx.adaptive(32), Error);
  EXPECT_NO_THROW(fx.adaptive(kMaxChartSize));
}

}  // namespace
}  // namespace isoatlas::multires
