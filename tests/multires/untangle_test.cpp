// The parametrisation over the base domain: a dense mesh made by subdividing a base mesh has a known,
// fold-free parametrisation; scrambling some of it makes folds that untangling must remove, after
// which the dense sampler gives back every dense vertex at its own parameter (the round trip).
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "multires/dense_sampler.h"
#include "multires/stellar_simplify.h"
#include "multires/untangle_parametrisation.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::multires {
namespace {

// Each base triangle cut into n x n triangles; dense vertex i has its lattice point's weights and
// sits off the base mesh (but for the base vertices), so a sampler that falls back to the base
// triangle instead of imaging the dense mesh misses it.
Mesh subdivide(BaseMesh& base, int n) {
  Mesh dense;
  std::map<std::vector<std::pair<std::uint32_t, int>>, std::uint32_t> index;  // (base vertex, weight)
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t) {
    const auto& c = base.triangles[t];
    auto vertex = [&](int i, int j) {  // weights (n - i - j, i, j) / n on the corners
      const int w[3] = {n - i - j, i, j};
      std::vector<std::pair<std::uint32_t, int>> key;
      for (int k = 0; k < 3; ++k)
        if (w[k] > 0) key.push_back({c[k], w[k]});
      std::sort(key.begin(), key.end());
      const auto [it, added] = index.insert({key, std::uint32_t(dense.positions.size())});
      if (added) {
        const std::array<double, 3> b{double(w[0]) / n, double(w[1]) / n, double(w[2]) / n};
        const double lift = 0.3 * (1 - *std::max_element(b.begin(), b.end()));  // 0 on base vertices
        dense.positions.push_back(base.pointAt(t, b) + Vec3{0.36, 0.48, 0.8} * lift);
        base.denseTriangle.push_back(t);
        base.denseBary.push_back(b);
        if (key.size() == 1) base.denseVertex[c[std::find(w, w + 3, n) - w]] = it->second;
      }
      return it->second;
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        dense.addFace({vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)});
        if (i + j + 1 < n) dense.addFace({vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
      }
  }
  return dense;
}

BaseMesh octahedron() {
  BaseMesh base;
  base.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  base.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  base.denseVertex.assign(6, -1);
  return base;
}

BaseMesh openPyramid() {  // four triangles around an apex of valence 4, with a boundary
  BaseMesh base;
  base.positions = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  base.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  base.denseVertex.assign(5, -1);
  return base;
}

// Moves a random share of the free dense vertices to a random point of a random neighbour's base
// triangle: folds, but every vertex still in the domain.
void scramble(const Mesh& dense, BaseMesh& base, double share, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<char> fixed(dense.vertexCount(), 0);
  for (const std::int64_t d : base.denseVertex)
    if (d >= 0) fixed[std::size_t(d)] = 1;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    if (unit(random) > share) continue;
    const std::uint32_t v = dense.face(f)[0];
    const std::uint32_t w = dense.face(f)[1];
    if (fixed[v]) continue;
    const double a = unit(random), b = unit(random) * (1 - a);
    base.denseTriangle[v] = base.denseTriangle[w];
    base.denseBary[v] = {a, b, 1 - a - b};
  }
}

void expectRoundTrip(const Mesh& dense, const BaseMesh& base, double tolerance) {
  const DenseSampler sampler(dense, base);
  double worst = 0;
  for (std::size_t v = 0; v < dense.vertexCount(); ++v)
    worst = std::max(worst, norm(sampler.position(base.denseTriangle[v], base.denseBary[v]) - dense.positions[v]));
  EXPECT_LT(worst, tolerance);
}

TEST(Untangle, SubdividedBaseMeshHasNoFoldsAndRoundTrips) {
  for (BaseMesh base : {octahedron(), openPyramid()}) {
    const Mesh dense = subdivide(base, 8);
    EXPECT_EQ(countFoldedTriangles(dense, base), 0u);
    expectRoundTrip(dense, base, 1e-12);
  }
}

TEST(Untangle, ScrambledParametrisationIsUntangled) {
  for (BaseMesh base : {octahedron(), openPyramid()}) {
    const Mesh dense = subdivide(base, 12);
    scramble(dense, base, 0.05, 7);
    const std::size_t folded = countFoldedTriangles(dense, base);
    ASSERT_GT(folded, 10u);
    const UntangleStats stats = untangleParametrisation(dense, base);
    EXPECT_EQ(stats.foldedBefore, folded);
    EXPECT_EQ(stats.foldedAfter, 0u);
    EXPECT_EQ(countFoldedTriangles(dense, base), 0u);
    for (std::size_t v = 0; v < dense.vertexCount(); ++v) {
      const auto& b = base.denseBary[v];
      EXPECT_TRUE(b[0] >= 0 && b[1] >= 0 && b[2] >= 0 && std::abs(b[0] + b[1] + b[2] - 1) < 1e-12);
    }
    expectRoundTrip(dense, base, 1e-9);
  }
}

// Folds counted by hand: in base triangle t cut 6 x 6, the centroid's dense vertex (lattice (2, 2))
// is pushed to lattice (2.6, 2.6), past the line i + j = 5 through its neighbours (3, 2) and (2, 3).
// Of its six triangles exactly one turns over: ((2,2), (3,2), (2,3)); the other five keep their
// orientation (each checked by hand: their signed areas stay 0.4 to 2.2).
void pushCentrePastItsRing(const Mesh& dense, BaseMesh& base, std::uint32_t t) {
  for (std::size_t v = 0; v < dense.vertexCount(); ++v) {
    const auto& b = base.denseBary[v];
    if (base.denseTriangle[v] == t && std::abs(b[0] - 1.0 / 3) < 1e-12 && std::abs(b[1] - 1.0 / 3) < 1e-12) {
      base.denseBary[v] = {0.8 / 6, 2.6 / 6, 2.6 / 6};
      return;
    }
  }
  FAIL() << "no centroid vertex in base triangle " << t;
}

TEST(Untangle, FoldsCountedByHand) {
  BaseMesh base = octahedron();
  const Mesh dense = subdivide(base, 6);
  pushCentrePastItsRing(dense, base, 0);
  EXPECT_EQ(countFoldedTriangles(dense, base), 1u);
  pushCentrePastItsRing(dense, base, 5);
  EXPECT_EQ(countFoldedTriangles(dense, base), 2u);
  const UntangleStats stats = untangleParametrisation(dense, base);
  EXPECT_EQ(stats.foldedBefore, 2u);
  EXPECT_EQ(stats.foldedAfter, 0u);
  EXPECT_EQ(stats.movedVertices, 2u) << "only the two pushed vertices need to move";
  EXPECT_EQ(countFoldedTriangles(dense, base), 0u);
}

// On simplified surfaces untangling is local and greedy: it never adds folds and removes most; the
// few left are dense triangles too long for one chart (their corners' base triangles share no
// vertex). Nearly every dense vertex then comes back exactly at its own parameter.
TEST(Untangle, SimplifiedSurfacesRoundTrip) {
  for (const Mesh& dense : {test::torusMesh(120, 60), test::doubleTorusMesh()}) {
    SimplifyStats stats;
    const BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.02}, &stats);
    EXPECT_LE(stats.untangle.foldedAfter * 2, stats.untangle.foldedBefore);
    EXPECT_EQ(countFoldedTriangles(dense, base), stats.untangle.foldedAfter);
    EXPECT_LT(double(stats.untangle.foldedAfter), 0.002 * double(dense.faceCount()));
    const DenseSampler sampler(dense, base);
    std::size_t exact = 0;
    for (std::size_t v = 0; v < dense.vertexCount(); ++v)
      exact += norm(sampler.position(base.denseTriangle[v], base.denseBary[v]) - dense.positions[v]) < 1e-9;
    EXPECT_GE(double(exact), 0.999 * double(dense.vertexCount()));
  }
}

// The grid over each base triangle's images answers as the scan of them all, bit for bit, at points
// inside base triangles, on their edges and corners, and a little outside; and it spares the scan
// for nearly every point of a surface whose parametrisation does not fold.
TEST(DenseSampler, IndexedQueriesAnswerAsTheScan) {
  const Mesh dense = test::torusMesh(160, 80);
  const BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.01});
  const DenseSampler indexed(dense, base), scan(dense, base, false);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
    for (int q = 0; q < 40; ++q) {
      double a = unit(random), b = unit(random);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      if (q % 8 == 1) b = 0;                      // on an edge
      if (q % 8 == 2) a = 1, b = 0;               // on a corner
      if (q % 8 == 3) a += 0.01, b -= 0.02;       // a little outside
      const std::array<double, 3> w{1 - a - b, a, b};
      ASSERT_EQ(indexed.position(t, w), scan.position(t, w)) << "base triangle " << t << " at " << a << ", " << b;
    }
  EXPECT_EQ(scan.fullScans(), scan.queries());
  EXPECT_LT(double(indexed.fullScans()), 0.02 * double(indexed.queries()))
      << indexed.fullScans() << " of " << indexed.queries() << " queries scanned every image";
}

}  // namespace
}  // namespace isoatlas::multires
